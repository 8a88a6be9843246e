"""Parquet tables with provenance metadata, and reading them back with clear errors."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Iterator, Mapping, Sequence
from importlib import metadata
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from qsm.workflow.json_files import plain

META_KEY = b"qsm"
#: Rows converted to Arrow and written at a time.
ROW_GROUP = 250_000
PACKAGES = ("qsm-design", "numpy", "scipy", "pandas", "pyarrow")


class TableError(ValueError):
    """A table file is missing, unreadable or lacks a column."""


def _remedy(path: str | Path) -> str:
    return (
        f"; it is damaged or was not written by this workflow: delete '{path}' and run again "
        f"(Snakemake then recomputes it)"
    )


def package_versions(names: Iterable[str] = PACKAGES) -> dict[str, str]:
    """Installed versions of ``names`` ("missing" for one that is not installed)."""
    versions = {}
    for name in names:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "missing"
    return versions


def write_table(
    table: pd.DataFrame, path: str | Path, meta: Mapping[str, Any] | None = None
) -> None:
    """Write ``table`` to Parquet with ``meta`` (strict JSON, :func:`qsm.workflow.json_files.plain`)
    and the package versions in its metadata, :data:`ROW_GROUP` rows at a time (Arrow holds a
    copy of one group, not of the table)."""
    groups = range(0, max(len(table), 1), ROW_GROUP)
    # one schema for every group (an object column may hold only None in one of them)
    schema = pa.Schema.from_pandas(table, preserve_index=False) if len(groups) > 1 else None
    write_batches((table.iloc[start : start + ROW_GROUP] for start in groups), path, meta, schema)


def write_batches(
    batches: Iterable[pd.DataFrame],
    path: str | Path,
    meta: Mapping[str, Any] | None = None,
    schema: pa.Schema | None = None,
) -> int:
    """Write the tables ``batches`` one after another to one Parquet file, as :func:`write_table`
    writes one table, holding one batch at a time; the rows written. Each batch is cast to
    ``schema`` (None: the first batch's), so that a column one batch holds only as nulls keeps
    its type."""
    info = {"package_versions": package_versions(), **(meta or {})}
    text = json.dumps(plain(info), default=str, allow_nan=False)  # strict: NaN as null
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    writer, rows = None, 0
    try:
        for batch in batches:
            if schema is None:
                arrow = pa.Table.from_pandas(batch, preserve_index=False)
            else:
                arrow = _as_schema(batch.reset_index(drop=True), schema)
            arrow = arrow.replace_schema_metadata(
                {**(arrow.schema.metadata or {}), META_KEY: text.encode()}
            )
            writer = writer or pq.ParquetWriter(path, arrow.schema)
            writer.write_table(arrow)
            rows += len(batch)
    finally:
        if writer is not None:
            writer.close()
    return rows


def read_table(
    path: str | Path,
    columns: Iterable[str] = (),
    only: bool = False,
    where: list[tuple[str, str, Any]] | None = None,
) -> pd.DataFrame:
    """Read a Parquet table, raising ``TableError`` naming the file on any problem.

    ``columns`` are required; a missing one is reported by name. With ``only``, just those
    columns are read, and with ``where`` (pyarrow's filters, such as ``[("status", "==",
    "ok")]``) just those rows: a job that needs part of a large table holds only that part.
    """
    columns = list(columns)
    if not Path(path).exists():
        raise TableError(
            f"table '{path}' does not exist: run the workflow that writes it first "
            f"(snakemake --cores 2), or give the folder of a run that did"
        )
    try:
        names = pq.read_schema(path).names
        missing = [c for c in columns if c not in names]
        wanted = columns if only and columns else None
        table = None if missing else _read_groups(path, wanted, where)
    except (OSError, pa.ArrowException) as exc:
        raise TableError(f"cannot read table '{path}': {exc}{_remedy(path)}") from exc
    if missing:
        raise TableError(f"table '{path}' lacks column(s) {', '.join(missing)}{_remedy(path)}")
    return table.to_pandas(split_blocks=True, self_destruct=True)  # Arrow's memory freed as read


def _read_groups(
    path: str | Path, columns: list[str] | None, where: list[tuple[str, str, Any]] | None
) -> pa.Table:
    """The table at ``path`` (``columns``; all when None), :data:`ROW_GROUP` rows at a time, each
    batch filtered by ``where`` as it is read: the reader holds one batch's buffers beside the rows
    kept, not the whole file's (``pq.read_table`` pre-buffers every column and filters a copy)."""
    file = pq.ParquetFile(path, pre_buffer=False)
    keys = list(dict.fromkeys(key for key, _, _ in where or []))
    read = None if columns is None else list(dict.fromkeys([*columns, *keys]))
    parts = []
    for batch in file.iter_batches(batch_size=ROW_GROUP, columns=read):
        part = pa.Table.from_batches([batch])
        if where:
            rows = _kept_rows(part.select(keys), where)
            part = part if len(rows) == part.num_rows else part.take(rows)  # no copy if all stay
        parts.append(part if columns is None else part.select(columns))
    if not parts:
        empty = file.schema_arrow.empty_table()
        return empty if columns is None else empty.select(columns)
    return pa.concat_tables(parts)


def _kept_rows(keys: pa.Table, where: list[tuple[str, str, Any]]) -> pa.Array:
    """The positions of the rows of ``keys`` (the filter's columns) that ``where`` keeps."""
    numbered = keys.append_column("__row__", pa.array(range(keys.num_rows), pa.int64()))
    return numbered.filter(pq.filters_to_expression(where))["__row__"].combine_chunks()


def read_batches(
    path: str | Path, columns: Iterable[str] = (), rows: int = 1_000_000
) -> Iterator[pd.DataFrame]:
    """The table at ``path`` ``rows`` at a time (its ``columns``, each required; all when none
    are named), with :func:`read_table`'s errors naming the file."""
    columns = list(columns)
    try:
        table = pq.ParquetFile(path)
        missing = [c for c in columns if c not in table.schema_arrow.names]
        if missing:
            raise TableError(f"table '{path}' lacks column(s) {', '.join(missing)}{_remedy(path)}")
        for batch in table.iter_batches(batch_size=rows, columns=columns or None):
            yield batch.to_pandas()
    except FileNotFoundError as exc:
        raise TableError(f"table '{path}' does not exist: run the workflow first") from exc
    except (OSError, pa.ArrowException) as exc:
        raise TableError(f"cannot read table '{path}': {exc}{_remedy(path)}") from exc


def read_meta(path: str | Path) -> dict[str, Any]:
    """The qsm metadata stored by ``write_table``; ``TableError`` naming the file if unreadable."""
    try:
        raw = pq.read_schema(path).metadata or {}
        return json.loads(raw.get(META_KEY, b"{}"))
    except (OSError, pa.ArrowException, ValueError) as exc:
        raise TableError(
            f"cannot read the metadata of table '{path}': {exc}{_remedy(path)}"
        ) from exc


def settings_hash(settings: Mapping[str, Any]) -> str:
    """Short SHA-256 of the canonical JSON of ``settings`` (what a stage's output depends on)."""
    text = json.dumps(settings, sort_keys=True, separators=(",", ":"), default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def table_schema(paths: Iterable[str | Path], columns: Sequence[str]) -> pa.Schema:
    """The schema of ``columns`` across the tables at ``paths``: a column that one table holds
    as text is text (another may hold it only as nulls, written as numbers), for
    :func:`write_batches`."""
    schemas = [pq.read_schema(p) for p in paths]
    fields = []
    for name in columns:
        found = [s.field(name) for s in schemas if name in s.names]
        text = [f for f in found if pa.types.is_string(f.type) or pa.types.is_large_string(f.type)]
        fields.append((text or found)[0])
    return pa.schema(fields)


def _as_schema(batch: pd.DataFrame, schema: pa.Schema) -> pa.Table:
    """``batch`` in ``schema``: a text column it holds only as missing numbers becomes nulls."""
    batch = batch[schema.names]
    for field in schema:
        text = pa.types.is_string(field.type) or pa.types.is_large_string(field.type)
        if text and batch[field.name].dtype.kind == "f" and batch[field.name].isna().all():
            batch = batch.assign(**{field.name: pd.Series([None] * len(batch), dtype=object)})
    return pa.Table.from_pandas(batch, schema=schema, preserve_index=False)

"""Parquet tables with provenance metadata, and reading them back with clear errors."""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Mapping
from importlib import metadata
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from qsm.workflow.json_files import plain

META_KEY = b"qsm"
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
    and the package versions in its metadata."""
    arrow = pa.Table.from_pandas(table, preserve_index=False)
    info = {"package_versions": package_versions(), **(meta or {})}
    text = json.dumps(plain(info), default=str, allow_nan=False)  # strict: NaN as null
    merged = {**(arrow.schema.metadata or {}), META_KEY: text.encode()}
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    pq.write_table(arrow.replace_schema_metadata(merged), path)


def read_table(path: str | Path, columns: Iterable[str] = ()) -> pd.DataFrame:
    """Read a Parquet table, raising ``TableError`` naming the file on any problem.

    ``columns`` are required; a missing one is reported by name.
    """
    if not Path(path).exists():
        raise TableError(
            f"table '{path}' does not exist: run the workflow that writes it first "
            f"(snakemake --cores 2), or give the folder of a run that did"
        )
    try:
        table = pq.read_table(path)
    except (OSError, pa.ArrowException) as exc:
        raise TableError(f"cannot read table '{path}': {exc}{_remedy(path)}") from exc
    missing = [c for c in columns if c not in table.column_names]
    if missing:
        raise TableError(f"table '{path}' lacks column(s) {', '.join(missing)}{_remedy(path)}")
    return table.to_pandas()


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

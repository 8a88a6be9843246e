"""Intermediate tables: part of one read as Arrow reads it; damaged or foreign ones give an error
naming the file and saying to delete it."""

import json

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

from qsm.workflow import tables
from qsm.workflow.tables import META_KEY, TableError, read_meta, read_table, write_table


@pytest.fixture
def table(tmp_path):
    path = tmp_path / "mechanisms.parquet"
    write_table(pd.DataFrame({"a": [1.0, 2.0], "b": [3, 4]}), path, {"settings_hash": "abc"})
    return path


@pytest.mark.parametrize(
    "damage",
    [
        lambda raw: raw[:200],  # truncated (a killed copy)
        lambda raw: raw[:3],
        lambda raw: b"",
        lambda raw: b"sample_id,l2\n1,0.3\n",  # a CSV under a Parquet name
        lambda raw: raw[:100] + b"\0" * 50 + raw[150:],  # corrupted pages
    ],
    ids=["truncated", "stub", "empty", "csv", "corrupt"],
)
def test_damaged_table_names_the_file_and_says_delete(table, damage):
    table.write_bytes(damage(table.read_bytes()))
    for read in (read_table, read_meta):
        try:
            read(table)
        except TableError as exc:
            assert f"'{table}'" in str(exc)
            assert f"delete '{table}' and run again" in str(exc)
        else:
            assert read is read_meta  # the footer may survive damage to the pages


def test_foreign_table_names_the_missing_columns(table, tmp_path):
    foreign = tmp_path / "foreign.parquet"
    pd.DataFrame({"x": [1]}).to_parquet(foreign)
    with pytest.raises(TableError, match=r"lacks column\(s\) a, b; .*delete .*foreign\.parquet"):
        read_table(foreign, ["a", "b"])
    assert read_meta(foreign) == {}
    assert read_table(table, ["a"])["b"].tolist() == [3, 4]


def test_the_metadata_is_strict_json(tmp_path):
    """A non-finite number in a table's metadata (a share of an empty front) is stored as null,
    so that strict JSON parsers read it."""

    def refuse(constant):
        raise ValueError(f"non-strict JSON constant {constant}")

    path = tmp_path / "t.parquet"
    write_table(pd.DataFrame({"a": [1.0]}), path, {"share": float("nan"), "n": 3})
    assert read_meta(path)["share"] is None and read_meta(path)["n"] == 3
    text = pq.read_schema(path).metadata[META_KEY]
    json.loads(text, parse_constant=refuse)


def test_a_missing_table_says_to_run_the_workflow_not_to_delete_it(tmp_path):
    """A results folder without the table (``qsm export --results`` of an unrun folder)."""
    path = tmp_path / "dataset.parquet"
    with pytest.raises(TableError) as info:
        read_table(path)
    assert f"'{path}' does not exist" in str(info.value) and "delete" not in str(info.value)


@pytest.mark.parametrize(
    ("columns", "only", "where"),
    [
        ((), False, None),
        (["x"], True, None),
        (["x", "name"], True, [("status", "==", "ok")]),  # the filter's column not asked for
        (["x"], False, [("status", "==", "ok"), ("x", ">", 4.0)]),
        (["x"], True, [("status", "==", "lost")]),  # no row kept
        (["x"], True, [("x", ">=", 0.0)]),  # every row kept
    ],
)
def test_part_of_a_table_read_group_by_group_is_what_arrow_reads(
    tmp_path, monkeypatch, columns, only, where
):
    """:func:`read_table` reads a row group at a time and filters each as it comes: the frame is
    pyarrow's whole-file read, exactly, over several groups of which some lose rows."""
    monkeypatch.setattr(tables, "ROW_GROUP", 7)
    n = 30
    frame = pd.DataFrame(
        {
            "x": np.linspace(0.0, 9.0, n),
            "status": np.where(np.arange(n) % 4 == 1, "error", "ok"),
            "name": [f"m{k}" for k in range(n)],
        }
    )
    path = tmp_path / "dataset.parquet"
    write_table(frame, path)
    assert pq.read_metadata(path).num_row_groups == 5
    wanted = list(columns) if only and columns else None
    arrow = pq.read_table(path, columns=wanted, filters=where).to_pandas()
    pd.testing.assert_frame_equal(read_table(path, columns, only, where), arrow, check_exact=True)

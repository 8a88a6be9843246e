"""The report's HTML pages of the Markdown results, and table cells that keep their pipes."""

import pandas as pd

from qsm.design_rules.findings import _markdown
from qsm.report.markdown_pages import markdown_cell, markdown_html


def test_a_cell_with_pipes_stays_one_cell():
    text = _markdown(pd.DataFrame({"experiment": ["|x / eta * d eta / dx|"], "verdict": ["ok"]}))
    row = text.splitlines()[2]
    assert row == "| \\|x / eta * d eta / dx\\| | ok |"
    page = markdown_html(text, "t")
    assert page.count("<td>") == 2
    assert "<td>|x / eta * d eta / dx|</td>" in page


def test_cells_escape_backslashes_and_drop_line_breaks():
    assert markdown_cell("a\\b") == "a\\\\b"
    assert markdown_cell("two\nlines") == "two lines"
    assert markdown_cell(1.5) == "1.5"


def test_page_is_self_contained_html():
    page = markdown_html(
        "# Title <x>\n\n**bold**\n\n| a | b |\n| --- | --- |\n| 1 | 2 |\n", "A & B"
    )
    assert page.startswith("<!DOCTYPE html>")
    assert "<title>A &amp; B</title>" in page
    assert "<strong>bold</strong>" in page and "<table>" in page and "<th>a</th>" in page
    assert "<script" not in page and "http" not in page

"""The run's Markdown results as HTML pages for the Snakemake report.

Snakemake's report shows an HTML output inline but a Markdown one only as a download link, so
``results/summary.md``, ``optimization/comparison.md``, ``realization/torques.md`` and
``design_rules/summary.md`` are converted to self-contained HTML pages (Python-Markdown with its
``tables`` extension, a small inline style sheet, no script and no network). The Markdown files
stay the results; the pages are only their view. :func:`markdown_cell` escapes a table cell's
text so that a ``|`` in it does not split the cell.
"""

from __future__ import annotations

import html
from pathlib import Path

#: Style of the pages: readable tables in the report's iframe and in a browser.
STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 1.5em;
       line-height: 1.45; color: #222; max-width: 75em; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.55em; text-align: left; vertical-align: top; }
th { background: #eef1f5; }
tr:nth-child(even) td { background: #fafafa; }
code { background: #f3f3f3; padding: 0 0.2em; }
h1 { font-size: 1.45em; } h2 { font-size: 1.2em; margin-top: 1.4em; }
"""


def markdown_cell(value: object) -> str:
    """``value`` as the text of a Markdown table cell: ``|`` and ``\\`` escaped, line breaks
    made spaces, so that the cell stays one cell."""
    text = " ".join(str(value).splitlines())
    return text.replace("\\", "\\\\").replace("|", "\\|")


def markdown_html(text: str, title: str) -> str:
    """The Markdown ``text`` as a complete HTML page titled ``title``."""
    import markdown  # here, so that modules using only markdown_cell do not load it

    body = markdown.markdown(text, extensions=["tables", "fenced_code", "sane_lists"])
    return (
        "<!DOCTYPE html>\n<html lang='en'>\n<head>\n<meta charset='utf-8'>\n"
        f"<title>{html.escape(title)}</title>\n<style>{STYLE}</style>\n</head>\n"
        f"<body>\n{body}\n</body>\n</html>\n"
    )


def write_markdown_html(source: str | Path, path: str | Path, title: str) -> Path:
    """Convert the Markdown file ``source`` into the HTML page ``path``."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(markdown_html(Path(source).read_text(), title))
    return out

"""A Plotly figure as one self-contained HTML page small enough for Snakemake's single-file report.

The single-file report (``snakemake --report report.html``) shows an HTML result in an iframe whose
``src`` is the whole file as a base64 ``data:`` URL, and Chromium shows no such URL longer than
2 MiB (:data:`CHROMIUM_MAX_URL_CHARS`): the page must stay under about 1.5 MB. Plotly's full
bundle (plotly.min.js, 4.8 MB) does not fit, so the page carries plotly.js's gl3d partial bundle
(scatter, scatter3d and the 3D scenes; ``data/plotly-gl3d.min.js.gz``, from the npm package
``plotly.js-gl3d-dist-min``, see ``data/README.md``) gzipped and base64-encoded, and a few lines of
JavaScript unpack it with the browser's ``DecompressionStream`` before drawing the figure, which
the page holds as JSON (:func:`figure_json`). The page opens offline, on its own, in the zip
report and in the single-file report.
"""

from __future__ import annotations

import base64
import html
import json
from importlib.resources import files
from pathlib import Path

import plotly.graph_objects as go
import plotly.io as pio

#: Longest URL Chromium navigates to, an iframe's ``data:`` URL included (url::kMaxURLChars).
CHROMIUM_MAX_URL_CHARS = 2 * 1024 * 1024
BUNDLE = "plotly-gl3d.min.js.gz"

_LOADER = """
(async () => {
  const note = document.getElementById("plotly-note");
  try {
    const packed = document.getElementById("plotly-bundle").textContent.trim();
    const bytes = Uint8Array.from(atob(packed), (c) => c.charCodeAt(0));
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
    const bundle = document.createElement("script");
    bundle.textContent = await new Response(stream).text();
    document.head.appendChild(bundle);
    const figure = JSON.parse(document.getElementById("plotly-figure").textContent);
    for (const trace of figure.data) {
      if (trace.text && trace.text.shared !== undefined) {
        trace.text = figure.shared_texts[trace.text.shared];
      }
    }
    const config = JSON.parse(document.getElementById("plotly-config").textContent);
    await Plotly.newPlot(DIV_ID, figure.data, figure.layout, config);
    note.remove();
  } catch (error) {
    note.textContent = "This browser could not draw the figure (" + error + "); " +
      "open the page in a current Chromium, Firefox or Safari.";
  }
})();
"""


def bundle_base64() -> str:
    """The gzipped plotly.js gl3d bundle, base64-encoded (about 0.74 MB)."""
    data = files("qsm.report").joinpath("data", BUNDLE).read_bytes()
    return base64.b64encode(data).decode()


def _script_json(value: object) -> str:
    """JSON safe inside a ``<script>`` element (no ``</`` to close it early)."""
    return json.dumps(value).replace("</", "<\\/")


def figure_json(fig: go.Figure) -> dict:
    """The figure's JSON (``data``, ``layout``), every list of hover texts held once in
    ``shared_texts``: a trace's ``text`` becomes ``{"shared": i}`` (the traces of one design
    in several views share their texts, which are most of the page's data)."""
    figure = json.loads(pio.to_json(fig, validate=False))
    shared: list[list[str]] = []
    for trace in figure["data"]:
        text = trace.get("text")
        if isinstance(text, list) and len(text) > 1:
            if text not in shared:
                shared.append(text)
            trace["text"] = {"shared": shared.index(text)}
    figure["shared_texts"] = shared
    return figure


def figure_page(fig: go.Figure, div_id: str, title: str, config: dict | None = None) -> str:
    """The HTML of a page drawing ``fig`` into the element ``div_id`` (see the module docstring)."""
    loader = _LOADER.replace("DIV_ID", json.dumps(div_id))
    return (
        "<!DOCTYPE html>\n<html><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title></head>\n<body style='margin: 0'>\n"
        "<p id='plotly-note' style='font-family: sans-serif; margin: 12px'>"
        "Drawing the figure...</p>\n"
        f"<div id='{html.escape(div_id)}' style='width: 100%'></div>\n"
        "<script type='application/json' id='plotly-figure'>"
        f"{_script_json(figure_json(fig))}</script>\n"
        f"<script type='application/json' id='plotly-config'>{_script_json(config or {})}"
        "</script>\n"
        f"<script type='text/plain' id='plotly-bundle'>{bundle_base64()}</script>\n"
        f"<script>{loader}</script>\n</body></html>\n"
    )


def write_figure_page(
    fig: go.Figure, path: str | Path, div_id: str, title: str, config: dict | None = None
) -> Path:
    """Write :func:`figure_page` to ``path``; return the path."""
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(figure_page(fig, div_id, title, config), encoding="utf-8")
    return out

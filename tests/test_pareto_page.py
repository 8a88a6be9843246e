"""The interactive front (qsm.report.interactive) as a browser draws it: 3D markers that every
font has a glyph for (plotly draws them as text), failing designs told apart, and 2D markers
outlined so that the colour scale's pale end shows on the light background."""

import numpy as np
import pytest

from qsm.report.interactive import front_figure
from qsm.workflow.tables import read_table

pytestmark = pytest.mark.workflow

#: plotly's scatter3d glyphs (src/constants/gl_markers.js) that DejaVu Sans, the fallback of
#: Debian's and most Linux browsers, draws; its "x" is U+274C, an emoji, drawn as an empty box.
DRAWN_GLYPHS = {"circle", "circle-open", "square", "square-open", "diamond", "diamond-open",
                "cross"}  # fmt: skip


def test_the_front_draws_every_marker_and_tells_failures_apart(run):
    table = read_table(run / "results/optimization/paper/verification.parquet")
    table.loc[table.index[::3], "printable"] = False
    fig = front_figure(table, "paper", "", None)
    failing = ~table["printable"].to_numpy(bool)
    three_d = [t for t in fig.data if t.type == "scatter3d"]
    for trace in three_d:
        symbols = np.atleast_1d(np.asarray(trace.marker.symbol, dtype=object))
        assert set(symbols) <= DRAWN_GLYPHS
    predicted = np.asarray(three_d[0].marker.symbol, dtype=object)
    assert set(predicted[failing]) != set(predicted[~failing])  # told apart
    flat = [t for t in fig.data if t.type == "scatter" and t.legendgroup == "predicted"]
    for trace in flat:
        assert trace.marker.line.color is not None and trace.marker.line.width > 0
        symbols = np.asarray(trace.marker.symbol, dtype=object)
        assert set(symbols[failing]) == {"x"} and set(symbols[~failing]) == {"circle"}

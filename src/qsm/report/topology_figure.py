"""Figure of the topology-optimised links (:mod:`qsm.realization.topology.topology`): the density
fields (0-1) with the CAD and the printed outlines in the link frames (m).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from qsm.realization.topology.geometry import (
    polygons,
)
from qsm.realization.topology.topology import TopologyResult


def plot_links(result: TopologyResult, path: str | Path) -> Path:
    """Figure of the optimised density fields with the CAD outline and the printed outline."""
    import matplotlib.pyplot as plt

    n = len(result.links)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.4), squeeze=False)
    for ax, res in zip(axes[:, 0], result.links.values(), strict=True):
        g = res.grid
        extent = (g.origin[0], g.origin[0] + g.nx * g.h, g.origin[1], g.origin[1] + g.ny * g.h)
        ax.imshow(res.density, origin="lower", extent=extent, cmap="Greys", vmin=0, vmax=1)
        ax.plot(*res.outline.T, color="tab:blue", lw=0.8, label="CAD outline")
        for i, poly in enumerate(polygons(res.polygon)):
            ax.plot(
                *np.asarray(poly.exterior.coords).T,
                color="tab:red",
                lw=0.8,
                label="printed" if i == 0 else None,
            )
            for hole in poly.interiors:
                ax.plot(*np.asarray(hole.coords).T, color="tab:red", lw=0.6)
        ax.set_aspect("equal")
        ax.set_title(
            f"{res.name}: mass {res.props_before.mass_kg:.3f} -> {res.props_after.mass_kg:.3f} kg, "
            f"compliance {res.compliance_before_J:.3g} -> {res.compliance_after_J:.3g} J, "
            f"peak von Mises {res.max_von_mises_after_pa / 1e6:.1f} MPa",
            fontsize=8,
        )
        ax.set_xlabel("x (m, link frame)")
        ax.set_ylabel("y (m)")
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=150)
    plt.close(fig)
    return out

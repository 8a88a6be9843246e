"""The export's printability: each link's box against the printer, each link of its own section
(the configured one, or the one sized by strength).

The boxes, fit test, needed volume and excess are those of :mod:`qsm.embodiment.printing` and
:func:`qsm.optimization.constraints.printability_violation_mm`, taken link by link: with one
section for every link they are the same numbers.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from qsm.embodiment.printing import link_boxes_mm
from qsm.physics.cad import CadSettings, link_outlines, link_settings
from qsm.physics.kinematics import LINK_NAMES, as_design


def _short_m(design: np.ndarray, k: int, cad: CadSettings) -> float:
    """How much (m) link ``k`` of ``design`` falls short of holding its bosses of section
    ``cad`` (<= 0: the slack; the bar and leg terms of ``printability_violation_mm``)."""
    x0, h = cad.boss_overlap_m, cad.width_m / 2
    if k < 3:
        return 2 * x0 - design[k]
    return max(2 * x0 - design[3], x0 + h - design[4], x0 + h - design[5])


def link_printability(
    design: ArrayLike, cad: CadSettings, scale: ArrayLike | None, volume_mm: tuple[float, ...]
) -> dict[str, Any]:
    """``links``: per link its outline's box (x, y extents and thickness, mm) and whether it fits
    ``volume_mm`` in some axis-aligned orientation; ``needed_volume_mm`` (sides from the largest)
    and ``print_excess_mm`` (g12: the largest excess of a sorted box over the sorted volume, or
    of a bar too short for its bosses), each link of ``cad``'s section scaled by its entry of
    ``scale`` (4,) (None: ``cad``'s)."""
    d = np.asarray(as_design(design), dtype=float)
    sections = link_settings(cad, scale)
    vol = np.sort(np.asarray(volume_mm, dtype=float))
    links = {}
    for name, poly in link_outlines(d, cad, scale).items():
        ext = (poly.max(axis=0) - poly.min(axis=0)) * 1e3
        dims = (float(ext[0]), float(ext[1]), sections[name].thickness_m * 1e3)
        links[name] = {"fits": bool(np.all(np.sort(dims) <= vol + 1e-9)), "dims_mm": dims}
    boxes = np.stack(
        [link_boxes_mm(d[None], None, sections[n])[0, k] for k, n in enumerate(LINK_NAMES)]
    )
    excess = max(
        max(float((np.sort(boxes[k]) - vol).max()), 1e3 * _short_m(d, k, sections[n]))
        for k, n in enumerate(LINK_NAMES)
    )
    return {
        "links": links,
        "needed_volume_mm": np.sort(boxes, axis=-1)[..., ::-1].max(axis=0).tolist(),
        "print_excess_mm": excess,
    }

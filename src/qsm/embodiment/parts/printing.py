"""Printability: link boxes, the fit test, and the smallest printer on which a design fits.

A link fits when its axis-aligned bounding box (outline extents in its link frame x plate
thickness, mm), sorted, is no larger than the sorted build volume dimension by dimension (the part
may be laid in any orientation aligned with the build axes). :func:`link_boxes_mm` gives the boxes
in closed form for a whole population (the optimisation's g12 and every fit test use it);
:func:`outline_boxes_mm` measures them on the outlines of :mod:`qsm.physics.cad` (a test holds
the two together).

The build volume a design needs is the largest sorted bounding box over its four links (each link
may be turned to any axis-aligned orientation, so only the sorted sides matter). With bored parts
the bosses follow the bearings (:func:`qsm.embodiment.parts.link_parts.joint_radii`), so the boxes
are computed from the per-joint boss radii (:func:`link_boxes_mm`, closed form of the outlines of
:mod:`qsm.embodiment.parts.link_parts`; with every radius equal to ``cad.boss_radius_m`` it is
:func:`link_boxes_mm` without radii).

This module is where printability is decided: the fit test (:func:`box_fits`, one tolerance),
the optimisation's g12 (:func:`printability_violation_mm`), the selection's and the STL files'
fit (:func:`all_links_fit`, :func:`box_fits`), the export's per-link account with each link of
its own section (:func:`link_printability`) and the advice on the printer a design needs.

"Smallest" orders the needed volumes lexicographically on their sides sorted from the largest down
(a long link decides first: it is what rules printers out), then by the volume. Sizes are rounded
**up** to whole millimetres, so the advised printer holds the parts (1409.22 mm -> 1410 mm).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import DEFAULT_CAD, CadError, CadSettings, link_outlines, link_settings
from qsm.physics.kinematics import DESIGN_COLUMNS, LINK_NAMES, as_design
from qsm.schema.defaults import default

#: How far (mm) a box may exceed the build volume and still fit: rounding, never a real excess.
#: Every fit test of qsm (the outlines', the STL files', the export's) uses it.
FIT_TOLERANCE_MM = 1e-9

#: The paper's printer, W x L x H (mm).
BUILD_VOLUME_MM: tuple[float, float, float] = tuple(map(float, default("printing.build_volume_mm")))


def link_boxes_mm(
    designs: ArrayLike, radii: ArrayLike | None = None, cad: CadSettings = DEFAULT_CAD
) -> NDArray[np.float64]:
    """Bounding boxes (N, 4, 3) in mm of the four links (link frames, LINK_NAMES order).

    ``designs`` (N, 6) scaled lengths (m); ``radii`` (N, 5) boss radii (m) at A, B, C, D, E (None:
    ``cad.boss_radius_m`` everywhere). A bar of length L between bosses r0, r1 spans
    ``L + r0 + r1`` by ``2 max(r0, r1)``; the upper arm (B at the origin, D = (-l4, 0),
    E = (EE_x, -EE_y)) spans ``max(l4 + rD, rB) + max(rB, EE_x + rE)`` by
    ``max(rD, rB, rE - EE_y) + max(rD, rB, EE_y + rE)``; every plate is ``thickness`` thick.
    """
    d = np.atleast_2d(as_design(designs))
    if radii is None:
        r = np.full((len(d), 5), cad.boss_radius_m)
    else:
        r = np.broadcast_to(np.asarray(radii, dtype=float), (len(d), 5))
    ra, rb, rc, rd, re = (r[:, k] for k in range(5))
    l1, l2, l3, l4, ex, ey = (d[:, k] for k in range(6))
    x = np.column_stack(
        [
            l1 + ra + rb,
            l2 + ra + rc,
            l3 + rc + rd,
            np.maximum(l4 + rd, rb) + np.maximum(rb, ex + re),
        ]
    )
    y = np.column_stack(
        [
            2 * np.maximum(ra, rb),
            2 * np.maximum(ra, rc),
            2 * np.maximum(rc, rd),
            np.maximum.reduce([rd, rb, re - ey]) + np.maximum.reduce([rd, rb, ey + re]),
        ]
    )
    z = np.full_like(x, cad.thickness_m)
    return np.stack([x, y, z], axis=-1) * 1e3


def needed_volume_mm(
    designs: ArrayLike, radii: ArrayLike | None = None, cad: CadSettings = DEFAULT_CAD
) -> NDArray[np.float64]:
    """Smallest build volume (N, 3) holding every link, sides from the largest (mm, exact)."""
    boxes = np.sort(link_boxes_mm(designs, radii, cad), axis=-1)[..., ::-1]
    return boxes.max(axis=1)


def box_excess_mm(
    designs: ArrayLike, cad: CadSettings, volume_mm: ArrayLike, radii: ArrayLike | None = None
) -> NDArray[np.float64]:
    """Largest excess (mm) of a link's sorted box over the sorted build volume, per design: the
    fit test (<= 0 fits)."""
    boxes = np.sort(link_boxes_mm(designs, radii, cad), axis=-1)
    return (boxes - np.sort(np.asarray(volume_mm, dtype=float))).max(axis=(1, 2))


def round_up_mm(sizes_mm: ArrayLike) -> list[int]:
    """Sizes rounded up to whole mm (a size within 1e-6 mm of an integer keeps it)."""
    return [math.ceil(float(v) - 1e-6) for v in np.ravel(sizes_mm)]


def smallest_build_volume(
    table: pd.DataFrame,
    holds: ArrayLike | str,
    cad: CadSettings = DEFAULT_CAD,
    radii: ArrayLike | None = None,
) -> dict[str, Any]:
    """The smallest build volume over the designs of ``table`` that truly hold the task.

    ``table`` has the scaled lengths :data:`qsm.physics.kinematics.DESIGN_COLUMNS` (m), one row per
    design (dataset and fronts together, with e.g. ``mechanism_id`` and ``source`` columns, kept
    in the answer when present); ``holds`` a boolean per row, or the name of such a column (e.g.
    clearance >= 0 and the dynamics ok); ``radii`` (N, 5) per-design boss radii (m) or None.

    Returns ``{"needed_volume_mm": [int, int, int]`` rounded up, sides from the largest,
    ``"exact_volume_mm"``, ``"row"`` (the table's index label of the design), ``"design_m"`` (its
    6 lengths), ``"designs_holding"`` (how many were considered) and the row's ``mechanism_id`` /
    ``source`` when present}, or None when no design holds the task.
    """
    ok = np.asarray(table[holds] if isinstance(holds, str) else holds, dtype=bool)
    if ok.shape != (len(table),):
        raise ValueError("holds needs one boolean per row of the table")
    if not ok.any():
        return None
    designs = table.loc[:, list(DESIGN_COLUMNS)].to_numpy(float)
    need = needed_volume_mm(designs, radii, cad)
    need = np.where(ok[:, None], need, np.inf)
    order = np.lexsort((need.prod(axis=1), need[:, 2], need[:, 1], need[:, 0]))
    best = int(order[0])
    out: dict[str, Any] = {
        "needed_volume_mm": round_up_mm(need[best]),
        "exact_volume_mm": [float(v) for v in need[best]],
        "row": table.index[best],
        "design_m": [float(v) for v in designs[best]],
        "designs_holding": int(ok.sum()),
    }
    for key in ("mechanism_id", "source", "formulation"):
        if key in table.columns:
            value = table.iloc[best][key]
            out[key] = value.item() if hasattr(value, "item") else value
    return out


def advice_sentence(advice: dict[str, Any] | None, volume_mm: ArrayLike) -> str:
    """The advice in one sentence, every number from ``advice``; a design that, realised, fits
    ``volume_mm`` is named as one to export (:func:`_fits_as_realised`)."""
    have = " x ".join(f"{v:g}" for v in np.ravel(volume_mm))
    if advice is None:
        return (
            f"no design holds the task, so no printer size can be advised (configured: {have} mm)"
        )
    need = " x ".join(str(v) for v in advice["needed_volume_mm"])
    who = advice.get("mechanism_id", advice["row"])
    if isinstance(who, float) and who.is_integer():
        who = int(who)
    where = f" ({advice['source']})" if "source" in advice else ""
    if advice.get("holds_loads") and box_fits(advice["exact_volume_mm"], volume_mm):
        return _fits_as_realised(advice, f"{who}{where}", need, have)
    sentence = (
        f"a printer of at least {need} mm (configured: {have} mm) for design {who}{where}, "
        f"the one of the {advice['designs_holding']} designs that hold their loads with the "
        "smallest printer at the configured section"
    )
    realised = ", its links as this run realises them" if "holds_loads" in advice else ""
    return sentence + realised


def _fits_as_realised(advice: dict[str, Any], who: str, need: str, have: str) -> str:
    """Design ``who`` of ``advice``, realised, fits the configured printer ``have`` (the pool
    was judged at the configured section; its realised, sized links are smaller): the command
    that builds it where it has drives and meets the tolerance as realised, else what fails."""
    fits = (
        f"design {who}, with its links as this run realises them, fits the configured printer "
        f"({need} mm needed, {have} mm configured) and holds its loads (strength utilisation "
        f"{advice['strength_utilisation']:.2f})"
    )
    fails = []
    if advice.get("has_drives") is False:
        fails.append("a motor has no drive of the catalogue that meets its duty")
    if advice.get("meets_tolerance") is False:
        got, allowed = advice.get("structure_mm"), advice.get("target_mm")
        fails.append(
            "its structure misses the tolerance"
            + (f" ({got:.2f} mm, {allowed:.2f} mm allowed)" if None not in (got, allowed) else "")
        )
    if fails:
        return f"{fits}, but {' and '.join(fails)}: no printer makes it ready"
    lengths = " ".join(np.format_float_positional(x, trim="-") for x in advice["design_m"])
    return (
        f"{fits}, while the designs were judged printable at the configured section: build it "
        f"with `qsm export --lengths {lengths} --config` and this run's config files"
    )


def outline_boxes_mm(design: ArrayLike, cad: CadSettings) -> dict[str, tuple[float, float, float]]:
    """Bounding box (x extent, y extent, thickness) in mm of every link's outline in its frame."""
    out = {}
    for name, poly in link_outlines(design, cad).items():
        ext = (poly.max(axis=0) - poly.min(axis=0)) * 1e3
        out[name] = (float(ext[0]), float(ext[1]), cad.thickness_m * 1e3)
    return out


def fits_build_volume(
    design: ArrayLike,
    cad: CadSettings = DEFAULT_CAD,
    volume_mm: tuple[float, float, float] = BUILD_VOLUME_MM,
) -> dict[str, dict[str, Any]]:
    """Per link: ``{"fits": bool, "dims_mm": (x, y, thickness)}``; a link fits when its sorted
    box does not exceed the sorted build volume ``volume_mm``.

    Raises :class:`qsm.physics.cad.CadError` when the section does not fit the design at all.
    """
    out = {}
    for name, dims in outline_boxes_mm(design, cad).items():
        out[name] = {"fits": box_fits(dims, volume_mm), "dims_mm": dims}
    return out


def box_fits(dims_mm: ArrayLike, volume_mm: ArrayLike) -> bool:
    """Whether a box (mm) fits the build volume ``volume_mm`` in some axis-aligned orientation:
    sorted side by side, within :data:`FIT_TOLERANCE_MM`."""
    dims, vol = np.sort(np.asarray(dims_mm, float)), np.sort(np.asarray(volume_mm, float))
    return bool(np.all(dims <= vol + FIT_TOLERANCE_MM))


def shortfall_m(designs: ArrayLike, cad: CadSettings) -> NDArray[np.float64]:
    """How much (m) each link (N, 4) of ``designs`` (N, 6) falls short of holding its bosses of
    section ``cad``: a bar (lower arm, crank, coupler) needs two boss overlaps, the upper arm's
    rocker leg too and its two legs ``cad.leg_min_m`` each (<= 0: the slack)."""
    d = np.atleast_2d(as_design(designs))
    x0, leg = cad.boss_overlap_m, cad.leg_min_m
    bars = 2 * x0 - d[:, :4]
    upper = np.column_stack([bars[:, 3], leg - d[:, 4], leg - d[:, 5]]).max(axis=1)
    return np.column_stack([bars[:, :3], upper])


def all_links_fit(
    design: ArrayLike,
    cad: CadSettings = DEFAULT_CAD,
    volume_mm: tuple[float, float, float] = BUILD_VOLUME_MM,
) -> bool:
    """Whether every link fits the build volume (False when the CAD section is invalid)."""
    try:
        return all(v["fits"] for v in fits_build_volume(design, cad, volume_mm).values())
    except CadError:
        return False


def printability_violation_mm(
    designs: ArrayLike, cad: CadSettings, volume_mm: ArrayLike
) -> NDArray[np.float64]:
    """g12: largest excess (mm) of a link's sorted box over the sorted build volume, per design.

    Also positive when the section is too large for a link (:class:`qsm.physics.cad.CadError`): by
    how much (mm) the shortest bar falls short of holding its two bosses.
    """
    d = np.atleast_2d(as_design(designs))
    excess = box_excess_mm(d, cad, volume_mm)
    return np.maximum(excess, shortfall_m(d, cad).max(axis=1) * 1e3)


def section_boxes_mm(
    design: ArrayLike, cad: CadSettings, scale: ArrayLike | None
) -> NDArray[np.float64]:
    """Bounding boxes (4, 3) in mm of the four links of ``design`` (6 lengths, m), each of
    ``cad``'s section scaled by its entry of ``scale`` (4,) (None: ``cad``'s):
    :func:`link_boxes_mm` link by link."""
    d = np.asarray(as_design(design), dtype=float)
    sections = link_settings(cad, scale)
    return np.stack(
        [link_boxes_mm(d[None], None, sections[n])[0, k] for k, n in enumerate(LINK_NAMES)]
    )


def section_needed_mm(
    design: ArrayLike, cad: CadSettings, scale: ArrayLike | None
) -> NDArray[np.float64]:
    """Smallest build volume (3,) holding every link of :func:`section_boxes_mm`, sides from the
    largest (mm, exact): :func:`needed_volume_mm` with each link at its own section."""
    return np.sort(section_boxes_mm(design, cad, scale), axis=-1)[..., ::-1].max(axis=0)


def link_printability(
    design: ArrayLike, cad: CadSettings, scale: ArrayLike | None, volume_mm: tuple[float, ...]
) -> dict[str, Any]:
    """``links``: per link its outline's box (x, y extents and thickness, mm) and whether it fits
    ``volume_mm`` (:func:`box_fits`); ``needed_volume_mm`` (sides from the largest) and
    ``print_excess_mm`` (g12, :func:`printability_violation_mm`, link by link), each link of
    ``cad``'s section scaled by its entry of ``scale`` (4,) (None: ``cad``'s). With one section
    for every link the numbers are g12's."""
    d = np.asarray(as_design(design), dtype=float)
    sections = link_settings(cad, scale)
    vol = np.sort(np.asarray(volume_mm, dtype=float))
    links = {}
    for name, poly in link_outlines(d, cad, scale).items():
        ext = (poly.max(axis=0) - poly.min(axis=0)) * 1e3
        dims = (float(ext[0]), float(ext[1]), sections[name].thickness_m * 1e3)
        links[name] = {"fits": box_fits(dims, vol), "dims_mm": dims}
    return {
        "links": links,
        "needed_volume_mm": section_needed_mm(d, cad, scale).tolist(),
        "print_excess_mm": section_excess_mm(d, cad, scale, vol),
    }


def section_excess_mm(
    design: ArrayLike, cad: CadSettings, scale: ArrayLike | None, volume_mm: ArrayLike
) -> float:
    """g12 (:func:`printability_violation_mm`) link by link, each link of ``cad``'s section
    scaled by its entry of ``scale`` (4,) (None: ``cad``'s): the largest excess (mm) of a link's
    sorted box over the sorted build volume, or of its bosses over its length (<= 0 fits)."""
    boxes = np.sort(section_boxes_mm(design, cad, scale), axis=-1)
    vol = np.sort(np.asarray(volume_mm, dtype=float))
    return max(float((boxes - vol).max()), 1e3 * section_shortfall_m(design, cad, scale))


def section_shortfall_m(design: ArrayLike, cad: CadSettings, scale: ArrayLike | None) -> float:
    """:func:`shortfall_m` link by link, each link of ``cad``'s section scaled by its entry of
    ``scale`` (4,) (None: ``cad``'s): how much (m) the link furthest from holding its bosses
    falls short (<= 0: every link holds them)."""
    d = np.asarray(as_design(design), dtype=float)
    sections = link_settings(cad, scale)
    return max(float(shortfall_m(d, sections[n])[0, k]) for k, n in enumerate(LINK_NAMES))

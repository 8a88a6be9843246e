"""Printability and the choice of the design to realise (paper Section 5, Fig. 6 diamond).

The paper picks its final design among the 100 Pareto designs "considering the maximum
manufacturable size" of its printer (W x L x H = 600 x 350 x 350 mm). A link fits when its
axis-aligned bounding box (outline extents in its link frame x plate thickness, mm), sorted, is
no larger than the sorted build volume dimension by dimension (the part may be laid in any
orientation aligned with the build axes).

Selection rules of :func:`select_design`, applied to the verified candidates (``feasible`` and
``dynamics_status == 'ok'``) whose links all fit:

* ``min_tau1``: smallest true peak torque of motor 1 (``tau1_true_Nm``);
* ``min_tau2``: smallest ``tau2_true_Nm``;
* ``min_torque_sum``: smallest ``tau1_true_Nm + tau2_true_Nm``;
* ``min_eta``: smallest true ``eta_true`` (largest workspace around the task);
* ``knee``: closest (Euclidean) to the ideal point of the three true objectives
  (eta_true, tau1_true_Nm, tau2_true_Nm), each min-max normalised over the candidates that fit.

Ties are broken by the row order of the table.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from qsm.physics.cad import DEFAULT_CAD, CadError, CadSettings, link_outlines
from qsm.physics.kinematics import DESIGN_COLUMNS

BUILD_VOLUME_MM: tuple[float, float, float] = (600.0, 350.0, 350.0)
RULES: tuple[str, ...] = ("min_tau1", "min_tau2", "min_torque_sum", "min_eta", "knee")
OBJECTIVES: tuple[str, ...] = ("eta_true", "tau1_true_Nm", "tau2_true_Nm")


def link_boxes_mm(design: ArrayLike, cad: CadSettings) -> dict[str, tuple[float, float, float]]:
    """Bounding box (x extent, y extent, thickness) in mm of every link in its link frame."""
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
    bounding-box dimensions do not exceed the sorted build volume ``volume_mm``.

    Raises :class:`qsm.physics.cad.CadError` when the section does not fit the design at all.
    """
    vol = np.sort(np.asarray(volume_mm, dtype=float))
    out = {}
    for name, dims in link_boxes_mm(design, cad).items():
        fits = bool(np.all(np.sort(dims) <= vol + 1e-9))
        out[name] = {"fits": fits, "dims_mm": dims}
    return out


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


def rule_scores(df: pd.DataFrame, rule: str) -> np.ndarray:
    """Score of every row of a verified table under selection ``rule`` (smaller is better)."""
    if rule == "min_tau1":
        return df["tau1_true_Nm"].to_numpy(float)
    if rule == "min_tau2":
        return df["tau2_true_Nm"].to_numpy(float)
    if rule == "min_torque_sum":
        return (df["tau1_true_Nm"] + df["tau2_true_Nm"]).to_numpy(float)
    if rule == "min_eta":
        return df["eta_true"].to_numpy(float)
    if rule == "knee":
        obj = df.loc[:, list(OBJECTIVES)].to_numpy(float)
        lo, hi = obj.min(axis=0), obj.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        return np.linalg.norm((obj - lo) / span, axis=1)
    raise ValueError(f"unknown selection rule {rule!r}; choose one of {RULES}")


def select_design(
    verified: pd.DataFrame,
    rule: str = "knee",
    cad: CadSettings = DEFAULT_CAD,
    volume_mm: tuple[float, float, float] = BUILD_VOLUME_MM,
) -> pd.Series:
    """The row of ``verified`` chosen by ``rule`` (see the module docstring) among the feasible,
    dynamically verified (``dynamics_status == 'ok'``) designs whose links all fit ``volume_mm``.

    The returned row (a copy, same index label) gains ``selection_rule``, ``selection_score``,
    ``n_candidates`` (rows that fit) and, per link, ``<link>_box_mm`` (x, y, thickness).
    Raises ``ValueError`` when no row qualifies or the rule is unknown.
    """
    if rule not in RULES:
        raise ValueError(f"unknown selection rule {rule!r}; choose one of {RULES}")
    missing = [
        c
        for c in (*DESIGN_COLUMNS, *OBJECTIVES, "feasible", "dynamics_status")
        if c not in verified.columns
    ]
    if missing:
        raise ValueError(f"verified table lacks columns {missing}")
    ok = verified[(verified["feasible"].astype(bool)) & (verified["dynamics_status"] == "ok")]
    ok = ok[np.isfinite(ok.loc[:, list(OBJECTIVES)].to_numpy(float)).all(axis=1)]
    designs = ok.loc[:, list(DESIGN_COLUMNS)].to_numpy(float)
    fit = np.array([all_links_fit(d, cad, volume_mm) for d in designs], dtype=bool)
    cand = ok[fit]
    if cand.empty:
        raise ValueError(
            f"no design qualifies: {len(verified)} rows, {len(ok)} feasible with dynamics 'ok', "
            f"none of them has every link within the build volume {tuple(volume_mm)} mm"
        )
    scores = rule_scores(cand, rule)
    k = int(np.argmin(scores))
    row = cand.iloc[k].copy()
    row["selection_rule"] = rule
    row["selection_score"] = float(scores[k])
    row["n_candidates"] = len(cand)
    for name, info in fits_build_volume(designs[fit][k], cad, volume_mm).items():
        row[f"{name}_box_mm"] = info["dims_mm"]
    return row

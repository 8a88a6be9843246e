"""A gearbox's lost motion and torsional stiffness at its output, from the catalogue's optional
columns ``backlash_arcmin`` and ``torsional_stiffness_Nm_rad``, or assumed where they are empty.

A catalogue row says whether each value is the maker's (``backlash_status``,
``stiffness_status``: published or assumed) and where it comes from (``stiffness_source``). A
catalogue without the columns (MGDB's own) gets the assumptions below, and the record says so.
"""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

#: Backlash (arcmin) assumed for a gearbox without one: a harmonic drive's lost motion is about
#: 1 arcmin (Harmonic Drive CSF/CSG catalogue); a planetary head's about 1 deg (maxon's standard
#: GP heads), which is taken for any other type as well.
ASSUMED_BACKLASH_ARCMIN: dict[str, float] = {"harmonic": 1.0}
DEFAULT_BACKLASH_ARCMIN = 60.0
#: Torsional stiffness (N m/rad) assumed for a gearbox without one: the low end of Neugart's
#: PLE040, the smallest planetary frame of the shipped catalogue's sources (0.7 N m/arcmin).
DEFAULT_STIFFNESS_NM_RAD = 2.4e3
ARCMIN_RAD = math.pi / (180 * 60)


def _given(gearbox: pd.Series, column: str) -> float | None:
    value = gearbox.get(column)
    return float(value) if value is not None and math.isfinite(float(value)) else None


def _origin(gearbox: pd.Series, what: str) -> str:
    """``status: source`` of a catalogue value (``backlash`` or ``stiffness``)."""
    status = str(gearbox.get(f"{what}_status", "") or "").strip() or "catalogue"
    source = str(gearbox.get(f"{what}_source", "") or "").strip()
    return f"{status}: {source}" if source else status


def gear_compliance(gearbox: pd.Series) -> dict[str, Any]:
    """JSON-ready backlash (arcmin) and torsional stiffness (N m/rad) of a catalogue gearbox row,
    with ``backlash_from`` and ``stiffness_from``: the catalogue's status and source, or the
    assumption taken where the row has no value."""
    kind = str(gearbox.get("type", "") or "").lower()
    backlash = _given(gearbox, "backlash_arcmin")
    stiffness = _given(gearbox, "torsional_stiffness_Nm_rad")
    if backlash is None:
        backlash = ASSUMED_BACKLASH_ARCMIN.get(kind, DEFAULT_BACKLASH_ARCMIN)
        backlash_from = f"assumed {backlash:g} arcmin for a {kind or 'untyped'} gearbox"
    else:
        backlash_from = _origin(gearbox, "backlash")
    if stiffness is None:
        stiffness = DEFAULT_STIFFNESS_NM_RAD
        stiffness_from = f"assumed {stiffness:g} N m/rad (Neugart PLE040's low end)"
    else:
        stiffness_from = _origin(gearbox, "stiffness")
    return {
        "backlash_arcmin": backlash,
        "torsional_stiffness_Nm_rad": stiffness,
        "backlash_from": backlash_from,
        "stiffness_from": stiffness_from,
    }

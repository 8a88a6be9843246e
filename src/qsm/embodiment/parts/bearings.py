"""Rolling bearings at the joints: a small catalogue, the choice per joint, and the boss it needs.

Every joint A, B, C, D of the mechanism turns slowly and through less than a revolution (the
motors sweep the operating range), so the bearing is sized on its **basic static load rating** C0,
as SKF advises for bearings that are stationary, rotate very slowly or make slow oscillating
movements (SKF, *Rolling bearings*, PUB BU/P1 17000/1 EN, 2018, "Selecting bearing size": size
selection based on static load). The requisite rating is ``C0 >= s0 P0`` with the equivalent static
load ``P0 = Fr`` for a purely radial load (``P0 = 0.6 Fr + 0.5 Fa``, and ``P0 = Fr`` when that is
smaller; a planar linkage has no designed axial load). SKF's guideline values of the static safety
factor s0 for rotating *ball* bearings are 0.5 / 1 / 2 for unimportant / normal / high performance
requirements (quiet, vibration-free running) under smooth or normal loading, and >= 1.5 / >= 1.5 /
>= 2 under pronounced shock loads (same catalogue, table "Guideline values for the static safety
factor s0"). The default ``s0 = 2`` is the largest of these for ball bearings: a printed, hand
assembled arm with unmeasured shocks. The dynamic rating C is carried along for reports only.

The catalogue (:data:`DEFAULT_CATALOGUE`, ``data/bearings.csv``) lists SKF single-row deep groove
ball bearings of bore 5-30 mm with the maker's figures and the document they come from. The choice
at a joint is the *smallest* bearing, ordered by outer diameter D (the boss grows with D), then
width B, then bore d, whose ``C0`` covers ``s0`` times the joint's peak radial force and, when a pin
material is given, whose bore takes a pin that holds the force in single shear. Optionally only
bearings no wider than the plate (``max_width_m``) are considered.

The boss of a link at a joint has radius ``max(boss_radius_m, D / 2 + wall)``: the bearing's seat
with a wall of ``boss_wall_m`` around it, never smaller than the configured boss (the bar's outline
needs a boss wider than the bar).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from importlib import resources
from pathlib import Path
from typing import NamedTuple

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

#: The joints that get a bearing: A (the motor shafts of the lower arm and the crank), B, C, D.
JOINTS: tuple[str, ...] = ("A", "B", "C", "D")
#: Default static safety factor s0 = C0 / P0 (SKF guideline for ball bearings, high requirements).
DEFAULT_SAFETY_FACTOR = 2.0
#: Default wall (m) of printed material around a bearing seat.
DEFAULT_BOSS_WALL_M = 0.004
#: Minimum yield strength (Pa) of structural steel S235 (EN 10025-2, thickness <= 16 mm): an
#: example pin material for :func:`min_pin_diameter_m`.
S235_YIELD_PA = 235e6


def _default_catalogue() -> Path:
    return Path(str(resources.files("qsm.embodiment.parts") / "data" / "bearings.csv"))


DEFAULT_CATALOGUE = _default_catalogue()


@dataclass(frozen=True)
class BearingTable:
    """A bearing catalogue in SI units, sorted by outer diameter, width, then bore (smallest first).

    designation (K,) str; d_m, D_m, B_m (K,) bore, outer diameter and width (m); C_N, C0_N (K,)
    basic dynamic and static load ratings (N); maker, source (K,) str.
    """

    designation: NDArray[np.str_]
    d_m: NDArray[np.float64]
    D_m: NDArray[np.float64]
    B_m: NDArray[np.float64]
    C_N: NDArray[np.float64]
    C0_N: NDArray[np.float64]
    maker: NDArray[np.str_]
    source: NDArray[np.str_]

    def __len__(self) -> int:
        return len(self.designation)

    def row(self, index: int) -> dict[str, object]:
        """One bearing as a plain dict (SI units)."""
        return {
            "designation": str(self.designation[index]),
            "d_m": float(self.d_m[index]),
            "D_m": float(self.D_m[index]),
            "B_m": float(self.B_m[index]),
            "C_N": float(self.C_N[index]),
            "C0_N": float(self.C0_N[index]),
            "maker": str(self.maker[index]),
            "source": str(self.source[index]),
        }


def load_catalogue(path: str | Path | None = None) -> BearingTable:
    """Read a bearing CSV (columns as ``data/bearings.csv``, mm and kN; ``#`` starts a comment)."""
    frame = pd.read_csv(path or DEFAULT_CATALOGUE, comment="#", dtype={"designation": str})
    needed = ["designation", "d_mm", "D_mm", "B_mm", "C_kN", "C0_kN", "maker", "source"]
    missing = [c for c in needed if c not in frame.columns]
    if missing:
        raise ValueError(f"bearing catalogue {path} lacks columns {missing}")
    if len(frame) == 0:
        raise ValueError(f"bearing catalogue {path} is empty")
    num = frame[["d_mm", "D_mm", "B_mm", "C_kN", "C0_kN"]].to_numpy(float)
    if not (np.isfinite(num).all() and (num > 0).all() and (num[:, 1] > num[:, 0]).all()):
        raise ValueError(f"bearing catalogue {path}: sizes and ratings must be positive, D > d")
    frame = frame.sort_values(["D_mm", "B_mm", "d_mm"], kind="stable").reset_index(drop=True)
    return BearingTable(
        designation=frame["designation"].to_numpy(str),
        d_m=frame["d_mm"].to_numpy(float) * 1e-3,
        D_m=frame["D_mm"].to_numpy(float) * 1e-3,
        B_m=frame["B_mm"].to_numpy(float) * 1e-3,
        C_N=frame["C_kN"].to_numpy(float) * 1e3,
        C0_N=frame["C0_kN"].to_numpy(float) * 1e3,
        maker=frame["maker"].to_numpy(str),
        source=frame["source"].to_numpy(str),
    )


def min_shaft_diameter_m(
    torque_Nm: ArrayLike,
    yield_pa: float = S235_YIELD_PA,
    safety_factor: float = DEFAULT_SAFETY_FACTOR,
) -> NDArray[np.float64]:
    """Smallest solid shaft (m) that carries ``torque_Nm`` in torsion: the peak shear stress
    ``16 T / (pi d^3)`` within the shear yield ``yield_pa / sqrt(3)`` (von Mises) divided by
    ``safety_factor``: ``d = (16 s T sqrt(3) / (pi yield))^(1/3)``."""
    t = np.abs(np.asarray(torque_Nm, dtype=float))
    return np.cbrt(16.0 * safety_factor * t * math.sqrt(3.0) / (math.pi * yield_pa))


def min_pin_diameter_m(
    force_N: ArrayLike,
    yield_pa: float = S235_YIELD_PA,
    safety_factor: float = DEFAULT_SAFETY_FACTOR,
) -> NDArray[np.float64]:
    """Smallest solid pin (m) that carries ``force_N`` in single shear.

    Mean shear stress ``4 F / (pi d^2)`` against the shear yield ``yield_pa / sqrt(3)`` (von Mises)
    divided by ``safety_factor``: ``d = sqrt(4 s F sqrt(3) / (pi yield))``.
    """
    f = np.abs(np.asarray(force_N, dtype=float))
    return np.sqrt(4.0 * safety_factor * f * math.sqrt(3.0) / (math.pi * yield_pa))


class BearingChoice(NamedTuple):
    """The bearing per joint, arrays of the loads' shape (..., J).

    index: row of the catalogue (-1 where none fits); violation: continuous, > 0 exactly where none
    fits (dimensionless: the requirement over what the best-suited bearing offers, minus 1);
    required_C0_N: ``s0 x`` the peak radial force (N); min_bore_m: the pin's smallest diameter (m,
    0 when no pin material is given).
    """

    index: NDArray[np.intp]
    violation: NDArray[np.float64]
    required_C0_N: NDArray[np.float64]
    min_bore_m: NDArray[np.float64]


def select_bearings(
    peak_radial_N: ArrayLike,
    table: BearingTable | None = None,
    safety_factor: float = DEFAULT_SAFETY_FACTOR,
    pin_yield_pa: float | None = None,
    max_width_m: float | None = None,
    min_bore_m: ArrayLike = 0.0,
) -> BearingChoice:
    """Smallest bearing (by D, then B, then d) per joint whose static rating covers the load.

    ``peak_radial_N`` (..., J) peak radial force at each joint over the duty (N), any shape
    (designs x joints, say). A bearing fits when ``C0 >= safety_factor x F``, its bore is at least
    :func:`min_pin_diameter_m` (when ``pin_yield_pa`` is given, with the same safety factor) and
    its width is at most ``max_width_m`` (when given) and its bore at least ``min_bore_m`` (m,
    broadcast with the loads: a shaft sized for its torque, say). Where none fits, ``index`` is
    -1 and ``violation`` = the largest of ``s0 F / max C0 - 1`` and ``d_min / max d - 1`` over the
    usable bearings (> 0); elsewhere ``violation`` is the same expression, <= 0: continuous.
    """
    t = table if table is not None else load_catalogue()
    if not safety_factor > 0:
        raise ValueError("safety_factor must be positive")
    f = np.abs(np.asarray(peak_radial_N, dtype=float))
    if not np.isfinite(f).all():
        raise ValueError("peak radial forces must be finite")
    need = safety_factor * f
    d_min = np.maximum(
        min_pin_diameter_m(f, pin_yield_pa, safety_factor)
        if pin_yield_pa is not None
        else np.zeros_like(f),
        np.broadcast_to(np.asarray(min_bore_m, dtype=float), f.shape),
    )
    usable = np.ones(len(t), dtype=bool)
    if max_width_m is not None:
        usable &= t.B_m <= max_width_m * (1 + 1e-12)
    if not usable.any():
        raise ValueError(f"no bearing of the catalogue is at most {max_width_m} m wide")
    ok = (t.C0_N[usable] >= need[..., None]) & (t.d_m[usable] >= d_min[..., None] * (1 - 1e-12))
    rows = np.flatnonzero(usable)
    first = np.argmax(ok, axis=-1)
    index = np.where(ok.any(axis=-1), rows[first], -1).astype(np.intp)
    violation = np.maximum(need / t.C0_N[usable].max() - 1.0, d_min / t.d_m[usable].max() - 1.0)
    # where a bearing fits, the violation is <= 0 by construction; where none does, it is > 0
    # unless no single bearing meets both limits: then give the smallest shortfall of any bearing
    short = np.maximum(
        need[..., None] / t.C0_N[usable] - 1.0, d_min[..., None] / t.d_m[usable] - 1.0
    ).min(axis=-1)
    violation = np.where(index < 0, np.maximum(violation, short), violation)
    return BearingChoice(index, violation, need, d_min)


def boss_radius_m(
    index: ArrayLike,
    table: BearingTable | None = None,
    wall_m: float = DEFAULT_BOSS_WALL_M,
    minimum_m: float = 0.0,
) -> NDArray[np.float64]:
    """Boss radius (m) around each chosen bearing: ``max(minimum_m, D / 2 + wall_m)``.

    ``index`` as :attr:`BearingChoice.index`; where it is -1 (nothing fits) the largest bearing of
    the catalogue is used, so that the part can still be drawn (the design is infeasible anyway).
    """
    t = table if table is not None else load_catalogue()
    i = np.asarray(index, dtype=np.intp)
    i = np.where(i < 0, int(np.argmax(t.D_m)), i)
    return np.maximum(minimum_m, t.D_m[i] / 2 + wall_m)


def astuple_shallow(table: BearingTable) -> tuple:
    """The fields of ``table`` in order, not copied."""
    return tuple(getattr(table, f.name) for f in fields(table))

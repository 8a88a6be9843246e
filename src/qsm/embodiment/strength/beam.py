"""The beam model of a link for its strength check: the plate section and the cuts through the
link's spine (link frames, m), with the joint load each piece beyond a cut carries.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import as_design


@dataclass(frozen=True)
class Section:
    """The plate section: width_m (in the plane), thickness_m, boss_radius_m (m); floats, or
    arrays over the designs' leading axes (one section per design)."""

    width_m: float | NDArray[np.float64]
    thickness_m: float | NDArray[np.float64]
    boss_radius_m: float | NDArray[np.float64]

    @classmethod
    def of(cls, cad: CadSettings, scale: ArrayLike | None = None) -> Section:
        """The CAD section, every length times ``scale`` (per design) when given."""
        if scale is None:
            return cls(cad.width_m, cad.thickness_m, cad.boss_radius_m)
        f = np.asarray(scale, dtype=float)
        return cls(cad.width_m * f, cad.thickness_m * f, cad.boss_radius_m * f)

    def trailing(self, axes: int) -> Section:
        """This section with ``axes`` trailing axes added (to broadcast against per-sample,
        per-cut arrays)."""
        grow = (...,) + (None,) * axes
        return Section(
            *(np.asarray(v)[grow] for v in (self.width_m, self.thickness_m, self.boss_radius_m))
        )

    @property
    def overlap_m(self) -> float | NDArray[np.float64]:
        """Distance from a joint centre to the boss edge along a bar (m)."""
        r, h = np.asarray(self.boss_radius_m, float), np.asarray(self.width_m, float) / 2
        return np.sqrt(r * r - h * h)

    @property
    def weak_inertia_m4(self) -> float | NDArray[np.float64]:
        """Second moment of the bar section about its weaker axis (m^4). Products, not powers:
        each is correctly rounded, so a Python float and a NumPy array give the same bits
        (``**`` is libm's ``pow`` on a float and a vectorised ufunc on an array)."""
        w, t = np.asarray(self.width_m, float), np.asarray(self.thickness_m, float)
        return np.minimum(w * (t * t * t), t * (w * w * w)) / 12


def _pt(x: ArrayLike, y: ArrayLike = 0.0) -> NDArray[np.float64]:
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    return np.stack([x, y], axis=-1)


class Cuts(NamedTuple):
    """The cuts through one link's spine (C of them; leading axes of the designs).

    at (..., C, 2): link-frame point of each cut; tangent (C, 2): unit vector into the piece
    beyond; piece (..., C, 3, 2): that piece's spine polyline from the cut on (a repeated point
    is a segment of length 0); load (..., C, 2): where the piece's one joint load acts;
    slot (C,): which of the link's joint loads (:data:`LOADS`) that is; bore (C,): the cut passes
    through a bore (net section); column (C,): the cut feeds the buckling check; labels.
    """

    at: NDArray[np.float64]
    tangent: NDArray[np.float64]
    piece: NDArray[np.float64]
    load: NDArray[np.float64]
    slot: NDArray[np.intp]
    bore: NDArray[np.bool_]
    column: NDArray[np.bool_]
    labels: tuple[str, ...]


#: The joint loads on each link's pieces beyond its cuts: (force of :class:`JointLoads`, sign).
LOADS: dict[str, tuple[tuple[str, float], ...]] = {
    "lower_arm": (("b", -1.0),),
    "crank": (("c", -1.0),),
    "coupler": (("d", 1.0),),
    "upper_arm": (("d", -1.0), ("e", 1.0)),
}


def _cuts(rows: list[tuple], labels: list[str]) -> Cuts:
    """Stack cut rows (at, tangent, piece points, load point, slot, bore, column)."""
    at, tangent, piece, load, slot, bore, column = zip(*rows, strict=True)
    pieces = [np.stack([*p, *[p[-1]] * (3 - len(p))], axis=-2) for p in piece]
    return Cuts(
        np.stack(at, -2),
        np.array(tangent, dtype=float),
        np.stack(pieces, -3),
        np.stack(load, -2),
        np.array(slot),
        np.array(bore),
        np.array(column),
        tuple(labels),
    )


def _bar(length: NDArray[np.float64], sec: Section, bore_at_start: bool) -> Cuts:
    """Cuts of a bar from (0, 0) to (length, 0), loaded at its far joint."""
    x0, end, tx = sec.overlap_m, _pt(length), (1.0, 0.0)
    rows, labels = [], []
    if bore_at_start:
        rows.append((_pt(0 * length), tx, (_pt(0 * length), end), end, 0, True, False))
        labels.append("net section at the bore of the driven joint")
    for frac, label in ((0.0, "first boss edge"), (0.5, "mid-span"), (1.0, "second boss edge")):
        x = _pt(x0 + frac * (length - 2 * x0))
        rows.append((x, tx, (x, end), end, 0, False, True))
        labels.append(f"bar at the {label}")
    return _cuts(rows, labels)


def link_cuts(
    design: ArrayLike, sec: Section, links: tuple[str, ...] = tuple(LOADS)
) -> dict[str, Cuts]:
    """The cuts of each of ``links`` (all by default) of ``design`` (..., 6) m (see
    :mod:`qsm.embodiment.strength.stresses`)."""
    d = as_design(design)
    l1, l2, l3, l4, ex, ey = (d[..., i] for i in range(6))
    out = {}
    for link in links:
        if link == "upper_arm":
            out[link] = _upper_arm(l4, ex, ey, sec)
        else:
            length = {"lower_arm": l1, "crank": l2, "coupler": l3}[link]
            out[link] = _bar(length, sec, link != "coupler")
    return out


def _upper_arm(
    l4: NDArray[np.float64], ex: NDArray[np.float64], ey: NDArray[np.float64], sec: Section
) -> Cuts:
    """Cuts of the upper arm: D - B towards D, B - corner - E towards E."""
    x0, h, z = sec.overlap_m, sec.width_m / 2, 0 * l4
    dp, corner, e = _pt(-l4), _pt(ex), _pt(ex, -ey)
    left, right, down = (-1.0, 0.0), (1.0, 0.0), (0.0, -1.0)
    upper = [
        ((_pt(z), left, (_pt(z), dp), dp, 0, True, False), "net section at bore B, D side"),
        ((_pt(-x0 + z), left, (_pt(-x0 + z), dp), dp, 0, False, True), "bar at boss B, D side"),
        ((_pt(-l4 + x0), left, (_pt(-l4 + x0), dp), dp, 0, False, True), "bar at boss D"),
        ((_pt(z), right, (_pt(z), corner, e), e, 1, True, False), "net section at bore B, E side"),
        (
            (_pt(x0 + z), right, (_pt(x0 + z), corner, e), e, 1, False, False),
            "bar at boss B, E side",
        ),
        ((_pt(ex - h), right, (_pt(ex - h), corner, e), e, 1, False, False), "bar at the corner"),
        ((_pt(ex, -h + z), down, (_pt(ex, -h + z), e), e, 1, False, False), "bar below the corner"),
        ((_pt(ex, x0 - ey), down, (_pt(ex, x0 - ey), e), e, 1, False, False), "bar at boss E"),
    ]
    return _cuts([r for r, _ in upper], [label for _, label in upper])

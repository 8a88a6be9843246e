"""The kit's fits, named with their ISO 286 tolerance classes, and their limits of clearance.

A tolerance class's limit deviations (micrometres) follow from ISO 286-1's standard tolerance
grades and fundamental deviations (``data/iso286.csv``): shafts ``f``, ``g`` (``es`` from the
table, ``ei = es - IT``) and ``h`` (``es = 0``); holes ``H`` (``EI = 0``, ``ES = IT``), ``N``
and ``P`` (``ES = -ei(n or p) + IT7 - IT6`` up to IT7, ``EI = ES - IT``). A rolling bearing's
ring is held to ISO 492's Normal class (``data/iso492.csv``: upper 0). A fit's clearance runs
from the smallest hole less the largest shaft to the largest hole less the smallest shaft; a
negative clearance is an interference.

**The kit's fits** (:data:`KIT_FITS`): a joint bearing's outer ring pressed into its printed
bore, reamed to P7 (a plastic housing takes a tighter class than a metal one, so that the
ring stays held at the least interference); an ISO 7379 shoulder (f9) through the ring and
through the other plate's printed bore, reamed to H7; a hub's spigot (g6) in its link's bore
at A, reamed to H7; a hub's bore (H7) on a drive's shaft, taken as h6 (the catalogue gives no
class). **The press fit's check** (:func:`seat_stress_MPa`): the printed boss (outer diameter
``Do``) on a rigid steel ring of diameter d with the largest interference delta, by Lame's
thick cylinder in plane stress: ``p = delta E / (d (k + nu))``, ``k = (Do^2 + d^2) / (Do^2 -
d^2)``, and the hoop stress at the bore ``p k``, within the plate's allowable.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING, Any

from qsm.embodiment.kit.fasteners import table

if TYPE_CHECKING:
    from qsm.embodiment.strength.record import BearingLoad

#: The hole classes and shaft classes :func:`limits_um` knows.
HOLES = ("H7", "N7", "P7")
SHAFTS = ("f9", "g6", "h6", "h7")
#: ISO 492 Normal ring tolerances, by the name :func:`limits_um` takes.
RINGS = {"ISO 492 Normal bore": "inner", "ISO 492 Normal outside": "outer"}
#: (hole, shaft) of each kind of fit in the kit (module docs).
KIT_FITS = {
    "ring seat": ("P7", "ISO 492 Normal outside"),
    "shoulder in ring": ("ISO 492 Normal bore", "f9"),
    "shoulder in plate": ("H7", "f9"),
    "spigot": ("H7", "g6"),
    "shaft in hub": ("H7", "h6"),
}


@dataclass(frozen=True)
class Fit:
    """One fit: ``what`` it joins, its nominal diameter (mm), the hole's and the shaft's
    classes, and its least and largest clearance (micrometres, negative: interference)."""

    what: str
    d_mm: float
    hole: str
    shaft: str
    min_clearance_um: float
    max_clearance_um: float

    def record(self) -> dict[str, Any]:
        """The fit as ``kit.json`` gives it, with its kind."""
        return asdict(self) | {"kind": self.kind}

    @property
    def kind(self) -> str:
        """``clearance``, ``interference`` or ``transition``."""
        if self.min_clearance_um >= 0:
            return "clearance"
        return "interference" if self.max_clearance_um <= 0 else "transition"


def _row(name: str, d_mm: float, ring: str = "") -> dict[str, str]:
    for row in table(name):
        if (not ring or row["ring"] == ring) and float(row["over_mm"]) < d_mm <= float(
            row["to_mm"]
        ):
            return row
    raise ValueError(f"{name}: no size range holds {d_mm:g} mm")


def limits_um(cls: str, d_mm: float) -> tuple[float, float]:
    """The lower and upper limit deviations (micrometres) of tolerance class ``cls`` (one of
    :data:`HOLES`, :data:`SHAFTS` or :data:`RINGS`) at the nominal diameter ``d_mm``."""
    if cls in RINGS:
        return float(_row("iso492", d_mm, RINGS[cls])["lower_um"]), 0.0
    row = _row("iso286", d_mm)
    letter, grade = cls[0], int(cls[1:])
    it = float(row[f"it{grade}_um"])
    if letter == "H":
        return 0.0, it
    if letter in "NP":
        delta = 0.0 if d_mm <= 3 else float(row["it7_um"]) - float(row["it6_um"])
        upper = -float(row[f"{letter.lower()}_ei_um"]) + delta
        return upper - it, upper
    upper = 0.0 if letter == "h" else float(row[f"{letter}_es_um"])
    return upper - it, upper


def fit(what: str, d_mm: float, hole: str, shaft: str) -> Fit:
    """The fit of a ``shaft`` class in a ``hole`` class at ``d_mm`` (mm)."""
    (h0, h1), (s0, s1) = limits_um(hole, d_mm), limits_um(shaft, d_mm)
    return Fit(what, float(d_mm), hole, shaft, h0 - s1, h1 - s0)


def kit_fit(kind: str, what: str, d_mm: float) -> Fit:
    """The kit's fit of ``kind`` (a key of :data:`KIT_FITS`) at ``d_mm``, joining ``what``."""
    return fit(what, d_mm, *KIT_FITS[kind])


def seat_stress_MPa(seat: Fit, boss_d_mm: float, e_MPa: float, nu: float) -> float:
    """The hoop stress (MPa) at the bore of a printed boss ``boss_d_mm`` across, of modulus
    ``e_MPa`` and Poisson's ratio ``nu``, pressed onto a rigid ring with ``seat``'s largest
    interference (module docs); 0 where the fit has none."""
    delta = max(-seat.min_clearance_um, 0.0) * 1e-3
    d, do = seat.d_mm, boss_d_mm
    k = (do**2 + d**2) / (do**2 - d**2)
    return delta * e_MPa / (d * (k + nu)) * k


def joint_fits(
    joint: str, bearing: BearingLoad, seat: tuple[str, float, float], e_MPa: float, nu: float
) -> list[dict[str, Any]]:
    """Joint ``joint``'s fits (module docs): its ``bearing``'s (``d_mm``, ``D_mm``) outer ring
    in its printed ``seat`` (link, boss diameter mm, allowable MPa), with the seat's hoop
    stress and whether the ring stays held at the least interference, and its shoulder in
    the ring and in the other plate; none without a bearing."""
    if not bearing.D_mm:
        return []
    link, boss, allowable = seat
    where = f"bearing {joint}'s outer ring in the {link.replace('_', ' ')}'s bore"
    ring = kit_fit("ring seat", where, bearing.D_mm)
    stress = seat_stress_MPa(ring, boss, e_MPa, nu)
    held = ring.max_clearance_um < 0
    d = float(bearing.d_mm)
    return [
        ring.record()
        | {"joint": joint, "hoop_stress_MPa": stress, "allowable_MPa": allowable,
           "held": held, "holds": held and stress <= allowable},
        kit_fit("shoulder in ring", f"pin {joint}'s shoulder in bearing {joint}", d).record(),
        kit_fit("shoulder in plate", f"pin {joint}'s shoulder in its other plate", d).record(),
    ]  # fmt: skip


def hub_fits(motor: int, link: str, spigot_mm: float, shaft_mm: float) -> list[dict[str, Any]]:
    """Hub ``motor``'s fits: its spigot (``spigot_mm``) in the ``link``'s bore at A, and its
    bore on the drive's shaft (``shaft_mm``; none for a flange drive)."""
    where = f"hub {motor}'s spigot in the {link.replace('_', ' ')}'s bore at A"
    out = [kit_fit("spigot", where, spigot_mm)]
    if shaft_mm > 0:
        out.append(kit_fit("shaft in hub", f"drive {motor}'s shaft in hub {motor}", shaft_mm))
    return [f.record() for f in out]

"""The kit's ISO 286 fits: the classes built from ISO 286-1's grades and fundamental deviations
against ISO 286-2's tabulated limit deviations, and fits' clearances by hand."""

from __future__ import annotations

import numpy as np
import pytest

from qsm.embodiment.kit.fits import fit, kit_fit, limits_um, seat_stress_MPa

#: ISO 286-2:2010's tabulated limit deviations (lower, upper; micrometres), read from its
#: tables for holes H and N and shafts f, g, h, not from ISO 286-1's rules the module uses.
TABULATED = [
    ("H7", 5.0, (0, 12)),
    ("H7", 50.0, (0, 25)),
    ("N7", 2.0, (-14, -4)),
    ("N7", 22.0, (-28, -7)),
    ("N7", 62.0, (-39, -9)),
    ("P7", 35.0, (-42, -17)),
    ("P7", 100.0, (-59, -24)),
    ("f9", 12.0, (-59, -16)),
    ("f9", 6.0, (-40, -10)),
    ("g6", 30.0, (-20, -7)),
    ("g6", 40.0, (-25, -9)),
    ("h6", 100.0, (-22, 0)),
    ("h7", 8.0, (-15, 0)),
]


@pytest.mark.parametrize(("cls", "d", "expected"), TABULATED)
def test_tolerance_classes_agree_with_iso_286_2(cls, d, expected):
    assert limits_um(cls, d) == pytest.approx(expected)


def test_fits_by_hand_and_their_kind():
    """A 22 mm outer ring (ISO 492 Normal: 0 / -9) in an N7 bore (-7 / -28): from 28 um of
    interference to 2 um of clearance; a 12 mm f9 shoulder (-16 / -59) in a Normal inner ring
    (0 / -8): 8 to 59 um of clearance; an H7 / g6 at 30 mm: 7 to 41 um."""
    ring = fit("ring", 22.0, "N7", "ISO 492 Normal outside")
    assert (ring.min_clearance_um, ring.max_clearance_um) == (-28.0, 2.0)
    assert ring.kind == "transition"
    shoulder = fit("shoulder", 12.0, "ISO 492 Normal bore", "f9")
    assert (shoulder.min_clearance_um, shoulder.max_clearance_um) == (8.0, 59.0)
    assert shoulder.kind == "clearance"
    spigot = fit("spigot", 30.0, "H7", "g6")
    assert (spigot.min_clearance_um, spigot.max_clearance_um) == (7.0, 41.0)
    assert fit("press", 22.0, "N7", "h6").kind == "transition"


def test_a_size_beyond_the_tables_is_named():
    with pytest.raises(ValueError, match="200 mm"):
        limits_um("H7", 200.0)


def test_the_press_fit_s_hoop_stress_agrees_with_lame_s_displacements():
    """A 35 mm ring in a 50 mm printed boss (E 2200 MPa, nu 0.35), P7: 42 um of interference
    at most, 6 at least. Lame's plane-stress solution u(r) = A r + B / r, sigma_r(a) = -p,
    sigma_r(b) = 0, solved for the p that opens the bore by half the interference, gives the
    same hoop stress at the bore."""
    seat = kit_fit("ring seat", "bearing", 35.0)
    assert (seat.min_clearance_um, seat.max_clearance_um) == (-42.0, -6.0)
    e, nu, a, b = 2200.0, 0.35, 17.5, 25.0
    # sigma_r = E / (1 - nu^2) (A (1 + nu) - B (1 - nu) / r^2); sigma_t the same with + B
    c = e / (1 - nu**2)
    rows = np.array([[c * (1 + nu), -c * (1 - nu) / a**2], [c * (1 + nu), -c * (1 - nu) / b**2]])
    unit = np.linalg.solve(rows, np.array([-1.0, 0.0]))  # A, B per MPa of pressure
    u_per_p = unit[0] * a + unit[1] / a  # the bore's radial growth per MPa of pressure
    p = (0.042 / 2) / u_per_p
    hoop = p * c * (unit[0] * (1 + nu) + unit[1] * (1 - nu) / a**2)
    assert seat_stress_MPa(seat, 2 * b, e, nu) == pytest.approx(hoop, rel=1e-9)
    assert seat_stress_MPa(fit("loose", 35.0, "H7", "g6"), 2 * b, e, nu) == 0.0

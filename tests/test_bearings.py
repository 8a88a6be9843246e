"""Bearing catalogue and choice: hand-checked against the catalogue's rows."""

from __future__ import annotations

import math

import numpy as np
import pytest

from qsm.embodiment.parts import bearings


@pytest.fixture(scope="module")
def table() -> bearings.BearingTable:
    return bearings.load_catalogue()


def _name(table, i) -> str:
    return str(table.designation[i]) if i >= 0 else "-"


def test_catalogue_rows_cite_the_maker_and_are_consistent(table) -> None:
    assert len(table) >= 10
    assert all(m == "SKF" for m in table.maker)
    assert all("17000" in s for s in table.source)
    assert (table.D_m > table.d_m).all() and (table.C_N > table.C0_N).all()
    assert table.d_m.min() <= 0.005 and table.d_m.max() >= 0.030
    assert (np.diff(table.D_m) >= 0).all()  # sorted smallest first
    row = table.row(int(np.flatnonzero(table.designation == "6204")[0]))
    assert (row["d_m"], row["D_m"], row["B_m"]) == pytest.approx((0.020, 0.047, 0.014))
    assert (row["C_N"], row["C0_N"]) == pytest.approx((13500.0, 6550.0))


def test_smallest_bearing_whose_static_rating_covers_s0_times_the_load(table) -> None:
    # s0 = 2: 600 N needs C0 >= 1200 N: 625 (380 N) and 626 (950 N) fail, 608 (1370 N, D 22) holds.
    # 1000 N needs 2000 N: 608 and 6000 (1960 N) fail; 6001 (2360 N, D 28) beats 6200 (D 30).
    # 5000 N needs 10000 N: only 6206 (C0 11.2 kN). 6000 N needs 12000 N: none (violation
    # 12000 / 11200 - 1).
    loads = np.array([[600.0, 1000.0, 5000.0, 6000.0], [0.0, 950.0 / 2, 950.0 / 2 + 1e-6, 1.0]])
    choice = bearings.select_bearings(loads, table, safety_factor=2.0)
    names = [[_name(table, i) for i in row] for row in choice.index]
    assert names == [["608", "6001", "6206", "-"], ["625", "626", "608", "625"]]
    assert choice.violation.shape == loads.shape
    assert choice.violation[0, 3] == pytest.approx(12000.0 / 11200.0 - 1.0)
    assert (choice.violation[choice.index >= 0] <= 0).all()
    np.testing.assert_allclose(choice.required_C0_N, 2.0 * loads)
    # the default safety factor is 2 and the choice does not depend on the load's sign
    again = bearings.select_bearings(-loads, table)
    np.testing.assert_array_equal(again.index, choice.index)


def test_violation_is_continuous_at_the_largest_rating(table) -> None:
    c0_max = 11200.0
    f = np.array([c0_max / 2 * (1 - 1e-9), c0_max / 2 * (1 + 1e-9)])
    choice = bearings.select_bearings(f, table)
    assert choice.index[0] >= 0 and choice.index[1] == -1
    assert abs(choice.violation[1] - choice.violation[0]) < 1e-6


def test_width_limit_and_pin_bore(table) -> None:
    # width at most 10 mm: the largest C0 is 6003's 3.25 kN (17 x 35 x 10)
    choice = bearings.select_bearings([1600.0, 1700.0], table, max_width_m=0.010)
    assert [_name(table, i) for i in choice.index] == ["6003", "-"]
    # pin in single shear: at d_min the mean shear stress is the yield / sqrt(3) / s0
    f, fy, s0 = 1000.0, 235e6, 2.0
    d = bearings.min_pin_diameter_m(f, fy, s0)
    assert 4 * f / (math.pi * d**2) == pytest.approx(fy / math.sqrt(3) / s0)
    # a 200 N joint needs only C0 >= 400 N (626), but a weak pin (18 MPa) needs 7.0 mm: 6 mm
    # bore too small -> 608 (8 mm)
    light = bearings.select_bearings([200.0], table, pin_yield_pa=18e6)
    d_min = bearings.min_pin_diameter_m(200.0, 18e6, 2.0)
    assert 0.006 < d_min < 0.008
    assert _name(table, light.index[0]) == "608"


def test_boss_radius_is_the_seat_plus_the_wall(table) -> None:
    i608 = int(np.flatnonzero(table.designation == "608")[0])
    i6206 = int(np.flatnonzero(table.designation == "6206")[0])
    r = bearings.boss_radius_m([i608, i6206, -1], table, wall_m=0.004, minimum_m=0.0)
    np.testing.assert_allclose(r, [0.011 + 0.004, 0.031 + 0.004, 0.031 + 0.004])
    r = bearings.boss_radius_m([i608, i6206], table, wall_m=0.004, minimum_m=0.025)
    np.testing.assert_allclose(r, [0.025, 0.035])

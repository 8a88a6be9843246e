"""Build-volume check and the choice of the design to print."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from qsm.embodiment.parts import printing
from qsm.physics import cad
from qsm.physics.kinematics import DESIGN_COLUMNS
from qsm.realization.selection.choice import select_design

SMALL = [0.30, 0.10, 0.30, 0.15, 0.36, 0.12]  # upper arm 0.56 m: fits 600 x 350 x 350 mm
LARGE = [0.40, 0.12, 0.40, 0.20, 0.48, 0.16]  # upper arm 0.73 m: does not fit


def test_fits_build_volume() -> None:
    small = printing.fits_build_volume(SMALL)
    assert all(v["fits"] for v in small.values())
    ua = small["upper_arm"]["dims_mm"]
    assert ua[0] == pytest.approx(150 + 360 + 50, abs=0.05)  # 64-gon bosses and ua[2] == 20.0
    large = printing.fits_build_volume(LARGE)
    assert not large["upper_arm"]["fits"] and large["crank"]["fits"]
    # any axis-aligned orientation: the 730 x 210 x 20 mm upper arm fits 20 x 800 x 250 mm
    assert printing.all_links_fit(LARGE, volume_mm=(20.0, 800.0, 250.0))
    assert not printing.all_links_fit(LARGE, volume_mm=(19.0, 800.0, 250.0))
    assert not printing.all_links_fit([0.1, 0.02, 0.1, 0.04, 0.12, 0.05])  # invalid CAD


def table() -> pd.DataFrame:
    rows = [  # design, eta, tau1, tau2, feasible, status
        (SMALL, 0.30, 50.0, 20.0, True, "ok"),
        (np.multiply(SMALL, 1.05).tolist(), 0.20, 60.0, 12.0, True, "ok"),
        (np.multiply(SMALL, 0.95).tolist(), 0.40, 40.0, 22.0, True, "ok"),
        (LARGE, 0.10, 10.0, 5.0, True, "ok"),  # best everywhere but too large to print
        (SMALL, 0.05, 5.0, 5.0, False, "ok"),  # infeasible
        (SMALL, 0.05, 5.0, 5.0, True, "singular"),  # dynamics failed
    ]
    recs = []
    for d, eta, t1, t2, feas, st in rows:
        rec = dict(zip(DESIGN_COLUMNS, d, strict=True))
        rec.update(
            eta_true=eta, tau1_true_Nm=t1, tau2_true_Nm=t2, feasible=feas, dynamics_status=st
        )
        recs.append(rec)
    return pd.DataFrame(recs, index=[10, 11, 12, 13, 14, 15])


@pytest.mark.parametrize(
    ("rule", "expected"),
    [("min_tau1", 12), ("min_tau2", 11), ("min_torque_sum", 12), ("min_eta", 11), ("knee", 11)],
)
def test_select_design_rules(rule: str, expected: int) -> None:
    row = select_design(table(), rule)
    assert row.name == expected
    assert row["selection_rule"] == rule and row["n_candidates"] == 3


def test_select_design_raises_when_nothing_fits() -> None:
    df = table()
    with pytest.raises(ValueError, match="build volume"):
        select_design(df, "knee", cad.CadSettings(), volume_mm=(300.0, 300.0, 300.0))
    with pytest.raises(ValueError, match="unknown selection rule"):
        select_design(df, "max_beauty")

"""Bill of materials: printed parts, bearings and pins per joint, empty drive rows, Markdown."""

from __future__ import annotations

import re

import numpy as np
import pandas as pd
import pytest

from qsm.embodiment.parts import bearings, bom, part_mass
from qsm.embodiment.parts import link_parts as parts

DESIGN = np.array([0.5, 0.15, 0.55, 0.22, 0.6, 0.2])


def _index(name: str) -> int:
    table = bearings.load_catalogue()
    return int(np.flatnonzero(table.designation == name)[0])


def test_bom_rows_and_files(tmp_path) -> None:
    idx = [_index(n) for n in ("6000", "608", "6204", "6206")]
    built = parts.link_parts(DESIGN, idx)
    masses = part_mass.part_mass_properties(built)
    frame = bom.bill_of_materials(
        built, masses, idx, topology_optimized={"lower_arm": True}, material="ABS | M30"
    )
    assert list(frame.columns) == list(bom.BOM_COLUMNS)
    printed = frame[frame.category == "printed part"].set_index("item")
    assert list(printed.index) == ["lower_arm", "crank", "coupler", "upper_arm"]
    assert printed.loc["lower_arm", "topology_optimised"]
    assert not printed.loc["crank", "topology_optimised"]
    assert printed.loc["coupler", "mass_kg"] == pytest.approx(masses["coupler"].mass_kg)
    # coupler box by hand: 550 + 27.5 (6204 boss) + 35 (6206 boss) by 2 x 35, 20 thick
    assert printed.loc["coupler", ["bbox_x_mm", "bbox_y_mm", "bbox_z_mm"]].tolist() == (
        pytest.approx([612.5, 70.0, 20.0], abs=0.05)
    )
    b = frame[frame.category == "bearing"].set_index("item")
    assert b.loc["bearing A", "quantity"] == 2 and b.loc["bearing A", "designation"] == "SKF 6000"
    assert b.loc["bearing D", "D_mm"] == pytest.approx(62.0)
    assert b.loc["bearing D", "C0_kN"] == pytest.approx(11.2)
    pins = frame[frame.category == "pin"].set_index("where")
    assert list(pins.index) == ["B", "C", "D"] and pins.loc["C", "d_mm"] == pytest.approx(20.0)
    drives = frame[frame.category.isin(["motor", "gearbox"])]
    assert len(drives) == 4 and drives.designation.isna().all()
    csv, md = bom.write_bom(frame, tmp_path)
    back = pd.read_csv(csv)
    assert len(back) == len(frame) == 4 + 4 + 3 + 4
    masses = frame["mass_kg"].dropna().to_numpy(dtype=float)
    np.testing.assert_allclose(back["mass_kg"].dropna(), masses, rtol=1e-9)  # 10 digits kept
    assert not re.search(r"\d{11,}", csv.read_text())  # no float's last bits
    text = md.read_text()
    assert "ABS \\| M30" in text and "ABS | M30" not in text
    header = text.splitlines()[0]
    assert header.count("|") == len(bom.SUMMARY_COLUMNS) + 1
    for line in text.splitlines():  # every row has as many unescaped separators
        assert line.replace("\\|", "").count("|") == header.count("|")


def test_missing_bearing_and_drive_values() -> None:
    idx = [_index("6000"), _index("608"), _index("608"), -1]
    built = parts.link_parts(DESIGN, idx)
    frame = bom.bill_of_materials(
        built,
        part_mass.part_mass_properties(built),
        idx,
        drives={"motor 1": {"designation": "T-motor AK80-64", "mass_kg": 0.85}},
    )
    d = frame.set_index("item")
    assert "no bearing" in d.loc["bearing D", "notes"] and "pin D" not in d.index
    assert d.loc["motor 1", "designation"] == "T-motor AK80-64"
    assert pd.isna(d.loc["motor 2", "designation"])


def test_a_motor_without_a_drive_is_built_with_its_nearest_drive_marked():
    from qsm.embodiment.drives.report import (
        CatalogueDrive,
        DriveReport,
        DriveRequirement,
        MotorReport,
    )
    from qsm.realization.selection.assembly import drive_rows

    nearest = CatalogueDrive("M", "G", "m", "g", 50.0, 1.2, 0.0, 1.0, 1e4, "", "")
    need = DriveRequirement(1.0, 1.0, 1.0, 1.0)
    motor = MotorReport(False, 0.5, need, nearest, {}, failing={"motor_rms": 0.5})
    rows = drive_rows(DriveReport(True, "lightest", {"motor1": motor}))
    assert rows["motor 1"]["designation"] == "M" and rows["motor 1"]["mass_kg"] == 1.2
    assert rows["motor 1"]["notes"].startswith("NONE of the catalogue meets its duty")
    assert rows["gearbox 1"]["designation"] == "G"

"""Numbers in sentences (qsm.prose): rounded, with their units, never a Python list."""

import math

import numpy as np
import pytest
from prose_checks import raw_values, significant_digits

from qsm.prose import fixed, listed, per_motor, point
from qsm.report import accuracy_report


def test_numbers_read_as_words_not_lists():
    assert per_motor(np.array([54.26, 17.249]), 1, "N m") == "motor 1 54.3 N m, motor 2 17.2 N m"
    assert per_motor([1.05, None], 2, "") == "motor 1 1.05, motor 2 -"
    assert point(np.array([-0.53, 0.17])) == "(-0.530, 0.170) m"
    assert listed([297.0, 112.04, 350.0], 1, "mm") == "297.0, 112.0 and 350.0 mm"
    assert listed([4.0], 0, "kg") == "4 kg"
    for text in (
        per_motor([0.6000000000000001], 2, ""),
        listed(np.array([43.78225891802785]), 2, ""),
    ):
        assert "[" not in text and "000000" not in text


@pytest.mark.parametrize(
    ("value", "digits", "text"),
    [
        (167.604, 2, "167.6"),  # 4 significant digits, not 167.60
        (7.924, 2, "7.92"),  # the decimals asked for
        (28.3344, 3, "28.33"),
        (2898.41, 2, "2898"),
        (24700.0, 1, "24700"),  # the whole part is never cut
        (9.9996, 3, "10.00"),  # rounding up gains a digit: one decimal fewer
        (-154.93, 2, "-154.9"),
        (0.0, 2, "0.00"),
    ],
)
def test_fixed_keeps_at_most_four_significant_digits(value, digits, text):
    assert fixed(value, digits) == text
    assert significant_digits(text) <= 4 or "." not in text
    assert math.isclose(float(text), value, rel_tol=5e-4, abs_tol=0.5 * 10.0**-digits)


def test_the_scan_finds_what_a_program_writes(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "the error reaches 167.60 mm\n"  # 5 significant digits
        "peak [669.5, 56.2] N m\n"
        "| 154.93 | a table keeps its columns' decimals |\n"
        "drive `CSF-32-100-2UH`, Python 3.11.7 on 2026-11-28, 1,600.25 of them, 0.987\n"
        "±11.7936 N m and nan\n"
    )
    found = raw_values(page)
    assert [hit.split(":")[1] for hit in found] == ["1", "2", "5"]


def test_the_gearboxes_built_for_the_tolerance_read_per_motor():
    """0 N m/rad is "any gearbox", a stiffness is written with its thousands."""
    built = {
        "target_mm": 1.4,
        "structure_share": 0.7,
        "structure_mm": 11.77,
        "meets_target": False,
        "section_scale": {"lower_arm": 2.0, "upper_arm": 1.5},
        "min_gearbox_stiffness_Nm_rad": [0.0, 24700.0],
    }
    (line,) = accuracy_report._built_for(built)
    assert "(motor 1: any gearbox, motor 2: a gearbox of at least 24,700 N m/rad)" in line
    assert "comes nearest at 11.77 mm with sections lower arm 2.00x, upper arm 1.50x" in line

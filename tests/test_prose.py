"""Numbers in sentences (qsm.prose): rounded, with their units, never a Python list."""

import numpy as np

from qsm.prose import listed, per_motor, point


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

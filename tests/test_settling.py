"""The settling check (qsm.realization.final.settling) against closed forms: a damped
oscillator's step response, its free decay staying within the bound after the settling time,
and the tool's first mode on light links, the payload ringing on the tool's compliance along its
principal direction."""

import math

import numpy as np
import pytest

from qsm.embodiment.stiffness.frame import FrameSections, tool_compliance
from qsm.embodiment.stiffness.modes import loaded_first_mode_hz, tool_mode
from qsm.realization.final.settling import ToolMode, amplitude_m, response, settling_s

MODE = ToolMode(frequency_hz=6.0, direction=(0.0, 1.0), compliance_m_N=2e-5)
ZETA = 0.03


def test_a_held_force_gives_the_step_response():
    """x(t) = c F (1 - e^(-z w t) (cos wd t + z / sqrt(1 - z^2) sin wd t)) under a force F
    held from t = 0 (exact stepping: to rounding)."""
    dt, force = 1e-3, 40.0
    x, _ = response(np.full(800, force), MODE, ZETA, dt)
    t = np.arange(800) * dt
    w = MODE.omega
    wd = w * math.sqrt(1 - ZETA**2)
    decay = np.exp(-ZETA * w * t) * (
        np.cos(wd * t) + ZETA / math.sqrt(1 - ZETA**2) * np.sin(wd * t)
    )
    np.testing.assert_allclose(x, MODE.compliance_m_N * force * (1 - decay), atol=1e-12)


def test_a_free_decay_stays_within_the_bound_after_its_settling_time():
    """From x0, v0: the exact decay x(t) never passes ``allowed`` after the settling time, and
    its envelope is past it just before."""
    x0, v0, allowed = 1.2e-3, -0.05, 2e-4
    amp = amplitude_m(x0, v0, MODE, ZETA)
    settle = settling_s(amp, MODE, ZETA, allowed)
    w = MODE.omega
    wd = w * math.sqrt(1 - ZETA**2)
    t = np.linspace(0.0, 3 * settle, 200_001)
    x = np.exp(-ZETA * w * t) * (x0 * np.cos(wd * t) + (v0 + ZETA * w * x0) / wd * np.sin(wd * t))
    assert 0.9 * amp < np.abs(x).max() <= amp * (1 + 1e-9)  # the envelope bounds the decay
    assert np.abs(x[t >= settle]).max() <= allowed
    assert amp * math.exp(-ZETA * w * 0.95 * settle) > allowed
    assert settling_s(amp, MODE, ZETA, amp * 1.01) == 0.0
    assert settling_s(amp, MODE, ZETA, 0.0) is None


def test_on_light_links_the_tool_rings_along_its_most_compliant_direction():
    """Links of negligible mass: the payload m rings at 1 / (2 pi sqrt(m lambda_max(C))) along
    the tool compliance C's principal direction (the frame's own eigenproblem, independently)."""
    design = np.array([0.55, 0.22, 0.5, 0.16, 0.42, 0.12])
    sections = FrameSections(np.array([0.04, 0.03, 0.025, 0.045]),
                             np.array([0.02, 0.018, 0.015, 0.022]), 2.2e9, 0.35)  # fmt: skip
    drives = np.array([3.0e3, 1.5e3])
    t1, t2 = np.radians([100.0, 190.0])
    f, u = tool_mode(design, t1, t2, sections, np.full(4, 1e-7), 4.0, drives, [0, 0])
    c = tool_compliance(design, t1, t2, sections, drives)
    values, vectors = np.linalg.eigh(c)
    assert f == pytest.approx(1 / (2 * np.pi * np.sqrt(4.0 * values[-1])), rel=3e-3)
    assert abs(u @ vectors[:, -1]) == pytest.approx(1.0, abs=1e-4)
    loaded = loaded_first_mode_hz(design, t1, t2, sections, np.full(4, 0.4), 4.0, drives, [1, 1])
    assert tool_mode(design, t1, t2, sections, np.full(4, 0.4), 4.0, drives, [1, 1])[0] == (
        pytest.approx(float(loaded), rel=1e-9)
    )

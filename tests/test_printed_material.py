"""The printed material as it behaves (qsm.embodiment.strength.printed): the links' weight on the
frame against reciprocity with the beams' own displacement fields, the creep's drift against
its closed form, Findley's law, and the kit's across-layer allowable."""

import dataclasses

import numpy as np
import pytest

from qsm.embodiment.kit import joints as jt
from qsm.embodiment.stiffness.frame import (
    BEAMS,
    DOFS,
    TOOL,
    FrameSections,
    at_dofs,
    beam_ends,
    nodes,
    stiffness_matrix,
    tool_compliance,
    tool_displacement,
    weight_loads,
)
from qsm.embodiment.strength.loads import Inertials
from qsm.embodiment.strength.printed import PrintedMaterial
from qsm.embodiment.strength.record import BearingLoad
from qsm.realization.accuracy.accuracy_budget import ArmModel, creep_drift_m

DESIGN = np.array([0.55, 0.22, 0.5, 0.16, 0.42, 0.12])  # m
POSES = np.radians([[60.0, 150.0], [100.0, 190.0], [140.0, 230.0]])
MASSES = np.array([0.9, 0.3, 0.6, 1.2])  # kg per link
G = 9.80665
# slender sections: shear adds under 1e-4 to the bending, so Hermite's cubics are the beams'
# own displacement fields
SLENDER = FrameSections(np.full(4, 0.004), np.full(4, 0.02), 2.2e9, 0.35)


def _field_work(design, t1, t2, field, masses):
    """The links' weight's work on a displacement ``field`` (20,) of the frame's degrees of
    freedom, each beam's displacement between its ends by Hermite's cubics (transverse) and a
    linear axial part, integrated by Gauss-Legendre."""
    at = nodes(design, t1, t2)
    lengths = [np.linalg.norm(np.subtract(*beam_ends(at, a, b)[::-1])) for _, a, b in BEAMS]
    per_link = np.zeros(4)
    for (link, _, _), length in zip(BEAMS, lengths, strict=True):
        per_link[link] += length
    xi, w = np.polynomial.legendre.leggauss(6)
    s = (xi + 1) / 2
    work = 0.0
    for (link, first, second), length in zip(BEAMS, lengths, strict=True):
        start, end = beam_ends(at, first, second)
        c, si = (end - start) / length
        rows, keep = at_dofs(first, second)
        ends = np.zeros(6)
        ends[keep] = field[rows]
        axial = [c * ends[0] + si * ends[1], c * ends[3] + si * ends[4]]
        across = [-si * ends[0] + c * ends[1], -si * ends[3] + c * ends[4]]
        h = [1 - 3 * s**2 + 2 * s**3, s - 2 * s**2 + s**3, 3 * s**2 - 2 * s**3, -(s**2) + s**3]
        v = h[0] * across[0] + h[1] * length * ends[2] + h[2] * across[1] + h[3] * length * ends[5]
        u = (1 - s) * axial[0] + s * axial[1]
        y = u * si + v * c  # the displacement along global y
        q = -G * masses[link] / per_link[link]  # N/m along y
        work += q * length / 2 * float(w @ y)
    return work


@pytest.mark.parametrize("pose", range(len(POSES)))
def test_the_weights_move_the_tool_as_their_work_on_its_unit_load_field(pose):
    """Reciprocity: the tool's vertical displacement under the links' weight is the weight's
    work on the frame's displacement field under a unit vertical force at the tool."""
    t1, t2 = POSES[pose]
    drives = np.array([3.0e3, 1.5e3])
    unit = np.zeros(len(DOFS))
    unit[TOOL[1]] = 1.0
    loads = weight_loads(DESIGN, t1, t2, MASSES, G)
    moved = tool_displacement(DESIGN, t1, t2, SLENDER, loads, drives)
    field = np.linalg.solve(stiffness_matrix(DESIGN, t1, t2, SLENDER, drives), unit)
    assert moved[1] == pytest.approx(_field_work(DESIGN, t1, t2, field, MASSES), rel=1e-6)
    assert moved[1] < 0  # the weight lowers the tool


def test_a_floating_links_loads_add_up_to_its_weight():
    """The coupler and the upper arm touch A nowhere: their nodal forces add up to their weight
    (the lower arm and the crank leave their share at A, which the base holds)."""
    t1, t2 = POSES[0]
    for link in (2, 3):
        only = np.zeros(4)
        only[link] = MASSES[link]
        f = weight_loads(DESIGN, t1, t2, only, G)
        assert sum(f[i] for i, n in enumerate(DOFS) if n.startswith("y")) == pytest.approx(
            -G * MASSES[link]
        )
        assert sum(f[i] for i, n in enumerate(DOFS) if n.startswith("x")) == 0.0


def _model(drives, printed):
    return ArmModel(
        design=DESIGN, sections=SLENDER._replace(width_m=np.full(4, 0.03)), factor=np.ones(4),
        inertials=Inertials(MASSES, np.zeros((4, 2)), np.full(4, 1e-3)),
        drive_stiffness=drives, backlash_rad=np.zeros(2), reflected_kgm2=np.zeros(2),
        drive_mass_kg=np.zeros(2), printed=printed,
    )  # fmt: skip


def test_the_creep_of_stiff_drives_is_phi_times_the_links_elastic_deflection():
    """Rigid drives: the frame's compliance is the links' alone, proportional to 1 / E, so the
    drift after creep is phi times the elastic deflection under the held loads (the links'
    weight and the payload's share); a stiff material's drift is phi times less."""
    printed = PrintedMaterial(service_time_h=8760.0, payload_share=0.5)
    phi = printed.creep_coefficient
    model = _model(np.full(2, np.inf), printed)
    t1, t2 = POSES[:, 0], POSES[:, 1]
    drift = creep_drift_m(model, t1, t2, 4.0)
    held = weight_loads(DESIGN, t1, t2, MASSES, G)
    sections = model.sections
    elastic = tool_displacement(DESIGN, t1, t2, sections, held)
    elastic = elastic + np.einsum("pij,j->pi", tool_compliance(DESIGN, t1, t2, sections),
                                  [0.0, -0.5 * 4.0 * G])  # fmt: skip
    np.testing.assert_allclose(drift, phi * elastic, rtol=1e-9, atol=1e-12)


def test_gearboxes_do_not_creep_and_no_service_time_is_no_drift():
    t1, t2 = POSES[:, 0], POSES[:, 1]
    printed = PrintedMaterial()
    rigid = np.linalg.norm(creep_drift_m(_model(np.full(2, np.inf), printed), t1, t2, 4.0), axis=-1)
    soft = np.linalg.norm(creep_drift_m(_model(np.full(2, 2e3), printed), t1, t2, 4.0), axis=-1)
    assert (soft > 0).all()
    # the springs at A carry the same moments and turn the links the same in both states
    np.testing.assert_allclose(soft, rigid, rtol=0.05)
    fresh = dataclasses.replace(printed, service_time_h=0.0)
    assert not creep_drift_m(_model(np.full(2, 2e3), fresh), t1, t2, 4.0).any()
    assert not creep_drift_m(_model(np.full(2, 2e3), None), t1, t2, 4.0).any()


def test_findleys_law():
    p = PrintedMaterial(creep_coefficient_1000h=0.3, creep_exponent=0.25)
    assert dataclasses.replace(p, service_time_h=1000.0).creep_coefficient == pytest.approx(0.3)
    year = dataclasses.replace(p, service_time_h=8760.0).creep_coefficient
    assert year == pytest.approx(0.3 * 8.76**0.25)
    assert p.record()["creep_modulus_factor"] == pytest.approx(1 / (1 + p.creep_coefficient))
    with pytest.raises(ValueError, match="across_layers"):
        PrintedMaterial(across_layers_strength_factor=1.5)


def test_a_pins_printed_bearing_length_grows_as_the_layers_allow_less():
    """F / (sigma d): the printed length that carries a pin's force, across the layers."""
    bearing = BearingLoad("", 900.0, (0.0, 0.0), d_mm=8.0, B_mm=7.0)
    seat = jt.Plate("upper_arm", 20.0, 15.5, 20.0)
    plain = jt.pin("B", bearing, seat, jt.Plate("lower_arm", 20.0, 15.5, 20.0), 2.0)
    across = jt.pin("B", bearing, seat, jt.Plate("lower_arm", 20.0, 15.5, 20.0, 15.5 * 0.84), 2.0)
    assert plain["printed_bearing_length_mm"] == pytest.approx(900.0 / (15.5 * 8.0))
    assert across["printed_bearing_length_mm"] == pytest.approx(900.0 / (15.5 * 0.84 * 8.0))
    assert across["bending_arm_mm"] > plain["bending_arm_mm"]

"""Stage 2's strength columns of a chunk of designs (:data:`qsm.dataset.columns.STRENGTH_COLUMNS`):
each link's peak stress, safety and buckling factors, each joint's bearing and peak force, the
weakest link and where it fails, and the sections, from :class:`StrengthCore`, what
:meth:`qsm.embodiment.strength.link_checks.StrengthCheck.core` gives."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from qsm.embodiment.parts.bearings import BearingChoice, BearingTable
from qsm.embodiment.strength.loads import JointLoads
from qsm.embodiment.strength.sizing import SizedSections
from qsm.embodiment.strength.strength_columns import JOINT_COLUMNS
from qsm.embodiment.strength.stresses import JOINTS, LinkStrength
from qsm.physics.cad import CadSettings
from qsm.physics.kinematics import LINK_NAMES


class StrengthCore(NamedTuple):
    """What the full table and g13 share for a chunk of designs: the sized sections (None with
    the fixed section) and each link's need for its bearing seats, the joint loads, where the
    check is undefined, each link's peaks and its stress and buckling utilisations, the bearing
    choice (its rows in ``table``) and utilisation, each link's utilisation and the largest."""

    sized: SizedSections | None
    seat: NDArray[np.float64]
    loads: JointLoads
    bad: NDArray[np.bool_]
    per_link: dict[str, LinkStrength]
    stress_u: dict[str, NDArray[np.float64]]
    buckle_u: dict[str, NDArray[np.float64]]
    choice: BearingChoice
    row: NDArray[np.intp]
    table: BearingTable
    bearing_util: NDArray[np.float64]
    link_util: NDArray[np.float64]
    util: NDArray[np.float64]


def strength_columns(
    core: StrengthCore, cad: CadSettings, yield_pa: float, theta_deg: NDArray[np.float64]
) -> dict[str, NDArray]:
    """The :data:`~qsm.dataset.columns.STRENGTH_COLUMNS` of a chunk of designs from their
    ``core``, the CAD section, the yield strength (Pa) and the duty's angles (samples, 2) deg,
    with the motor torques (``_tau``) and where they are defined (``_good``)."""
    choice, row, table, bad, seat = core.choice, core.row, core.table, core.bad, core.seat
    forces, bearing_util = core.loads._asdict(), core.bearing_util
    out: dict[str, NDArray] = {}
    for k, (link, res) in enumerate(core.per_link.items()):
        with np.errstate(divide="ignore"):
            out[f"buckling_factor_{link}"] = res.euler_N / res.compression_N
        out[f"stress_peak_{link}_MPa"] = res.stress_pa / 1e6
        out[f"safety_factor_{link}"] = yield_pa / res.stress_pa
        stress_u, buckle_u = core.stress_u[link], core.buckle_u[link]
        labels = np.array([*res.labels, "buckling"], dtype=object)
        check = np.where(buckle_u > stress_u, labels[-1], labels[res.where])
        seated = ~(seat[:, k] > 1.0)  # the seat's sliver of boss is what fails
        out[f"_check_{link}"] = np.where(seated, check, "bearing seat")
    for k, joint in enumerate(JOINTS):
        out[f"bearing_{joint}"] = np.where(
            choice.index[..., k] < 0, "", table.designation[row[..., k]]
        ).astype(object)
    out["bearing_violation"] = choice.violation.max(-1)
    out["bearing_utilisation"] = bearing_util.max(-1)
    out["strength_utilisation"] = core.util
    # the chosen bearing sits near its rating by design: name it only when it fails
    weakest = np.concatenate(
        [core.link_util, np.where(bearing_util > 1.0, bearing_util, 0.0)], axis=-1
    ).argmax(-1)
    names = [*LINK_NAMES, *(f"bearing {j}" for j in JOINTS)]
    out["weakest_link"] = np.asarray(names, dtype=object)[weakest]
    checks = np.stack(
        [out.pop(f"_check_{k}") for k in LINK_NAMES]
        + [np.full(len(bad), "static load rating", dtype=object)] * len(JOINTS),
        -1,
    )
    out["weakest_check"] = np.take_along_axis(checks, weakest[:, None], -1)[:, 0]
    theta = theta_deg
    for suffix, name in JOINT_COLUMNS.items():
        x, y = forces[name][..., 0], forces[name][..., 1]
        square = np.nan_to_num(x * x + y * y, nan=-1.0)  # the magnitude's order, cheaply
        k = square.argmax(-1)
        peak = np.take_along_axis(square, k[:, None], -1)[:, 0]
        out[f"joint_force_peak_{suffix}_N"] = np.where(peak < 0, -1.0, np.sqrt(np.abs(peak)))
        out[f"joint_force_peak_{suffix}_theta1_deg"] = theta[k, 0]
        out[f"joint_force_peak_{suffix}_theta2_deg"] = theta[k, 1]
    for col in out.values():
        col[bad] = np.nan if col.dtype.kind == "f" else ""
    out["holds_loads"] = out["strength_utilisation"] <= 1.0
    factor = np.ones((len(bad), 4)) if core.sized is None else core.sized.scale
    for i, link in enumerate(LINK_NAMES):
        out[f"section_width_{link}_mm"] = 1e3 * cad.width_m * factor[:, i]
        out[f"section_thickness_{link}_mm"] = 1e3 * cad.thickness_m * factor[:, i]
    out["section_iterations"] = (
        np.zeros(len(bad), dtype=np.intp) if core.sized is None else core.sized.iterations
    )
    out["_tau"], out["_good"] = core.loads.tau, ~bad
    return out

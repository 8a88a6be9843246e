"""Peak motor torques of a design with the CAD links or with replaced link mass properties (the
printed, topology-optimised links; paper Table 3). MuJoCo only: no finite elements."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from qsm.physics.cad import CadSettings, MassProperties, mass_properties
from qsm.physics.duty import Duty
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.kinematics import as_design
from qsm.physics.mjcf import model_spec


def peak_torques(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    props: dict[str, MassProperties] | None = None,
    scale: ArrayLike | None = None,
) -> dict[str, float]:
    """Peak |tau1|, |tau2| (N m) over ``duty`` of the model built with ``props`` (default: the
    CAD links, each of ``cad``'s section scaled by its entry of ``scale`` (4,))."""
    d = as_design(design)
    if props is None:
        props = mass_properties(d, cad, scale)
    model = model_spec(d, cad, payload_kg, props).compile()
    state = loop_state(d, duty.theta, duty.dtheta, duty.ddtheta)
    tau = inverse_dynamics(model, d, state).tau
    return {
        "tau1_Nm": float(np.nanmax(np.abs(tau[:, 0]))),
        "tau2_Nm": float(np.nanmax(np.abs(tau[:, 1]))),
    }


def torques_before_after(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    new_props: dict[str, MassProperties],
    scale: ArrayLike | None = None,
) -> dict[str, dict[str, float]]:
    """Peak motor torques (N m) over ``duty`` with the CAD links of the sections ``scale``
    (:func:`peak_torques`; "before") and with ``new_props`` ("after"), each from a freshly built
    MJCF model; plus the relative change in percent."""
    before = peak_torques(design, cad, payload_kg, duty, scale=scale)
    after = peak_torques(design, cad, payload_kg, duty, new_props)
    change = {f"{k[:-3]}_change_pct": 100.0 * (after[k] - before[k]) / before[k] for k in before}
    return {"before": before, "after": after, "change": change}

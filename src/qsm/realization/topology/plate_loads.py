"""Peak loads on the link plates over the duty (from the closed-chain dynamics) and the
finite-element problem of each plate."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import (
    CadSettings,
    MassProperties,
    link_outlines,
    link_settings,
    mass_properties,
)
from qsm.physics.duty import Duty
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.kinematics import as_design, perp
from qsm.physics.mjcf import GRAVITY_M_S2, model_spec
from qsm.realization.topology.fe import (
    DEFAULT_TOPOLOGY,
    FeProblem,
    TopologySettings,
    clamped_dofs,
    grid_for_box,
    nodal_forces,
)


@dataclass(frozen=True)
class LinkLoads:
    """Link-frame joint loads of one load case: ``clamp`` (joint name), and ``forces`` mapping a
    joint name to a force (N, link frame); ``label`` names the duty sample."""

    label: str
    clamp: str
    forces: dict[str, NDArray[np.float64]]


def _rot(angle: float) -> NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def joint_points(design: ArrayLike) -> dict[str, dict[str, NDArray[np.float64]]]:
    """Joint positions (m) in the link frames of the two optimised links."""
    l1, _l2, _l3, l4, ee_x, ee_y = (float(v) for v in as_design(design))
    return {
        "lower_arm": {"A": np.zeros(2), "B": np.array([l1, 0.0])},
        "upper_arm": {
            "B": np.zeros(2),
            "D": np.array([-l4, 0.0]),
            "E": np.array([ee_x, -ee_y]),
        },
    }


def peak_loads(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    props: dict[str, MassProperties] | None = None,
) -> dict[str, list[LinkLoads]]:
    """Joint loads of the lower and upper arm (link frames) at the duty samples of peak |tau1| and
    peak |tau2|, from the closed-chain inverse dynamics (see the module docstring)."""
    d = as_design(design)
    l1 = float(d[0])
    props = mass_properties(d, cad) if props is None else props
    model = model_spec(d, cad, payload_kg, props).compile()
    state = loop_state(d, duty.theta, duty.dtheta, duty.ddtheta)
    if not state.closes.all():
        raise ValueError("the loop does not close over the whole duty")
    inv = inverse_dynamics(model, d, state)
    gvec = np.array([0.0, -GRAVITY_M_S2])
    pts = joint_points(d)
    m_u, com_u = props["upper_arm"].mass_kg, props["upper_arm"].com_m[:2]
    out: dict[str, list[LinkLoads]] = {"lower_arm": [], "upper_arm": []}
    peaks = {
        "peak_tau1": int(np.nanargmax(np.abs(inv.tau[:, 0]))),
        "peak_tau2": int(np.nanargmax(np.abs(inv.tau[:, 1]))),
    }
    for label, k in peaks.items():
        t1, dt1, ddt1 = duty.theta[k, 0], duty.dtheta[k, 0], duty.ddtheta[k, 0]
        phi = t1 + state.q[k, 1]
        phi_d = state.qd[k, 0] + state.qd[k, 1]
        phi_dd = state.qdd[k, 0] + state.qdd[k, 1]
        e1 = np.array([math.cos(t1), math.sin(t1)])
        a_b = l1 * (ddt1 * perp(e1) - dt1**2 * e1)

        def accel(local: NDArray[np.float64], phi=phi, phi_d=phi_d, phi_dd=phi_dd, a_b=a_b):
            r = _rot(phi) @ local
            return a_b + phi_dd * perp(r) - phi_d**2 * r

        lam = inv.coupler_force[k]  # on the coupler at D from the upper arm (world)
        f_payload = payload_kg * (gvec - accel(pts["upper_arm"]["E"]))
        f_b_upper = m_u * accel(com_u) - m_u * gvec + lam - f_payload  # on upper arm at B
        to_upper, to_lower = _rot(-phi), _rot(-t1)
        out["upper_arm"].append(
            LinkLoads(label, "B", {"D": to_upper @ -lam, "E": to_upper @ f_payload})
        )
        out["lower_arm"].append(LinkLoads(label, "A", {"B": to_lower @ -f_b_upper}))
    return out


def link_problem(
    design: ArrayLike,
    cad: CadSettings,
    link: str,
    cases: list[LinkLoads],
    settings: TopologySettings = DEFAULT_TOPOLOGY,
    scale: ArrayLike | None = None,
) -> tuple[FeProblem, shapely.Polygon]:
    """FE problem of ``link`` ('lower_arm' or 'upper_arm') and its CAD outline polygon, the link
    of ``cad``'s section scaled by its entry of ``scale`` (4,) (None: ``cad``'s)."""
    sec = link_settings(cad, scale)[link]
    outline = shapely.Polygon(link_outlines(design, cad, scale)[link])
    pts = joint_points(design)[link]
    lo, hi = np.asarray(outline.bounds[:2]), np.asarray(outline.bounds[2:])
    grid = grid_for_box(lo, hi, settings.cell_size_m)
    centres = grid.cell_centres()
    inside = shapely.contains_xy(outline, centres[..., 0], centres[..., 1])
    r = sec.boss_radius_m
    solid = np.zeros_like(inside)
    for p in pts.values():
        solid |= np.linalg.norm(centres - p, axis=-1) <= r
    solid &= inside
    design_cells = inside & ~solid
    clamps = {c.clamp for c in cases}
    if len(clamps) != 1:
        raise ValueError(f"load cases of {link} clamp different joints {clamps}")
    fixed = clamped_dofs(grid, pts[clamps.pop()], r)
    forces = np.column_stack(
        [nodal_forces(grid, [(pts[j], f) for j, f in c.forces.items()], r) for c in cases]
    )
    forces[fixed] = 0.0
    return FeProblem(grid, fixed, forces, design_cells, solid, sec.thickness_m), outline


# ----------------------------------------------------------------------------- driver

"""The beam model of :mod:`qsm.embodiment.strength.stresses` against plane-stress finite elements.

For one design, at the duty samples of peak |tau1| and |tau2| (those of
:func:`qsm.realization.topology.plate_loads.peak_loads`), the lower and the upper arm are analysed
twice under the same loads: the joint forces of :func:`qsm.embodiment.strength.loads.joint_loads`
plus the link's own weight and d'Alembert inertia.

* Beam: :func:`qsm.embodiment.strength.stresses.cut_forces` with a solid section (no bore, as
  the FE plate has solid bosses), the peak over the link's bar cuts.
* FE: the solid CAD plate of :func:`qsm.realization.topology.plate_loads.link_problem` (clamped over
  the whole boss of A, for the lower arm, or B, for the upper arm; joint forces spread over the
  nodes of the other bosses), each cell's stiffness and body force in proportion to its area inside
  the outline; von Mises stress per cell. The peak is taken over the whole cells outside every boss
  (centre farther than the boss radius from every joint): inside, the clamp and the spread point
  loads make stresses that are not real, and a cut cell's strain overstates the stress.

Besides the peaks, both are compared on cross-sections clear of the bosses (the largest von Mises
stress of the cells of one cell column across the bar against the beam stress at that column's
centre) and at the upper arm's filleted inside corner (against the beam's corner cuts, the
calibration of ``strength.corner_stress_concentration``). docs/strength.md gives the method and
the measured agreement.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from reference_fe_sections import (
    SectionResult,
    bar_sections,
    inside_corner,
    section_cuts,
    snap,
)

from qsm.embodiment.strength.beam import Section, link_cuts
from qsm.embodiment.strength.loads import GRAVITY, Inertials, joint_loads, link_motion
from qsm.embodiment.strength.stresses import cut_forces, section_stress
from qsm.physics.cad import DEFAULT_CAD, CadSettings, link_outlines, mass_properties
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import loop_state
from qsm.physics.kinematics import LINK_NAMES, as_design, perp
from qsm.realization.topology.fe import (
    DEFAULT_TOPOLOGY,
    FeProblem,
    Grid,
    TopologySettings,
    analyse,
    clamped_dofs,
    nodal_forces,
)
from qsm.realization.topology.geometry import cell_fill
from qsm.realization.topology.plate_loads import LinkLoads, joint_points

#: Links with a finite-element problem
#: (:data:`qsm.realization.topology.plate_loads.OPTIMISED_LINKS`).
FE_LINKS = ("lower_arm", "upper_arm")


class LinkComparison(NamedTuple):
    """One link at one duty sample: the beam model's peak bar stress and where it is, the FE's
    peak von Mises stress outside the bosses and its cell centre (m, link frame), and the
    sections clear of the bosses."""

    link: str
    case: str
    sample: int
    beam_pa: float
    beam_where: str
    fe_pa: float
    fe_at: tuple[float, float]
    sections: tuple[SectionResult, ...]

    @property
    def ratio(self) -> float:
        """FE peak over beam peak (below 1: the beam model is conservative)."""
        return self.fe_pa / self.beam_pa


def aligned_problem(
    design: NDArray[np.float64], cad: CadSettings, link: str, case: LinkLoads, h: float
) -> FeProblem:
    """The FE problem of :func:`qsm.realization.topology.plate_loads.link_problem` (solid plate of
    the CAD outline, bosses solid, the clamp joint's boss clamped, joint forces spread over the boss
    nodes) on a grid whose cell edges lie on the bars' edges, so that a bar is exactly
    ``width / h`` cells wide (``h`` must divide the width). link_problem centres its grid on the
    outline's box instead, which makes a bar one cell wider or offset by half a cell."""
    w = cad.width_m
    if abs(w / h - round(w / h)) > 1e-9:
        raise ValueError("the cell size must divide the bar width")
    outline = shapely.Polygon(link_outlines(design, cad)[link])
    lo, hi = np.asarray(outline.bounds[:2]), np.asarray(outline.bounds[2:])
    # grid lines on y = -w/2 (every bar of the lower arm, the upper arm's horizontal legs) and on
    # x = E_x - w/2 (the upper arm's vertical leg)
    anchor = np.array([float(design[4]) if link == "upper_arm" else 0.0, 0.0]) - w / 2
    origin = anchor + np.floor((lo - anchor) / h + 1e-9) * h
    n = np.ceil((hi - origin) / h - 1e-9).astype(int)
    grid = Grid((float(origin[0]), float(origin[1])), h, int(n[0]), int(n[1]))
    centres = grid.cell_centres()
    inside = shapely.contains_xy(outline, centres[..., 0], centres[..., 1])
    pts = joint_points(design)[link]
    r = cad.boss_radius_m
    solid = np.zeros_like(inside)
    for p in pts.values():
        solid |= np.linalg.norm(centres - p, axis=-1) <= r
    solid &= inside
    fixed = clamped_dofs(grid, pts[case.clamp], r)
    forces = nodal_forces(grid, [(pts[j], f) for j, f in case.forces.items()], r)
    forces[fixed] = 0.0
    return FeProblem(grid, fixed, forces[:, None], inside & ~solid, solid, cad.thickness_m)


def compare_design(
    design: ArrayLike,
    cad: CadSettings = DEFAULT_CAD,
    payload_kg: float = 5.0,
    duty: Duty | None = None,
    cell_size_m: float = 0.004,
    settings: TopologySettings = DEFAULT_TOPOLOGY,
    links: tuple[str, ...] = FE_LINKS,
) -> list[LinkComparison]:
    """Beam against FE for ``links`` (of the lower and upper arm) of ``design`` (6,) m at the
    duty samples of peak |tau1| and |tau2| (see the module docstring); FE cells of side
    ``cell_size_m``."""
    d = as_design(design)
    duty = duty_cycle() if duty is None else duty
    props = mass_properties(d, cad)
    inertials = Inertials.of(props)
    state = loop_state(d, duty.theta, duty.dtheta, duty.ddtheta)
    if not state.closes.all():
        raise ValueError("the loop does not close over the whole duty")
    motion = link_motion(d, state)
    loads = joint_loads(d, inertials, payload_kg, state, motion)
    sec = Section(cad.width_m, cad.thickness_m, cad.boss_radius_m)
    fe_settings = dataclasses.replace(settings, cell_size_m=cell_size_m)
    samples = {
        "peak_tau1": int(np.nanargmax(np.abs(loads.tau[:, 0]))),
        "peak_tau2": int(np.nanargmax(np.abs(loads.tau[:, 1]))),
    }
    outlines = link_outlines(d, cad)
    out = []
    for link in links:
        k = LINK_NAMES.index(link)
        cuts = link_cuts(d, sec)[link]
        bar = np.array([label.startswith("bar") for label in cuts.labels])
        axial, moment = cut_forces(d, sec, inertials, loads, motion, link, cuts)
        beam = section_stress(axial, moment, sec)[:, bar]  # (N, bar cuts)
        bar_labels = [lab for lab, b in zip(cuts.labels, bar, strict=True) if b]
        pts = joint_points(d)[link]
        for case, j in samples.items():
            if link == "lower_arm":
                forces = {"B": motion.rotate_to_link(-loads.b, k)[j]}
                clamp = "A"
            else:
                forces = {
                    "D": motion.rotate_to_link(-loads.d, k)[j],
                    "E": motion.rotate_to_link(loads.e, k)[j],
                }
                clamp = "B"
            problem = aligned_problem(d, cad, link, LinkLoads(case, clamp, forces), cell_size_m)
            g = problem.grid
            filled = problem.design | problem.solid
            # each cell's stiffness and mass in proportion to its area inside the outline (the
            # fillet's arc is not a staircase); the bosses solid
            fill = np.where(problem.solid, 1.0, cell_fill(g, shapely.Polygon(outlines[link])))
            # body force of every cell, a quarter at each of its nodes
            c = g.cell_centres()
            g_rel = motion.rotate_to_link(GRAVITY - motion.origin_acc[:, k], k)[j]
            acc = g_rel - motion.alpha[j, k] * perp(c) + motion.omega[j, k] ** 2 * c
            cell_f = cad.density_kg_m3 * cad.thickness_m * g.h**2 * acc * fill[..., None]
            nodal = np.zeros((g.ny + 1, g.nx + 1, 2))
            for dj in (0, 1):
                for di in (0, 1):
                    nodal[dj : dj + g.ny, di : di + g.nx] += cell_f / 4
            f = problem.forces[:, 0] + nodal.reshape(-1)
            f[problem.fixed] = 0.0
            problem = dataclasses.replace(problem, forces=f[:, None])
            vm = analyse(problem, fill, fe_settings, penal=1.0).von_mises_pa
            # whole cells only: the strain of a cut cell is that of a softer cell, and a stress
            # from it overstates the material's (up to 40 % on the fillet's arc)
            far = fill > 1 - 1e-9
            for p in pts.values():
                far &= np.linalg.norm(c - p, axis=-1) > cad.boss_radius_m
            vm_far = np.where(far, vm, 0.0)
            jj, ii = np.unravel_index(int(np.argmax(vm_far)), vm_far.shape)
            # sections: snap to the cell-centre line, beam there, FE across the bar
            results = []
            snapped = []
            for s in bar_sections(d, link, sec, g.h, cad.corner_fillet_m):
                x, y = s.at
                if s.tangent[1] == 0:
                    x = float(snap(g.origin[0], g.h, x))
                else:
                    y = float(snap(g.origin[1], g.h, y))
                snapped.append(s._replace(at=(x, y)))
            ax_s, mo_s = cut_forces(
                d, sec, inertials, loads, motion, link, section_cuts(d, link, snapped)
            )
            beam_s = section_stress(ax_s, mo_s, sec)[j]
            for s, b in zip(snapped, beam_s, strict=True):
                along = 0 if s.tangent[1] == 0 else 1
                on_line = np.abs(c[..., along] - s.at[along]) < g.h / 2
                across = np.abs(c[..., 1 - along] - s.at[1 - along]) <= sec.width_m / 2
                cells = on_line & across & filled
                results.append(SectionResult(s.label, s.at, float(b), float(vm[cells].max())))
            if link == "upper_arm":
                results.append(inside_corner(d, cad, c, vm_far, beam[j], bar_labels))
            out.append(
                LinkComparison(
                    link,
                    case,
                    j,
                    float(beam[j].max()),
                    bar_labels[int(beam[j].argmax())],
                    float(vm_far[jj, ii]),
                    (float(c[jj, ii, 0]), float(c[jj, ii, 1])),
                    tuple(results),
                )
            )
    return out

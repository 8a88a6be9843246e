"""2D topology optimisation (SIMP) of the lower-arm and upper-arm plates (paper Section 5, Table 3).

Finite elements, filtering and sensitivities come from pyMOTO (``pymoto.VoxelDomain``,
``DensityFilter``, ``AssembleStiffness``, ``LinSolve``, ``Stress``); this module only sets up the
domains and loads, runs the optimality-criteria (OC) update and turns the result into solids.

Problem per link (plane stress, plate thickness = the link's CAD thickness, ABS-M30; each link
of its own section when sized, ``scale``):

* design domain: a regular grid of square cells (``cell_size_m``) over the link's bounding box in
  its link frame (:mod:`qsm.physics.cad`); cells whose centre lies outside the CAD outline are void
  (passive, density ``min_density``), cells within ``boss_radius_m`` of a joint are solid
  (passive, density 1); the rest is designable;
* supports and loads, quasi-static at the two duty samples of peak |tau1| and peak |tau2|
  (two load cases, compliance summed), from :func:`qsm.physics.dynamics.inverse_dynamics`:

  - upper arm: boss B clamped (a pin plus the small residual moment of the arm's own weight and
    inertia, which the FE model does not apply as a body load); at D the force of the coupler on
    the upper arm (``-coupler_force``); at E the payload's force m (g - a_E) (gravity plus
    d'Alembert inertia, a_E from the loop kinematics);
  - lower arm: boss A clamped (the motor); at B the force of the upper arm on the lower arm,
    -F_B, where F_B = m_u a_cu - m_u g + coupler_force - F_payload is the pin force on the upper arm
    from its Newton equation (m_u, a_cu: upper-arm mass and centre-of-mass acceleration);

  each joint force is spread uniformly over the FE nodes inside that joint's boss;
* objective: minimum compliance with the physical (filtered) volume of the designable cells equal
  to ``volume_fraction`` of them; SIMP penalty ``penal``, density filter radius
  ``filter_radius_cells``, OC move limit ``move``, at most ``max_iterations``.

The optimised density field is thresholded at ``threshold``; the union of the solid cells (shapely),
closed by half a cell, clipped to the CAD outline and joined with the boss discs, is extruded by
trimesh into a watertight plate whose ``mass_properties`` replace the link's
:class:`qsm.physics.cad.MassProperties`. The load check re-solves both load cases on the printed
plate (rasterised as the covered fraction of each cell, stiffness proportional to it): the
compliance, and the peak von Mises stress of the cells at least half filled (element averages) must
stay within ``allowable_stress_pa = yield_strength_pa / safety_factor``.

Stress and stiffness limits: compliance at a fixed volume fraction has no reason to respect
either, so a printed plate that exceeds the allowable stress, or keeps less than
``min_stiffness_factor`` of the solid plate's stiffness (the solid plate's compliance over the
printed one's, the factor the accuracy budget applies to the link; the realisation sized the
sections for the tolerance with the plates at that factor), is not kept. The optimisation runs
again with more material, ``volume_fraction`` raised by :data:`VOLUME_STEP` up to
:data:`MAX_VOLUME_FRACTION`, until the printed plate passes both; if none does, the link stays the
solid CAD plate (``kept_solid``), and the result says so. Every attempt is recorded.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import shapely
import trimesh
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import CadSettings, MassProperties, link_settings, mass_properties
from qsm.physics.duty import Duty
from qsm.physics.kinematics import as_design
from qsm.realization.topology import OPTIMIZED_LINKS
from qsm.realization.topology.fe import (
    DEFAULT_TOPOLOGY,
    FeProblem,
    FeResult,
    Grid,
    TopologySettings,
    analyse,
)
from qsm.realization.topology.geometry import (
    cell_fill,
    cells_to_geometry,
    extrude,
    mesh_mass_properties,
    polygons,
)
from qsm.realization.topology.plate_loads import (
    LinkLoads,
    joint_points,
    link_problem,
    peak_loads,
)
from qsm.realization.topology.simp import SimpResult, simp

#: Step (of the designable cells) by which the kept material grows after a plate that fails.
VOLUME_STEP = 0.1
#: Most material a lighter plate may keep; beyond it the solid link is kept.
MAX_VOLUME_FRACTION = 0.9


@dataclass
class LinkResult:
    """Topology optimisation of one link (SI units); see :func:`optimise_links`."""

    name: str
    grid: Grid
    density: NDArray[np.float64]
    design_cells: NDArray[np.bool_]
    solid_cells: NDArray[np.bool_]
    outline: NDArray[np.float64]
    polygon: shapely.Geometry
    mesh: trimesh.Trimesh
    props_before: MassProperties
    props_after: MassProperties
    loads: list[LinkLoads]
    history_J: NDArray[np.float64]
    iterations: int
    volume_fraction: float
    threshold: float
    compliance_before_J: float
    compliance_after_J: float
    max_von_mises_before_pa: float
    max_von_mises_after_pa: float
    p99_von_mises_after_pa: float
    allowable_stress_pa: float
    seconds: float
    kept_solid: bool = False
    attempts: list[dict[str, float]] = field(default_factory=list)

    @property
    def carries_loads(self) -> bool:
        """Peak von Mises stress of the printed (thresholded) plate within the allowable."""
        return self.max_von_mises_after_pa <= self.allowable_stress_pa

    def summary(self) -> dict[str, Any]:
        """Scalar figures of this link (JSON-friendly)."""
        return {
            "link": self.name,
            "grid": [self.grid.nx, self.grid.ny],
            "cell_size_m": self.grid.h,
            "iterations": self.iterations,
            "volume_fraction": self.volume_fraction,
            "threshold": self.threshold,
            "mass_before_kg": self.props_before.mass_kg,
            "mass_after_kg": self.props_after.mass_kg,
            "compliance_before_J": self.compliance_before_J,
            "compliance_after_J": self.compliance_after_J,
            "max_von_mises_before_MPa": self.max_von_mises_before_pa / 1e6,
            "max_von_mises_after_MPa": self.max_von_mises_after_pa / 1e6,
            "p99_von_mises_after_MPa": self.p99_von_mises_after_pa / 1e6,
            "allowable_stress_MPa": self.allowable_stress_pa / 1e6,
            "carries_loads": self.carries_loads,
            "kept_solid": self.kept_solid,
            "attempts": self.attempts,
            "watertight": bool(self.mesh.is_watertight),
            "seconds": self.seconds,
        }


@dataclass
class TopologyResult:
    """Per-link results and the new mass properties of all four links (``props``)."""

    links: dict[str, LinkResult]
    props: dict[str, MassProperties]
    settings: TopologySettings = field(default_factory=TopologySettings)

    @property
    def carries_loads(self) -> bool:
        """Every optimised link passes its stress check."""
        return all(r.carries_loads for r in self.links.values())


def printed_geometry(
    grid: Grid,
    density: ArrayLike,
    outline: shapely.Polygon,
    joints: list[ArrayLike],
    boss_radius_m: float,
    threshold: float,
    segments_per_circle: int = 64,
) -> tuple[shapely.Geometry, float]:
    """Printed plate outline and the threshold used.

    Solid cells (density >= threshold), closed morphologically by half a cell (bridges diagonally
    touching cells, rounds the staircase), clipped to the CAD outline, plus the boss discs; pieces
    not touching a boss are dropped. When the joints are not all in one piece the threshold is
    lowered in steps of 0.05 (down to 0.05) until they are, so the part always connects its joints
    (grey members of a not fully converged design are kept rather than cut).
    """
    rho = np.asarray(density)
    bosses = [
        shapely.Point(p).buffer(boss_radius_m, quad_segs=max(2, segments_per_circle // 4))
        for p in joints
    ]
    geom: shapely.Geometry = shapely.Polygon()
    t = threshold
    for t in np.arange(threshold, 0.0, -0.05):
        # a closing by half a cell bridges diagonally touching cells with real material
        cells = (
            cells_to_geometry(grid, rho >= t)
            .buffer(0.5 * grid.h, quad_segs=2)
            .buffer(-0.5 * grid.h, quad_segs=2)
        )
        geom = shapely.make_valid(shapely.union_all([cells.intersection(outline), *bosses]))
        keep = [p for p in polygons(geom) if any(p.intersects(b) for b in bosses)]
        geom = shapely.union_all(keep)
        if any(all(p.intersects(b) for b in bosses) for p in keep):
            break
    return geom, float(t)


@dataclass(frozen=True)
class _Plate:
    """The plate a link is printed as: the last SIMP run, its printed geometry (shapely, m) and
    threshold, the plate's FE, its mesh, its mass properties (None: the solid plate is kept) and
    every volume fraction tried with its peak von Mises stress (MPa)."""

    opt: SimpResult
    geometry: shapely.Polygon
    threshold: float
    fe: FeResult
    mesh: trimesh.Trimesh
    props: MassProperties | None
    attempts: list[dict[str, float]]


def _printed_plate(
    problem: FeProblem,
    outline: shapely.Polygon,
    joints: list[NDArray[np.float64]],
    sec: CadSettings,
    settings: TopologySettings,
    fe_before: FeResult,
) -> _Plate:
    """SIMP at the configured volume fraction, raised by VOLUME_STEP until the printed plate
    holds its loads (peak von Mises at most the allowable) and keeps ``min_stiffness_factor`` of
    the solid plate's stiffness; past MAX_VOLUME_FRACTION the solid plate is kept."""
    attempts: list[dict[str, float]] = []
    fraction = settings.volume_fraction
    while True:
        opt = simp(problem, replace(settings, volume_fraction=fraction))
        geom, threshold = printed_geometry(
            problem.grid,
            opt.density,
            outline,
            joints,
            sec.boss_radius_m,
            settings.threshold,
            sec.segments_per_circle,
        )
        # the printed plate, rasterised by cell fill, stiffness proportional to the fill
        fe_after = analyse(problem, cell_fill(problem.grid, geom), settings, penal=1.0)
        factor = fe_before.compliance_J / fe_after.compliance_J
        attempts.append(
            {
                "volume_fraction": fraction,
                "max_von_mises_MPa": fe_after.max_von_mises_pa / 1e6,
                "stiffness_factor": factor,
            }
        )
        holds = fe_after.max_von_mises_pa <= settings.allowable_stress_pa
        if holds and factor >= settings.min_stiffness_factor:
            mesh = extrude(geom, sec.thickness_m)
            props = mesh_mass_properties(mesh, sec.density_kg_m3)
            return _Plate(opt, geom, threshold, fe_after, mesh, props, attempts)
        if fraction + VOLUME_STEP > MAX_VOLUME_FRACTION + 1e-9:
            mesh = extrude(outline, sec.thickness_m)
            return _Plate(opt, outline, 1.0, fe_before, mesh, None, attempts)
        fraction = round(fraction + VOLUME_STEP, 10)


def optimize_links(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    settings: TopologySettings = DEFAULT_TOPOLOGY,
    links: tuple[str, ...] = OPTIMIZED_LINKS,
    scale: ArrayLike | None = None,
) -> TopologyResult:
    """Topology-optimise ``links`` of ``design`` (6 lengths, m) for the peak loads over ``duty``
    with ``payload_kg`` at E, each link of ``cad``'s section scaled by its entry of ``scale``
    (4,) (None: ``cad``'s); returns the density fields, printed meshes, masses, compliances
    before (full solid CAD plate) and after (printed plate), the stress check, and ``props``:
    the mass properties of all four links with the optimised ones replaced."""
    d = as_design(design)
    before = mass_properties(d, cad, scale)
    loads = peak_loads(d, cad, payload_kg, duty, before)
    sections = link_settings(cad, scale)
    results: dict[str, LinkResult] = {}
    props = dict(before)
    for link in links:
        start = time.perf_counter()
        problem, outline = link_problem(d, cad, link, loads[link], settings, scale)
        fe_before = analyse(problem, (problem.design | problem.solid).astype(float), settings)
        joints = list(joint_points(d)[link].values())
        plate = _printed_plate(problem, outline, joints, sections[link], settings, fe_before)
        props[link] = plate.props if plate.props is not None else before[link]
        results[link] = LinkResult(
            name=link,
            grid=problem.grid,
            density=plate.opt.density,
            design_cells=problem.design,
            solid_cells=problem.solid,
            outline=np.asarray(outline.exterior.coords),
            polygon=plate.geometry,
            mesh=plate.mesh,
            props_before=before[link],
            props_after=props[link],
            loads=loads[link],
            history_J=plate.opt.history_J,
            iterations=plate.opt.iterations,
            volume_fraction=plate.opt.volume_fraction,
            threshold=plate.threshold,
            compliance_before_J=fe_before.compliance_J,
            compliance_after_J=plate.fe.compliance_J,
            max_von_mises_before_pa=fe_before.max_von_mises_pa,
            max_von_mises_after_pa=plate.fe.max_von_mises_pa,
            p99_von_mises_after_pa=plate.fe.p99_von_mises_pa,
            allowable_stress_pa=settings.allowable_stress_pa,
            seconds=time.perf_counter() - start,
            kept_solid=plate.props is None,
            attempts=plate.attempts,
        )
    return TopologyResult(results, props, settings)

"""2D topology optimisation (SIMP) of the lower-arm and upper-arm plates (paper Section 5, Table 3).

Finite elements, filtering and sensitivities come from pyMOTO (``pymoto.VoxelDomain``,
``DensityFilter``, ``AssembleStiffness``, ``LinSolve``, ``Stress``); this module only sets up the
domains and loads, runs the optimality-criteria (OC) update and turns the result into solids.

Problem per link (plane stress, plate thickness = the CAD thickness, ABS-M30):

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

The optimised density field is thresholded at ``threshold``; the union of the solid cells
(shapely), closed by half a cell, clipped to the CAD outline and joined with the boss discs, is
extruded by trimesh into a watertight plate whose ``mass_properties`` replace the link's
:class:`qsm.physics.cad.MassProperties`. The load check re-solves both load cases on the printed
plate
(rasterised as the covered fraction of each cell, stiffness proportional to it): the compliance,
and the peak von Mises stress of the cells at least half filled (element averages) must stay within
``allowable_stress_pa = yield_strength_pa / safety_factor``.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import matplotlib
import numpy as np
import scipy.sparse as sps
import shapely
import trimesh
from numpy.typing import ArrayLike, NDArray

from qsm.physics.cad import CadSettings, MassProperties, link_outlines, mass_properties
from qsm.physics.duty import Duty
from qsm.physics.dynamics import inverse_dynamics, loop_state
from qsm.physics.kinematics import as_design, perp
from qsm.physics.mjcf import GRAVITY_M_S2, model_spec

# pymoto 2.0.1 calls matplotlib.use("TkAgg") when imported, which takes a notebook's backend away
# and fails without a display once pyplot is loaded: make that call a no-op while importing it.
_use, matplotlib.use = matplotlib.use, lambda *args, **kwargs: None
try:
    import pymoto as pym
finally:
    matplotlib.use = _use

OPTIMISED_LINKS: tuple[str, ...] = ("lower_arm", "upper_arm")


@dataclass(frozen=True)
class TopologySettings:
    """SIMP settings (SI units).

    volume_fraction: target filled fraction of the designable cells, default 0.6 (at 0.5 the
        upper arm of the example design exceeds the stress limit in a thin member).
    cell_size_m: side of the square FE cells, default 4 mm.
    max_iterations: OC iterations, default 80; stops earlier when the largest density change
        falls below ``change_tol`` (default 0.01).
    penal: SIMP exponent, default 3. filter_radius_cells: density filter radius, default 1.5.
    move: OC move limit, default 0.2. min_density: void stiffness factor, default 1e-9.
    youngs_modulus_pa, poisson_ratio: ABS-M30, default 2.2 GPa and 0.35.
    yield_strength_pa: ABS-M30 tensile strength (XZ), default 31 MPa; safety_factor default 2.
    threshold: density above which a cell is solid in the printed part, default 0.5.
    """

    volume_fraction: float = 0.6
    cell_size_m: float = 0.004
    max_iterations: int = 80
    change_tol: float = 0.01
    penal: float = 3.0
    filter_radius_cells: float = 1.5
    move: float = 0.2
    min_density: float = 1e-9
    youngs_modulus_pa: float = 2.2e9
    poisson_ratio: float = 0.35
    yield_strength_pa: float = 31e6
    safety_factor: float = 2.0
    threshold: float = 0.5

    def __post_init__(self) -> None:
        if not 0.0 < self.volume_fraction <= 1.0:
            raise ValueError("volume_fraction must be in (0, 1]")
        if self.cell_size_m <= 0 or self.max_iterations < 1 or self.penal < 1:
            raise ValueError("need cell_size_m > 0, max_iterations >= 1, penal >= 1")
        if not 0.0 < self.threshold < 1.0:
            raise ValueError("threshold must be in (0, 1)")

    @property
    def allowable_stress_pa(self) -> float:
        """Allowed peak von Mises stress (Pa)."""
        return self.yield_strength_pa / self.safety_factor


DEFAULT_TOPOLOGY = TopologySettings()


# ----------------------------------------------------------------------------- grid and FE


@dataclass(frozen=True)
class Grid:
    """A regular grid of ``nx`` x ``ny`` square cells of side ``h`` (m) whose lower-left corner is
    ``origin`` (m, link frame). Cell (i, j) is element ``j * nx + i`` (pyMOTO's numbering); fields
    of shape (ny, nx) are indexed [j, i]."""

    origin: tuple[float, float]
    h: float
    nx: int
    ny: int

    def cell_centres(self) -> NDArray[np.float64]:
        """(ny, nx, 2) cell centres (m)."""
        x = self.origin[0] + (np.arange(self.nx) + 0.5) * self.h
        y = self.origin[1] + (np.arange(self.ny) + 0.5) * self.h
        return np.stack(np.meshgrid(x, y, indexing="xy"), axis=-1)

    def node_positions(self) -> NDArray[np.float64]:
        """(n_nodes, 2) node positions (m) in pyMOTO node order (x fastest)."""
        x = self.origin[0] + np.arange(self.nx + 1) * self.h
        y = self.origin[1] + np.arange(self.ny + 1) * self.h
        xx, yy = np.meshgrid(x, y, indexing="xy")
        return np.column_stack([xx.ravel(), yy.ravel()])

    def domain(self, thickness_m: float) -> pym.VoxelDomain:
        """pyMOTO domain with this grid's cell size (and plate thickness as the 2D depth)."""
        return pym.VoxelDomain(self.nx, self.ny, unitx=self.h, unity=self.h, unitz=thickness_m)


def grid_for_box(lo: ArrayLike, hi: ArrayLike, h: float) -> Grid:
    """Smallest grid of cells of side ``h`` (m) covering the box [lo, hi] (m), centred on it."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    n = np.maximum(np.ceil((hi - lo) / h - 1e-9).astype(int), 1)
    origin = (lo + hi) / 2 - n * h / 2
    return Grid((float(origin[0]), float(origin[1])), float(h), int(n[0]), int(n[1]))


def nodes_within(grid: Grid, centre: ArrayLike, radius: float) -> NDArray[np.int_]:
    """Node numbers within ``radius`` (m) of ``centre`` (m); at least the nearest node."""
    d = np.linalg.norm(grid.node_positions() - np.asarray(centre, dtype=float), axis=1)
    inside = np.flatnonzero(d <= radius)
    return inside if inside.size else np.array([int(np.argmin(d))])


def nodal_forces(grid: Grid, loads: list[tuple[ArrayLike, ArrayLike]], radius: float) -> NDArray:
    """Global force vector (2 n_nodes,) from point loads ``(point_m, force_N)`` each spread
    uniformly over the nodes within ``radius`` (m) of its point."""
    f = np.zeros(2 * (grid.nx + 1) * (grid.ny + 1))
    for point, force in loads:
        nodes = nodes_within(grid, point, radius)
        fv = np.asarray(force, dtype=float) / len(nodes)
        np.add.at(f, 2 * nodes, fv[0])
        np.add.at(f, 2 * nodes + 1, fv[1])
    return f


def clamped_dofs(grid: Grid, centre: ArrayLike, radius: float) -> NDArray[np.int_]:
    """Both dofs of every node within ``radius`` (m) of ``centre`` (m)."""
    nodes = nodes_within(grid, centre, radius)
    return np.concatenate([2 * nodes, 2 * nodes + 1])


@dataclass(frozen=True)
class FeProblem:
    """A plane-stress problem on ``grid``: ``fixed`` dofs, ``forces`` (2 n_nodes, n_cases) in N,
    ``design`` (ny, nx) bool designable cells, ``solid`` (ny, nx) bool cells kept solid (others
    that are neither are void), plate ``thickness_m``."""

    grid: Grid
    fixed: NDArray[np.int_]
    forces: NDArray[np.float64]
    design: NDArray[np.bool_]
    solid: NDArray[np.bool_]
    thickness_m: float


@dataclass(frozen=True)
class FeResult:
    """Compliance (J, summed over load cases), per-case compliances, peak and 99th-percentile
    von Mises stress (Pa) over solid cells, the element stresses (ny, nx) of the worst case."""

    compliance_J: float
    case_compliance_J: NDArray[np.float64]
    max_von_mises_pa: float
    p99_von_mises_pa: float
    von_mises_pa: NDArray[np.float64]


def _von_mises(s: NDArray[np.float64]) -> NDArray[np.float64]:
    sxx, syy, txy = s
    return np.sqrt(sxx**2 + syy**2 - sxx * syy + 3 * txy**2)


def _stiffness(
    dom: pym.VoxelDomain, problem: FeProblem, s: TopologySettings
) -> pym.AssembleStiffness:
    """pyMOTO's plane-stress stiffness assembly for ``problem`` with the settings' material."""
    return pym.AssembleStiffness(
        dom,
        bc=problem.fixed,
        e_modulus=s.youngs_modulus_pa,
        poisson_ratio=s.poisson_ratio,
        plane="stress",
        matrix_type=sps.csc_matrix,
    )


def analyse(
    problem: FeProblem, density: ArrayLike, settings: TopologySettings, penal: float | None = None
) -> FeResult:
    """Linear static analysis of ``density`` (ny, nx) with SIMP stiffness (pyMOTO assembly);
    ``penal`` overrides the settings' exponent (1: stiffness proportional to cell fill)."""
    g, s = problem.grid, settings
    dom = g.domain(problem.thickness_m)
    rho = np.asarray(density, dtype=float).ravel()
    scale = s.min_density + (1 - s.min_density) * rho ** (s.penal if penal is None else penal)
    K = _stiffness(dom, problem, s)(scale)
    u = pym.LinSolve(hermitian=True)(K, problem.forces)
    u = np.atleast_2d(u.T).T
    per_case = np.einsum("ik,ik->k", u, problem.forces)
    stress = pym.Stress(
        dom, e_modulus=s.youngs_modulus_pa, poisson_ratio=s.poisson_ratio, plane="stress"
    )
    vm = np.stack([_von_mises(stress(u[:, k])) for k in range(u.shape[1])])  # solid-material
    solid_cells = rho >= 0.5
    worst = vm.max(axis=0)
    vals = worst[solid_cells] if solid_cells.any() else np.zeros(1)
    return FeResult(
        float(per_case.sum()),
        per_case,
        float(vals.max()),
        float(np.percentile(vals, 99)),
        np.where(solid_cells, worst, 0.0).reshape(g.ny, g.nx),
    )


@dataclass(frozen=True)
class SimpResult:
    """Physical (filtered) density (ny, nx), compliance history (J) and final volume fraction of
    the designable cells, and the iteration count."""

    density: NDArray[np.float64]
    history_J: NDArray[np.float64]
    volume_fraction: float
    iterations: int


def simp(problem: FeProblem, settings: TopologySettings = DEFAULT_TOPOLOGY) -> SimpResult:
    """Minimum-compliance SIMP with OC updates on ``problem`` (pyMOTO network for the analysis and
    the sensitivities); passive solid/void cells are overwritten after the filter."""
    g, s = problem.grid, settings
    dom = g.domain(problem.thickness_m)
    design = problem.design.ravel()
    solid = problem.solid.ravel() & ~design
    void = ~design & ~solid
    if not design.any():
        raise ValueError("the problem has no designable cells")
    n_design = int(design.sum())
    x0 = np.where(solid, 1.0, 0.0)
    x0[design] = s.volume_fraction
    sx = pym.Signal("x", state=x0)
    sf = pym.Signal("f", state=problem.forces)
    passive = np.flatnonzero(~design)
    passive_value = np.where(solid[passive], 1.0, 0.0)
    filt = pym.DensityFilter(dom, radius=s.filter_radius_cells)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sps.SparseEfficiencyWarning)
        with pym.Network() as net:
            xf = filt(sx)
            xphys = pym.SetValue(passive, passive_value)(xf)
            xs = pym.MathExpression(f"{s.min_density} + {1 - s.min_density}*inp0^{s.penal}")(xphys)
            K = _stiffness(dom, problem, s)(xs)
            u = pym.LinSolve(hermitian=True)(K, sf)
            c = pym.EinSum("ij,ij->")(u, sf)
        target = s.volume_fraction * n_design
        filt_h = sps.csr_matrix(filt.H)
        filt_hs = np.asarray(filt.H.sum(axis=1)).ravel()
        x = x0.copy()
        history = []
        it = 0
        for it in range(1, s.max_iterations + 1):  # noqa: B007
            net.response()
            net.reset()
            c.sensitivity = 1.0
            net.sensitivity()
            history.append(float(c.state))
            dc = np.minimum(np.asarray(sx.sensitivity), 0.0)
            lo = np.maximum(0.0, x - s.move)
            hi = np.minimum(1.0, x + s.move)
            l1, l2 = 0.0, max(float(-dc.min()), 1e-300) * 1e6  # xn = lo at l2
            xn = x
            for _ in range(100):
                lm = 0.5 * (l1 + l2)
                xn = np.clip(x * np.sqrt(-dc / lm), lo, hi)
                xn[~design] = x0[~design]
                vol = (filt_h @ xn / filt_hs)[design].sum()  # physical volume
                if vol > target:
                    l1 = lm
                else:
                    l2 = lm
                if (l2 - l1) <= 1e-6 * (l1 + l2):
                    break
            change = float(np.abs(xn - x).max())
            x = xn
            sx.state = x
            if change < s.change_tol:
                break
        net.response()
        history.append(float(c.state))
    rho = np.asarray(xphys.state, dtype=float)
    rho[void] = 0.0
    return SimpResult(
        rho.reshape(g.ny, g.nx),
        np.asarray(history),
        float(rho[design].sum() / n_design),
        it,
    )


# ----------------------------------------------------------------------------- solids


def cells_to_geometry(grid: Grid, mask: ArrayLike) -> shapely.Geometry:
    """Union (m, link frame) of the cells where ``mask`` (ny, nx) is true (exact, may contain
    pinch points where cells touch diagonally; :func:`extrude` removes them)."""
    m = np.asarray(mask, dtype=bool)
    j, i = np.nonzero(m)
    if j.size == 0:
        return shapely.Polygon()
    x0 = grid.origin[0] + i * grid.h
    y0 = grid.origin[1] + j * grid.h
    return shapely.union_all(shapely.box(x0, y0, x0 + grid.h, y0 + grid.h))


def cell_fill(grid: Grid, geom: shapely.Geometry) -> NDArray[np.float64]:
    """Fraction (ny, nx) of each cell covered by ``geom`` (rasterisation of a printed outline)."""
    j, i = np.mgrid[0 : grid.ny, 0 : grid.nx]
    x0 = grid.origin[0] + i.ravel() * grid.h
    y0 = grid.origin[1] + j.ravel() * grid.h
    boxes = shapely.box(x0, y0, x0 + grid.h, y0 + grid.h)
    area = shapely.area(shapely.intersection(boxes, geom))
    return np.clip(area / grid.h**2, 0.0, 1.0).reshape(grid.ny, grid.nx)


def _polygons(geom: shapely.Geometry) -> list[shapely.Polygon]:
    if geom.is_empty:
        return []
    if isinstance(geom, shapely.Polygon):
        return [geom]
    return [p for p in getattr(geom, "geoms", []) if isinstance(p, shapely.Polygon)]


def extrude(geom: shapely.Geometry, thickness_m: float, dilate_m: float = 1e-5) -> trimesh.Trimesh:
    """Watertight plate (m) extruding every polygon of ``geom`` symmetrically about z = 0.

    The outline is first dilated by ``dilate_m`` (default 10 um: about +0.2 % area for the link
    plates) and snapped to a 1 um grid, which turns the pinch points of diagonally touching cells
    and rings that touch at a vertex into short necks, so every edge of the solid is manifold.
    """
    if dilate_m > 0:
        geom = geom.buffer(dilate_m, join_style="mitre")
    geom = shapely.set_precision(geom, min(1e-6, dilate_m / 5) if dilate_m > 0 else 0.0)
    parts = [
        trimesh.creation.extrude_polygon(
            shapely.geometry.polygon.orient(p, 1.0), thickness_m, mid_plane=True, engine="earcut"
        )
        for p in _polygons(geom)
    ]
    if not parts:
        raise ValueError("nothing to extrude")
    return trimesh.util.concatenate(parts) if len(parts) > 1 else parts[0]


def mesh_mass_properties(mesh: trimesh.Trimesh, density_kg_m3: float) -> MassProperties:
    """Mass properties of a watertight mesh (m) about its centre of mass, link-frame axes."""
    mesh.density = density_kg_m3
    return MassProperties(
        float(mesh.mass),
        np.asarray(mesh.center_mass, dtype=float),
        np.asarray(mesh.moment_inertia, dtype=float),
    )


# ----------------------------------------------------------------------------- link problems


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
) -> tuple[FeProblem, shapely.Polygon]:
    """FE problem of ``link`` ('lower_arm' or 'upper_arm') and its CAD outline polygon."""
    outline = shapely.Polygon(link_outlines(design, cad)[link])
    pts = joint_points(design)[link]
    lo, hi = np.asarray(outline.bounds[:2]), np.asarray(outline.bounds[2:])
    grid = grid_for_box(lo, hi, settings.cell_size_m)
    centres = grid.cell_centres()
    inside = shapely.contains_xy(outline, centres[..., 0], centres[..., 1])
    r = cad.boss_radius_m
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
    return FeProblem(grid, fixed, forces, design_cells, solid, cad.thickness_m), outline


# ----------------------------------------------------------------------------- driver


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

    Solid cells (density >= threshold), closed morphologically by half a cell (bridges
    diagonally touching cells, rounds the staircase), clipped to the CAD outline, plus the boss
    discs; pieces
    not touching a boss are dropped. When the joints are not all in one piece the threshold is
    lowered in steps of 0.05 (down to 0.05) until they are, so the part always connects its
    joints (grey members of a not fully converged design are kept rather than cut).
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
        keep = [p for p in _polygons(geom) if any(p.intersects(b) for b in bosses)]
        geom = shapely.union_all(keep)
        if any(all(p.intersects(b) for b in bosses) for p in keep):
            break
    return geom, float(t)


def optimise_links(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    settings: TopologySettings = DEFAULT_TOPOLOGY,
    links: tuple[str, ...] = OPTIMISED_LINKS,
) -> TopologyResult:
    """Topology-optimise ``links`` of ``design`` (6 lengths, m) for the peak loads over ``duty``
    with ``payload_kg`` at E; returns the density fields, printed meshes, masses, compliances
    before (full solid CAD plate) and after (printed plate), the stress check, and ``props``:
    the mass properties of all four links with the optimised ones replaced."""
    d = as_design(design)
    before = mass_properties(d, cad)
    loads = peak_loads(d, cad, payload_kg, duty, before)
    results: dict[str, LinkResult] = {}
    props = dict(before)
    for link in links:
        start = time.perf_counter()
        problem, outline = link_problem(d, cad, link, loads[link], settings)
        full = (problem.design | problem.solid).astype(float)
        fe_before = analyse(problem, full, settings)
        opt = simp(problem, settings)
        joints = list(joint_points(d)[link].values())
        geom, threshold = printed_geometry(
            problem.grid,
            opt.density,
            outline,
            joints,
            cad.boss_radius_m,
            settings.threshold,
            cad.segments_per_circle,
        )
        mesh = extrude(geom, cad.thickness_m)
        after_props = mesh_mass_properties(mesh, cad.density_kg_m3)
        # the printed plate, rasterised by cell fill, stiffness proportional to the fill
        fe_after = analyse(problem, cell_fill(problem.grid, geom), settings, penal=1.0)
        props[link] = after_props
        results[link] = LinkResult(
            name=link,
            grid=problem.grid,
            density=opt.density,
            design_cells=problem.design,
            solid_cells=problem.solid,
            outline=np.asarray(outline.exterior.coords),
            polygon=geom,
            mesh=mesh,
            props_before=before[link],
            props_after=after_props,
            loads=loads[link],
            history_J=opt.history_J,
            iterations=opt.iterations,
            volume_fraction=opt.volume_fraction,
            threshold=threshold,
            compliance_before_J=fe_before.compliance_J,
            compliance_after_J=fe_after.compliance_J,
            max_von_mises_before_pa=fe_before.max_von_mises_pa,
            max_von_mises_after_pa=fe_after.max_von_mises_pa,
            p99_von_mises_after_pa=fe_after.p99_von_mises_pa,
            allowable_stress_pa=settings.allowable_stress_pa,
            seconds=time.perf_counter() - start,
        )
    return TopologyResult(results, props, settings)


def peak_torques(
    design: ArrayLike,
    cad: CadSettings,
    payload_kg: float,
    duty: Duty,
    props: dict[str, MassProperties] | None = None,
) -> dict[str, float]:
    """Peak |tau1|, |tau2| (N m) over ``duty`` of the model built with ``props`` (default CAD)."""
    d = as_design(design)
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
) -> dict[str, dict[str, float]]:
    """Peak motor torques (N m) over ``duty`` with the CAD links ("before") and with ``new_props``
    ("after"), each from a freshly built MJCF model; plus the relative change in percent."""
    before = peak_torques(design, cad, payload_kg, duty)
    after = peak_torques(design, cad, payload_kg, duty, new_props)
    change = {f"{k[:-3]}_change_pct": 100.0 * (after[k] - before[k]) / before[k] for k in before}
    return {"before": before, "after": after, "change": change}


def plot_links(result: TopologyResult, path: str | Path) -> Path:
    """Figure of the optimised density fields with the CAD outline and the printed outline."""
    import matplotlib.pyplot as plt

    n = len(result.links)
    fig, axes = plt.subplots(n, 1, figsize=(9, 2.6 * n + 0.4), squeeze=False)
    for ax, res in zip(axes[:, 0], result.links.values(), strict=True):
        g = res.grid
        extent = (g.origin[0], g.origin[0] + g.nx * g.h, g.origin[1], g.origin[1] + g.ny * g.h)
        ax.imshow(res.density, origin="lower", extent=extent, cmap="Greys", vmin=0, vmax=1)
        ax.plot(*res.outline.T, color="tab:blue", lw=0.8, label="CAD outline")
        for i, poly in enumerate(_polygons(res.polygon)):
            ax.plot(
                *np.asarray(poly.exterior.coords).T,
                color="tab:red",
                lw=0.8,
                label="printed" if i == 0 else None,
            )
            for hole in poly.interiors:
                ax.plot(*np.asarray(hole.coords).T, color="tab:red", lw=0.6)
        ax.set_aspect("equal")
        ax.set_title(
            f"{res.name}: mass {res.props_before.mass_kg:.3f} -> {res.props_after.mass_kg:.3f} kg, "
            f"compliance {res.compliance_before_J:.3g} -> {res.compliance_after_J:.3g} J, "
            f"peak von Mises {res.max_von_mises_after_pa / 1e6:.1f} MPa",
            fontsize=8,
        )
        ax.set_xlabel("x (m, link frame)")
        ax.set_ylabel("y (m)")
        ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=150)
    plt.close(fig)
    return out

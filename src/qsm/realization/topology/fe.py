"""Plane-stress finite elements of a link plate on a regular grid (pyMOTO): the settings and
material, grids, loads and supports, and one static analysis with von Mises stresses."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
from numpy.typing import ArrayLike, NDArray
from scipy.sparse.linalg import splu

from qsm.realization.topology.pymoto_quiet import pym
from qsm.schema.defaults import default


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
    youngs_modulus_pa, poisson_ratio, yield_strength_pa, safety_factor: the material's and the
    strength requirement's (:mod:`qsm.embodiment.strength.material`; the workflow passes the
    config's). threshold: density above which a cell is solid in the printed part, default 0.5.
    min_stiffness_factor: the least share of the solid plate's stiffness (its compliance over
    the printed plate's) a printed plate keeps, default 0.8.
    """

    volume_fraction: float = default("topology.volume_fraction")
    cell_size_m: float = default("topology.cell_size_m")
    max_iterations: int = default("topology.max_iterations")
    change_tol: float = default("topology.change_tol")
    penal: float = default("topology.penal")
    filter_radius_cells: float = default("topology.filter_radius_cells")
    move: float = default("topology.move")
    min_density: float = 1e-9
    youngs_modulus_pa: float = default("material.youngs_modulus_pa")
    poisson_ratio: float = default("material.poisson_ratio")
    yield_strength_pa: float = default("material.yield_strength_pa")
    safety_factor: float = default("strength.safety_factor")
    threshold: float = default("topology.threshold")
    min_stiffness_factor: float = default("topology.min_stiffness_factor")

    def __post_init__(self) -> None:
        if not 0.0 < self.volume_fraction <= 1.0:
            raise ValueError("volume_fraction must be in (0, 1]")
        if self.cell_size_m <= 0 or self.max_iterations < 1 or self.penal < 1:
            raise ValueError("need cell_size_m > 0, max_iterations >= 1, penal >= 1")
        if not 0.0 < self.threshold < 1.0:
            raise ValueError("threshold must be in (0, 1)")
        if not 0.0 < self.min_stiffness_factor <= 1.0:
            raise ValueError("min_stiffness_factor must be in (0, 1]")

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


def stiffness(
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


class SymmetricLU(pym.solvers.SolverSparseLU):
    """pyMOTO's sparse LU (SuperLU) with a symmetric fill-reducing ordering (minimum degree on
    A^T + A) and diagonal pivots, for the symmetric positive-definite stiffness matrices: 0.45x
    the time of pyMOTO's default (COLAMD ordering) on a 19,872-DOF plate, at the same residual
    (benchmarks/bench_topology.py)."""

    def update(self, A: sps.spmatrix) -> SymmetricLU:
        """Factorise ``A``."""
        self.iscomplex = False
        self.inv = splu(
            sps.csc_matrix(A),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
        return self


def linear_solve() -> pym.LinSolve:
    """pyMOTO's K u = f module with :class:`SymmetricLU`."""
    return pym.LinSolve(hermitian=True, solver=SymmetricLU())


def analyse(
    problem: FeProblem, density: ArrayLike, settings: TopologySettings, penal: float | None = None
) -> FeResult:
    """Linear static analysis of ``density`` (ny, nx) with SIMP stiffness (pyMOTO assembly);
    ``penal`` overrides the settings' exponent (1: stiffness proportional to cell fill)."""
    g, s = problem.grid, settings
    dom = g.domain(problem.thickness_m)
    rho = np.asarray(density, dtype=float).ravel()
    scale = s.min_density + (1 - s.min_density) * rho ** (s.penal if penal is None else penal)
    K = stiffness(dom, problem, s)(scale)
    u = linear_solve()(K, problem.forces)
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

"""SIMP topology optimisation of a link plate (pyMOTO): minimum compliance at a volume fraction,
density filter, optimality-criteria update."""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sps
from numpy.typing import NDArray

from qsm.realization.topology.fe import (
    DEFAULT_TOPOLOGY,
    FeProblem,
    TopologySettings,
    linear_solve,
    stiffness,
)
from qsm.realization.topology.pymoto_quiet import pym


@dataclass(frozen=True)
class SimpResult:
    """Physical (filtered) density (ny, nx), compliance history (J) and final volume fraction of
    the designable cells, and the iteration count."""

    density: NDArray[np.float64]
    history_J: NDArray[np.float64]
    volume_fraction: float
    iterations: int


def _oc_update(
    x: np.ndarray,
    dc: np.ndarray,
    x0: np.ndarray,
    design: np.ndarray,
    move: float,
    filt: tuple[sps.csr_matrix, np.ndarray],
    target: float,
) -> np.ndarray:
    """One optimality-criteria step from densities ``x`` with compliance sensitivities ``dc``
    (<= 0): the Lagrange multiplier bisected until the filtered (physical) volume of the
    ``design`` cells meets ``target`` (cells); cells outside ``design`` keep ``x0``."""
    filt_h, filt_hs = filt
    lo = np.maximum(0.0, x - move)
    hi = np.minimum(1.0, x + move)
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
    return xn


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
            K = stiffness(dom, problem, s)(xs)
            u = linear_solve()(K, sf)
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
            xn = _oc_update(x, dc, x0, design, s.move, (filt_h, filt_hs), target)
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

"""qsm: generative design of quasi-serial manipulators (Lee, Yang, Kang), as a plain library.

The Snakemake workflow in this repository calls these functions; tests and notebooks use them
directly. The names a notebook needs are importable from ``qsm`` itself (loaded on first use, so
``import qsm`` stays cheap):

* :func:`end_effector` (kinematics), :func:`joint_torques` (closed-chain MuJoCo dynamics);
* :func:`evaluate_ratios` (Stages 1 and 2 for one unit design), :func:`load_config`;
* :func:`load_surrogate` (a trained MLP), :func:`choose_design` (the design to realise),
  :func:`printing_advice`;
* :func:`containment_margin_m`, :func:`printability_violation_mm` (constraints g11 and g12).
"""

from __future__ import annotations

from importlib import import_module
from typing import Any

__version__ = "0.1.0"

#: The parts of ``qsm`` by layer, lowest first: a package, a top-level module, or a subpackage
#: (``realization.kit``). A layer imports only from the layers before it (tests/test_layers.py
#: holds the code to this).
LAYERS: tuple[tuple[str, ...], ...] = (
    ("schema", "prose"),  # the config schema and every setting's default; numbers in sentences
    ("physics",),  # kinematics, workspace, solids, MuJoCo dynamics, clearance
    ("mechanisms", "surrogate"),  # Stage 1 designs; the MLP
    ("embodiment",),  # parts and printability, strength, drives, stiffness; their columns
    ("dataset",),  # Stage 2: every domain's columns, one shard's table, the gathered table
    ("optimization",),  # NSGA-II, constraints, verification, ranking
    # Stage 6, operations on the one chosen design:
    ("realization.topology", "realization.motion"),  # plates (SIMP); payload test, cycle
    ("realization.accuracy",),  # the accuracy budget and the sizing for the tolerance
    ("realization.selection",),  # the choice, the realisation, the machine record
    ("realization.kit",),  # the builder's kit, the plates and STLs built with it
    ("realization.final",),  # the cycle checked, the final budget
    ("report",),  # records into prose and figures: headline, datasheet, drawings, pages
    ("design_rules",),  # Stage 5 and the study
    ("workflow",),  # tables, logs, shards, provenance: plumbing for the rules
    ("config",),  # reading and checking a config, its settings for the library
    ("app",),  # the command line and notebook calls: evaluate, locate and export a design
    ("__main__",),
)

_EXPORTS: dict[str, tuple[str, str]] = {
    "end_effector": ("qsm.physics.kinematics", "end_effector"),
    "joint_torques": ("qsm.physics.dynamics", "joint_torques"),
    "evaluate_ratios": ("qsm.app.evaluate", "evaluate_ratios"),
    "load_config": ("qsm.config.reading", "load_config"),
    "load_surrogate": ("qsm.surrogate.model", "load"),
    "choose_design": ("qsm.realization.selection.choice", "choose_design"),
    "printing_advice": ("qsm.realization.selection.choice", "printing_advice"),
    "containment_margin_m": ("qsm.optimization.constraints", "containment_margin_m"),
    "printability_violation_mm": ("qsm.embodiment.parts.printing", "printability_violation_mm"),
}
__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    try:
        module, attr = _EXPORTS[name]
    except KeyError:
        raise AttributeError(f"module 'qsm' has no attribute {name!r}") from None
    return getattr(import_module(module), attr)


def __dir__() -> list[str]:
    return sorted([*globals(), *__all__])

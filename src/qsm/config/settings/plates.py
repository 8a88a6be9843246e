"""Settings of the topology optimisation of the printed plates (Stage 6)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.realization.topology.fe import TopologySettings

Section = Mapping[str, Any]


def topology(
    section: Section, material_section: Section, strength_section: Section
) -> TopologySettings:
    """``topology`` with ``material``'s elasticity and strength and ``strength``'s safety
    factor: SIMP and the stress check of the printed plates."""
    return TopologySettings(
        **section,
        youngs_modulus_pa=material_section["youngs_modulus_pa"],
        poisson_ratio=material_section["poisson_ratio"],
        yield_strength_pa=material_section["yield_strength_pa"],
        safety_factor=strength_section["safety_factor"],
    )

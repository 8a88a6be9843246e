"""Settings of the surrogate (Stage 3) and of its adaptive infill (Stage 4)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.optimization.infill import InfillSettings
from qsm.surrogate.model import SurrogateSettings


def surrogate(section: Mapping[str, Any]) -> SurrogateSettings:
    """``surrogate``: network and training (its ``infill`` apart)."""
    net = {k: v for k, v in section.items() if k != "infill"}
    return SurrogateSettings(**{**net, "hidden_layers": tuple(net["hidden_layers"])})


def infill(section: Mapping[str, Any]) -> InfillSettings:
    """``surrogate.infill``: the rounds of true evaluations and refits after NSGA-II."""
    return InfillSettings(**section["infill"])

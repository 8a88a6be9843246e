"""Settings of the surrogate (Stage 3); its adaptive infill's are Stage 4's
(:func:`qsm.config.settings.optimization.infill`)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.surrogate.model import SurrogateSettings


def surrogate(section: Mapping[str, Any]) -> SurrogateSettings:
    """``surrogate``: network and training (its ``infill`` apart)."""
    net = {k: v for k, v in section.items() if k != "infill"}
    return SurrogateSettings(**{**net, "hidden_layers": tuple(net["hidden_layers"])})

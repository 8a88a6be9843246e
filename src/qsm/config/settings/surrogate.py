"""Settings of the surrogate (Stage 3)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from qsm.surrogate.model import SurrogateSettings


def surrogate(section: Mapping[str, Any]) -> SurrogateSettings:
    """``surrogate``: network and training."""
    return SurrogateSettings(**{**section, "hidden_layers": tuple(section["hidden_layers"])})

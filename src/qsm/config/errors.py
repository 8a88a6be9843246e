"""The error of a configuration value no run can use (:func:`qsm.config.checks.check_config`)."""

from __future__ import annotations


class ConfigError(ValueError):
    """A configuration value is missing, unknown, of the wrong type or out of range."""

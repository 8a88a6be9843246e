"""Configuration: the schema and its defaults, reading and checking a config, and the settings.

* ``config.schema.yaml``: every key, its type, bounds and default (the one source of defaults);
* :mod:`~qsm.config.defaults`: a key's default, for the library's dataclasses (lowest layer);
* :mod:`~qsm.config.reading`: read, merge and validate config files (:func:`load_config`);
* :mod:`~qsm.config.checks`, :mod:`~qsm.config.points`, :mod:`~qsm.config.drive_limits`: the
  checks across keys, each error naming its key (:class:`~qsm.config.errors.ConfigError`);
* :mod:`~qsm.config.settings`: the validated sections as the library's frozen settings.

This package imports nothing, so the physics can read a default without loading the checks.
"""

"""Configuration: reading and checking a config, and its sections as the library's settings.

* :mod:`~qsm.config.reading`: read, merge and validate config files (:func:`load_config`)
  against the schema (:mod:`qsm.schema`, the one source of defaults);
* :mod:`~qsm.config.checks`, :mod:`~qsm.config.points`, :mod:`~qsm.config.drive_limits`: the
  checks across keys, each error naming its key (:class:`~qsm.config.errors.ConfigError`);
* :mod:`~qsm.config.settings`: the validated sections as the library's frozen settings.

It sits above the library's computing packages, whose settings it builds; the schema and the
defaults sit below them all, in :mod:`qsm.schema`.
"""

"""The configuration schema (``config.schema.yaml``: every key, its type, bounds and default) and
:mod:`~qsm.schema.defaults`, a key's default for the library's dataclasses.

The lowest layer of ``qsm``: it imports no other package, so the physics can read a default
without loading the config checks.
"""

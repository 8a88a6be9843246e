"""The one settings layer: the validated config's sections as the library's frozen dataclasses.

One function per section, in a module per domain; scripts, the command line and
``qsm.app.evaluate`` build their settings here and nowhere else. A stage's ``*_of`` function
(``realization_of``, ``dataset_of``, ``front_of``, ``cycles_of``) takes a whole config or the
stage's share of one (:mod:`qsm.config.sections`, the rules' one param) and builds the same
settings from either.
Each function takes the section(s) as validated by :mod:`qsm.config.reading` (every default
filled from the schema) and passes every field on, so the schema's defaults are the ones a run
uses; the dataclasses' own defaults, for direct notebook calls, are read from the same schema
(:mod:`qsm.schema.defaults`).

Each module imports what it builds at its top, and this package imports none of them: a workflow
script's rerun hash (:mod:`qsm.workflow.provenance`) holds exactly the modules of the settings it
builds. :mod:`~qsm.config.settings.physics` (motor ranges, the scale-up, link solids, the duty),
:mod:`~qsm.config.settings.links` (material, strength, sizing, parts),
:mod:`~qsm.config.settings.actuation` (the drive catalogue and check),
:mod:`~qsm.config.settings.dataset` (Stage 2's checks together),
:mod:`~qsm.config.settings.surrogate`, :mod:`~qsm.config.settings.optimization` (a front's
NSGA-II, g11-g15 and true check),
:mod:`~qsm.config.settings.realization`, :mod:`~qsm.config.settings.plates` and
:mod:`~qsm.config.settings.simulation` (Stage 6, and the front's cycles).
"""

"""Physical embodiment of a design, by domain: :mod:`~qsm.embodiment.parts` (bearings, bored
link parts, printability, BOM), :mod:`~qsm.embodiment.strength` (loads, stresses, sizing,
the strength check) and :mod:`~qsm.embodiment.drives` (the catalogue and the drive check), each
importing only those before it.

Sits above :mod:`qsm.physics` (kinematics, solids, dynamics) and below the optimization, the
realization and the report, which use it to check that a design can be built.
"""

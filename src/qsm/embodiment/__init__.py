"""Physical embodiment of a design: link loads and strength, motor drives, bores and bearings.

Sits above :mod:`qsm.physics` (kinematics, solids, dynamics) and below the optimisation, the
realisation and the report, which use it to check that a design can be built.
"""

"""Topology optimisation of the printed plates: plane-stress finite elements (pyMOTO), SIMP, the
plates' peak loads, and the density field made a printable solid.

The package itself holds only :data:`OPTIMIZED_LINKS`, so that a module that needs to know which
plates are cut (the accuracy's sizing) does not import pyMOTO, whose import takes about 2 s."""

#: The links whose plates are topology-optimised.
OPTIMIZED_LINKS: tuple[str, ...] = ("lower_arm", "upper_arm")

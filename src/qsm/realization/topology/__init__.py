"""Topology optimisation of the printed plates: plane-stress finite elements (pyMOTO), SIMP, the
plates' peak loads, and the density field made a printable solid."""

"""Stage 4: constraints g11 and g12, NSGA-II on the surrogate, and the check of the fronts against
the physics."""

"""Stage 1: Latin-hypercube sampling, kinematic filters and the scale-up to the task."""

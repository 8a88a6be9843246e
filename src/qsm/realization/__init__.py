"""Stage 6: the choice of the design, printability, topology optimisation, export and the payload
test."""

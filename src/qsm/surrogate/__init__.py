"""Stage 3: the MLP surrogate of (eta, tau1, tau2)."""

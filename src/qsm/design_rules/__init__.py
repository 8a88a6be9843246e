"""Stage 5: Sobol indices, decision trees, correlations, eta derivatives and the findings against
the paper."""

"""Stage 1 and the dataset: Latin-hypercube sampling, kinematic filters, the scale-up to the task,
and the gathered dynamics."""

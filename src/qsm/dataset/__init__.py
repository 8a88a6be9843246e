"""Stage 2: every mechanism's closed-chain dynamics, link strength, drives and tool sag, as the
dataset's columns (:mod:`~qsm.dataset.columns`), one shard at a time
(:mod:`~qsm.dataset.evaluation`), gathered into one table (:mod:`~qsm.dataset.gathering`)."""

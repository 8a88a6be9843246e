"""The application: what the command line and a notebook call. :mod:`qsm.app.evaluate` evaluates
one design, :mod:`qsm.app.locate` finds a run's design, :mod:`qsm.app.export` writes one design's
files, and :mod:`qsm.app.cli` is the ``qsm`` command."""

"""qsm: generative design of quasi-serial manipulators (Lee, Yang, Kang), as a plain library.

The Snakemake workflow in this repository calls these functions; tests and notebooks use them
directly. Submodules: ``kinematics``, ``workspace``, ``task``, ``sampling``, ``filters``,
``mechanisms``, ``config``, ``tables``, ``evaluate``, ``plots``.
"""

__version__ = "0.1.0"

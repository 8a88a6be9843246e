"""pyMOTO, imported without the ``matplotlib.use("TkAgg")`` that pymoto 2.0.1 runs on import.

That call takes a notebook's backend away and fails without a display once pyplot is loaded, so
it is a no-op while pymoto is imported. Import ``pym`` from here, never pymoto directly.
"""

import matplotlib

_use, matplotlib.use = matplotlib.use, lambda *args, **kwargs: None
try:
    import pymoto as pym
finally:
    matplotlib.use = _use

__all__ = ["pym"]

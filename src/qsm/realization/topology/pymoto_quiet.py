"""pyMOTO, imported without two costs of pymoto 2.0.1, for the rest of ``qsm`` to use.

* Its import runs ``matplotlib.use("TkAgg")``, which takes a notebook's backend away and fails
  without a display once pyplot is loaded: that call is a no-op while pymoto is imported.
* Every module call records where it was made with ``inspect.stack()``, which reads the source
  of every frame on the stack: about 40 % of a SIMP run. The same location (file, line,
  function of the first frame outside ``pymoto.core_objects``) is read from the frames directly.

Import ``pym`` from here, never pymoto directly.
"""

from __future__ import annotations

import sys

import matplotlib

_use, matplotlib.use = matplotlib.use, lambda *args, **kwargs: None
try:
    import pymoto as pym
    from pymoto import core_objects
finally:
    matplotlib.use = _use


def _init_loc() -> tuple[str, int | str, str]:
    """``pymoto.core_objects.get_init_loc`` without reading source files: file, line and
    function of the innermost caller outside ``core_objects``."""
    frame = sys._getframe(1)
    while frame is not None and frame.f_code.co_filename == core_objects.__file__:
        frame = frame.f_back
    if frame is None:
        return "N/A", "N/A", "N/A"
    return frame.f_code.co_filename, frame.f_lineno, frame.f_code.co_name


core_objects.get_init_loc = _init_loc

__all__ = ["pym"]

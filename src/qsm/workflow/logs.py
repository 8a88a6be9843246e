"""Logging for workflow jobs: one log file per job, exceptions included."""

from __future__ import annotations

import logging
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def logged(path: str | Path, name: str = "qsm") -> Iterator[logging.Logger]:
    """Send the ``qsm`` loggers to ``path`` for the duration; log and re-raise any exception."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
    root = logging.getLogger("qsm")
    root.addHandler(handler)
    root.setLevel(logging.INFO)
    log = logging.getLogger(name)
    try:
        yield log
    except Exception:
        log.exception("failed")
        raise
    finally:
        root.removeHandler(handler)
        handler.close()

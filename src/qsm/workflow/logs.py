"""Logging for workflow jobs: one log file per job, exceptions included."""

from __future__ import annotations

import json
import logging
import os
import sys
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
        record_modules(path)


#: Environment variable naming a folder: when set, every job records the ``qsm`` modules it ran.
MODULES_ENV = "QSM_RECORD_MODULES"


def record_modules(log_path: str | Path) -> None:
    """When ``$QSM_RECORD_MODULES`` names a folder, write there (one JSON file per job, named
    after its log) the script that ran and the ``qsm`` modules it loaded: the test that holds
    each rule's rerun hash (:mod:`qsm.workflow.provenance`) to what its script really runs."""
    folder = os.environ.get(MODULES_ENV)
    if not folder:
        return
    name = str(log_path).replace("/", "__").replace("\\", "__")
    record = {
        "script": Path(sys.argv[0]).name,
        "modules": sorted(m for m in sys.modules if m == "qsm" or m.startswith("qsm.")),
    }
    Path(folder).mkdir(parents=True, exist_ok=True)
    (Path(folder) / f"{name}.json").write_text(json.dumps(record, indent=1))

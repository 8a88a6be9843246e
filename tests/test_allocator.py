"""The jobs' malloc settings (qsm.workflow.allocator): set for every job unless the user set
them, and effective: an inner loop's arrays no longer fault their pages in again."""

import os
import platform
import subprocess
import sys
from pathlib import Path

import pytest

from qsm.workflow.allocator import MALLOC_SETTINGS, set_job_malloc

# An inner loop's temporaries: three arrays of 6 MiB made and freed together, 100 times; prints
# the minor page faults that took.
LOOP = """
import resource
import numpy as np
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(100):
    a = np.ones((13, 600, 100))
    b = 2 * a
    c = np.sqrt(b)
    del a, b, c
print(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
"""


def test_the_settings_go_to_every_job_unless_the_user_set_them():
    environ = {"MALLOC_TRIM_THRESHOLD_": "0"}
    set_job_malloc(environ)
    assert environ["MALLOC_TRIM_THRESHOLD_"] == "0"
    assert environ["MALLOC_MMAP_THRESHOLD_"] == MALLOC_SETTINGS["MALLOC_MMAP_THRESHOLD_"]


def test_the_workflow_sets_them_before_its_jobs_start():
    """workflow/Snakefile calls it on os.environ, which the jobs inherit."""
    snakefile = Path(__file__).resolve().parents[1] / "workflow" / "Snakefile"
    assert "set_job_malloc(os.environ)" in snakefile.read_text()


def _faults(environ):
    out = subprocess.run(
        [sys.executable, "-c", LOOP], env=environ, capture_output=True, text=True, check=True
    )
    return int(out.stdout)


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="glibc's malloc settings")
def test_a_loops_arrays_reuse_the_heap():
    """By default glibc maps each array and faults its 1,536 pages in again at every turn; with
    the settings the heap serves them after the first: at least ten times fewer faults."""
    bare = {k: v for k, v in os.environ.items() if not k.startswith("MALLOC_")}
    tuned = dict(bare)
    set_job_malloc(tuned)
    assert 10 * _faults(tuned) < _faults(bare)

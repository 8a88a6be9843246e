"""glibc malloc's thresholds for the workflow's jobs (environment variables, read at a process's
start; ignored by other C libraries).

By default glibc serves a block of 128 KiB or more with its own ``mmap`` and gives the pages back
to the system when it is freed, raising that threshold only as such blocks are freed, and trims
the heap's top whenever 128 KiB lie free there. The jobs allocate and free numpy arrays of a few
MB in their inner loops (the workspace slicing, SIMP's solves, the motion planning), so each
array's pages were faulted in again and zeroed: on the default DAG that was about a sixth of
the job seconds. Blocks up to 32 MiB now come from the heap and up to 64 MiB of free heap is
kept for reuse; larger blocks are mapped and returned as before, so a job's peak memory grows by
at most that much (benchmarks/LOG.md).
"""

from __future__ import annotations

from collections.abc import MutableMapping

#: The jobs' malloc settings (bytes): the size from which a block is mapped on its own, and the
#: free heap kept before it is trimmed.
MALLOC_SETTINGS = {
    "MALLOC_MMAP_THRESHOLD_": str(32 << 20),
    "MALLOC_TRIM_THRESHOLD_": str(64 << 20),
}


def set_job_malloc(environ: MutableMapping[str, str]) -> None:
    """Put :data:`MALLOC_SETTINGS` into ``environ`` (the workflow's ``os.environ``, which every
    job inherits, locally and under SLURM), keeping any value the user set."""
    for name, value in MALLOC_SETTINGS.items():
        environ.setdefault(name, value)

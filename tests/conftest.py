"""Shared fixtures: one complete Snakemake run of config/test.yaml for the whole session, shared
by pytest-xdist's workers."""

import pytest
from filelock import FileLock
from workflow_helpers import copy_workflow, snakemake

from qsm.workflow.logs import MODULES_ENV

#: Written in the run's folder when its Snakemake run has finished.
DONE = ".run-finished"


@pytest.fixture(scope="session")
def run(tmp_path_factory, worker_id):
    """A finished run of the default target; tests read it and must not change it. Each job
    records the ``qsm`` modules it ran in ``modules/`` (tests/test_provenance.py). Under
    pytest-xdist the first worker that asks runs it and the others wait for it (the pattern of
    pytest-xdist's documentation), so the session pays for one run."""
    if worker_id == "master":  # one process: its own folder
        work = copy_workflow(tmp_path_factory.mktemp("wf"))
        snakemake(work, env={MODULES_ENV: str(work / "modules")})
        return work
    work = tmp_path_factory.getbasetemp().parent / "shared-run"  # this session's, per worker
    with FileLock(f"{work}.lock"):
        if not (work / DONE).is_file():
            copy_workflow(work)
            snakemake(work, env={MODULES_ENV: str(work / "modules")})
            (work / DONE).touch()
    return work


def pytest_collection_modifyitems(items):
    """Every test that reads the shared run is a workflow test (it starts Snakemake)."""
    for item in items:
        if "run" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.workflow)

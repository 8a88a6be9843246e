"""Shared fixtures: one complete Snakemake run of config/test.yaml for the whole session."""

import pytest
from workflow_helpers import copy_workflow, snakemake

from qsm.workflow.logs import MODULES_ENV


@pytest.fixture(scope="session")
def run(tmp_path_factory):
    """A finished run of the default target; tests read it and must not change it. Each job
    records the ``qsm`` modules it ran in ``modules/`` (tests/test_provenance.py)."""
    work = copy_workflow(tmp_path_factory.mktemp("wf"))
    snakemake(work, env={MODULES_ENV: str(work / "modules")})
    return work


def pytest_collection_modifyitems(items):
    """Every test that reads the shared run is a workflow test (it starts Snakemake)."""
    for item in items:
        if "run" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.workflow)

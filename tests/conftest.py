"""Shared fixtures: one complete Snakemake run of config/test.yaml for the whole session."""

import pytest
from workflow_helpers import copy_workflow, snakemake


@pytest.fixture(scope="session")
def run(tmp_path_factory):
    """A finished run of the default target; tests read it and must not change it."""
    work = copy_workflow(tmp_path_factory.mktemp("wf"))
    snakemake(work)
    return work

"""The workflow used as a Snakemake module by another directory, with the catalog's test config.

This is how ``snakedeploy deploy-workflow`` sets a user up: a Snakefile of their own that names
``workflow/Snakefile`` of this repository as a module and passes it their config. The run here
is real (not a dry run): ``.test/config/config.yaml`` end to end, in a directory that holds only
that Snakefile and the config.
"""

import os
import shutil
import subprocess
import sys

import pytest
from workflow_helpers import copy_workflow

pytestmark = pytest.mark.workflow

USER_SNAKEFILE = """\
configfile: "config/config.yaml"


module qsm:
    snakefile:
        "{snakefile}"
    config:
        config


use rule * from qsm
"""


def test_another_directory_runs_the_test_config_through_the_module(tmp_path):
    checkout = copy_workflow(tmp_path / "qsm-design")
    user = tmp_path / "my-project"
    (user / "config").mkdir(parents=True)
    shutil.copy2(checkout / ".test/config/config.yaml", user / "config/config.yaml")
    (user / "Snakefile").write_text(
        USER_SNAKEFILE.format(snakefile=checkout / "workflow" / "Snakefile")
    )
    # the jobs import the copy's qsm, whichever qsm the environment has installed
    env = {**os.environ, "PYTHONPATH": str(checkout / "src")}
    out = subprocess.run(
        [sys.executable, "-m", "snakemake", "--cores", "2"],
        cwd=user,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    results = user / "results"
    assert any(line.startswith("**") for line in (results / "summary.md").read_text().splitlines())
    for page in ("summary", "comparison", "design_rules", "torques", "surrogate"):
        assert (results / "html" / f"{page}.html").stat().st_size > 0
    assert (results / "realization/payload_test.json").exists()
    assert not (checkout / "results").exists()  # results go to the user's directory only

"""README's own-task commands, run as written from a copy of the checkout: the task file, the
config check, the run in its own directory and the report. The run takes README's documented
combination with the test config (``--configfile config/config.yaml config/test.yaml
my_task.yaml``), so that it finishes in a test's time; everything else is README's text."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from workflow_helpers import ROOT, copy_workflow

pytestmark = pytest.mark.workflow

README = (ROOT / "README.md").read_text()


def own_task_block() -> str:
    """README's bash block that writes my_task.yaml and runs it."""
    blocks = re.findall(r"```bash\n(.*?)```", README, flags=re.S)
    return next(b for b in blocks if "cat > my_task.yaml" in b)


def commands(block: str) -> list[str]:
    """The block's command lines after its heredoc, comments dropped."""
    tail = block.split("\nYAML\n", 1)[1]
    return [line.split("#")[0].strip() for line in tail.splitlines() if line.split("#")[0].strip()]


def run(cwd: Path, line: str) -> subprocess.CompletedProcess:
    """One README command line, with ``snakemake`` and ``qsm`` as modules of this Python."""
    words = shlex.split(line)
    program = {"snakemake": "snakemake", "qsm": "qsm"}[words[0]]
    out = subprocess.run(
        [sys.executable, "-m", program, *words[1:]],
        cwd=cwd,
        capture_output=True,
        text=True,
        check=False,
    )
    assert out.returncode == 0, f"{line}\n{out.stdout[-3000:]}\n{out.stderr[-3000:]}"
    return out


def test_readme_own_task_commands_run_as_written(tmp_path):
    work = copy_workflow(tmp_path / "checkout")
    block = own_task_block()
    yaml_text = block.split("<<'YAML'\n", 1)[1].split("\nYAML\n", 1)[0]
    (work / "my_task.yaml").write_text(yaml_text + "\n")
    check, snake = commands(block)
    combined = "--configfile config/config.yaml config/test.yaml my_task.yaml"
    assert combined in README.replace("\n", " ")  # README documents the combination
    run(work, check)
    run(
        work,
        snake.replace(
            "config/config.yaml my_task.yaml", "config/config.yaml config/test.yaml my_task.yaml"
        ),
    )
    summary = (work / "runs/my_task/results/summary.md").read_text()
    assert summary.startswith("# qsm-design") and "my_task" not in str(work / "results")
    report = re.search(r"\*\*The report\.\*\* `(snakemake [^`]*)`", README.replace("\n", " "))
    line = report.group(1).replace(
        "config/config.yaml my_task.yaml", "config/config.yaml config/test.yaml my_task.yaml"
    )
    run(work, line)
    with zipfile.ZipFile(work / "runs/my_task/results/report.zip") as archive:
        assert any(n.endswith("summary.html") for n in archive.namelist())

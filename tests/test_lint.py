"""Lint gates, run as tests so that README's one test command enforces them."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize(
    "command",
    [
        [sys.executable, "-m", "ruff", "check", "."],
        [sys.executable, "-m", "ruff", "format", "--check", "."],
        [
            sys.executable,
            "-m",
            "snakefmt",
            "--check",
            "Snakefile",
            "workflow/Snakefile",
            "workflow/rules",
        ],
    ],
    ids=["ruff-check", "ruff-format", "snakefmt"],
)
def test_lint(command):
    out = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=False)
    assert out.returncode == 0, out.stdout + out.stderr

"""Run the Snakemake workflow on a copy of the repository in a temporary directory."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def copy_workflow(dest: Path) -> Path:
    """Copy what a run needs (Snakefile, workflow, config, .test, profiles, src) into ``dest``
    (config/test.yaml links to .test/config/config.yaml)."""
    dest.mkdir(parents=True, exist_ok=True)
    shutil.copy2(ROOT / "Snakefile", dest / "Snakefile")
    for name in ("workflow", "config", ".test", "profiles", "src"):
        shutil.copytree(
            ROOT / name,
            dest / name,
            symlinks=True,
            ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"),
        )
    return dest


def snakemake(
    workdir: Path,
    *args: str,
    check: bool = True,
    configs: tuple[str, ...] = (),
    env: dict[str, str] | None = None,
) -> subprocess.CompletedProcess:
    """Run ``snakemake`` in ``workdir`` with the test config (and ``configs`` over it), with
    ``env`` added to the environment."""
    cmd = [sys.executable, "-m", "snakemake", *args]
    if "--cores" not in args and "--profile" not in args:
        cmd += ["--cores", "2"]
    cmd += ["--configfile", "config/test.yaml", *configs]  # last: it takes several values
    out = subprocess.run(
        cmd,
        cwd=workdir,
        capture_output=True,
        text=True,
        check=False,
        env={**os.environ, **(env or {})},
    )
    if check and out.returncode != 0:
        raise AssertionError(f"snakemake {' '.join(args)} failed:\n{out.stdout}\n{out.stderr}")
    return out


def copy_run(run: Path, dest: Path) -> Path:
    """A copy of a finished run (results and Snakemake's metadata included) to change freely."""
    shutil.copytree(run, dest, symlinks=True)
    return dest


def planned_jobs(workdir: Path, *args: str, configs: tuple[str, ...] = ()) -> dict[str, int]:
    """Rules a dry run would execute, with their job counts (empty when nothing is to be done)."""
    out = snakemake(workdir, "--dry-run", *args, configs=configs)
    text = out.stdout + out.stderr
    if "Nothing to be done" in text:
        return {}
    lines = text.split("Job stats:", 1)[1].splitlines()[3:]
    jobs = {}
    for line in lines:
        parts = line.split()
        if not parts or parts[0] == "total":
            break
        jobs[parts[0]] = int(parts[1])
    return jobs


def assert_one_machine(work: Path) -> None:
    """The outputs of the finished run in ``work`` describe one machine: ``selected.json``,
    ``machine.json``, ``summary.md``, ``datasheet.md``, ``bom.csv``, ``kit.json`` and
    ``topology.json`` name the same drives, bearings, sections, printed masses, placing error
    and verdict."""
    import json

    import pandas as pd
    import pytest

    from qsm.embodiment.drives.report import drive_of

    res = work / "results"
    real = res / "realization"
    selected = json.loads((real / "selected.json").read_text())
    machine = json.loads((real / "machine.json").read_text())
    topology = json.loads((real / "topology.json").read_text())
    kit = json.loads((real / "kit/kit.json").read_text())
    bom = pd.read_csv(real / "bom.csv")
    summary, datasheet = (res / "summary.md").read_text(), (res / "datasheet.md").read_text()
    assert selected["drives"] == machine["drives"] and selected["strength"] == machine["strength"]
    for k, motor in enumerate(selected["drives"]["motors"].values(), start=1):
        drive = drive_of(motor)
        name = f"{drive['motor']} + {drive['gearbox']}"
        assert name in summary and name in datasheet, name
        assert kit["drives"][k - 1]["drive"] == name
        row = bom.set_index("item").loc[f"motor {k}"]
        assert row["designation"] == drive["motor"]
        assert row["mass_kg"] == pytest.approx(drive["mass_kg"], rel=1e-9)  # bom.csv: 10 digits
    built = bom.loc[bom["category"] == "bearing"].set_index("where")["designation"]
    for joint, designation in built.items():
        assert designation.endswith(selected["strength"]["bearings"][joint]["designation"])
    printed = bom.loc[bom["category"] == "printed part"].set_index("item")
    for link, r in selected["strength"]["links"].items():
        section = topology["parts"]["section_mm"][link]
        assert section == pytest.approx([r["width_mm"], r["thickness_mm"]], rel=1e-9)
        assert printed.loc[link, "bbox_z_mm"] == round(r["thickness_mm"], 1)
        assert printed.loc[link, "mass_kg"] == pytest.approx(
            topology["parts"]["masses_kg"][link], rel=1e-9
        )
    weighed = bom.dropna(subset=["mass_kg"])  # the BOM's own sum, not the datasheet's code
    total = float((weighed["mass_kg"] * weighed["quantity"]).sum())
    assert f"{total:.2f} kg as built" in datasheet
    budget = selected.get("stiffness")
    if budget is not None:
        worst = max(budget["per_point"]["error_budget_mm"])
        stated = re.search(r"\| placing error \| ([0-9.]+) mm worst", datasheet)
        # two decimals, at most four significant digits (qsm.prose.fixed)
        assert stated and abs(float(stated.group(1)) - worst) <= 0.005 + 5e-4 * worst
    verdict = summary.split("\n\n")[1]
    assert verdict.startswith("**") and verdict.split("\n")[0] in datasheet
    if "What fails, worst first:" in summary:  # the same lines head both, each with its ratio
        lines = summary.split("What fails, worst first:\n\n")[1].split("\n\n")[0]
        assert lines in datasheet and lines.startswith("1. ")
    _assert_sized_as_printed(real, selected, machine, topology, kit, datasheet)


def _assert_sized_as_printed(real, selected, machine, topology, kit, datasheet) -> None:
    """The arm as printed is the arm as sized: each cut plate keeps the stiffness factor the
    sections were sized with (``topology.min_stiffness_factor``, the default 0.8), the tool
    flange the realisation carried is the kit's and the payload test's, and the kit is checked
    at the drives' torque limits, which the datasheet states."""
    import json

    import pytest

    for name, link in topology["links"].items():
        if not link["kept_solid"]:
            assert link["compliance_before_J"] / link["compliance_after_J"] >= 0.8 - 1e-12, name
    assert kit["tool_flange"] == selected["tool_flange"] == machine["tool_flange"]
    payload = json.loads((real / "payload_test.json").read_text())
    assert (
        payload["tool_flange_kg"]
        == selected["tool_flange_kg"]
        == machine["fixed_point"]["tool_kg"][-1]
    )
    limits = selected["torque_limits_Nm"]
    assert limits == machine["torque_limits_Nm"]
    assert [h["torque_Nm"] for h in kit["hubs"]] == pytest.approx(limits, rel=1e-12)
    assert " / ".join(f"{v:.1f}" for v in limits) + " N m" in datasheet

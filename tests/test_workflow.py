"""Snakemake itself on config/test.yaml: outputs, their provenance and shard-count invariance."""

import copy
import json
import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import trimesh
import yaml
from datasheet_lines import check_lines, run_records
from prose_checks import assert_plain_numbers
from workflow_helpers import (
    ROOT,
    assert_one_machine,
    copy_run,
    copy_workflow,
    planned_jobs,
    snakemake,
)

from qsm.app.evaluate import evaluate_ratios
from qsm.config.reading import validate_config
from qsm.config.settings import links, physics
from qsm.dataset.columns import DATASET_COLUMNS
from qsm.embodiment.drives.catalogue import load_catalogue
from qsm.embodiment.drives.envelope import OutputEnvelope
from qsm.embodiment.parts.printing import all_links_fit
from qsm.mechanisms.filters import kinematic_filters
from qsm.mechanisms.sampling import latin_hypercube
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.optimization.comparison import summary
from qsm.optimization.verify import verify_design
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import evaluate_mechanism
from qsm.physics.inverse_kinematics import joint_path
from qsm.physics.kinematics import DESIGN_COLUMNS, end_effector
from qsm.physics.task_points import task_cycle
from qsm.physics.workspace import OperatingRange
from qsm.realization.motion.cycle import top_speed
from qsm.report.headline import headline_markdown
from qsm.surrogate.model import INPUTS
from qsm.surrogate.model import load as load_surrogate
from qsm.workflow.tables import read_meta, read_table, settings_hash

pytestmark = pytest.mark.workflow


def effective_config(work):
    config = yaml.safe_load((work / "config" / "config.yaml").read_text())
    for key, value in yaml.safe_load((work / "config" / "test.yaml").read_text()).items():
        config[key] = {**config.get(key, {}), **value}
    return validate_config(config)


def test_mechanism_table(run):
    config = effective_config(run)
    table = read_table(run / "results/mechanisms/mechanisms.parquet", MECHANISM_COLUMNS)
    assert list(table.columns) == list(MECHANISM_COLUMNS)
    assert len(table) == config["sampling"]["n_mechanisms"] == 100
    assert table["mechanism_id"].is_unique and table["mechanism_id"].is_monotonic_increasing
    meta = read_meta(run / "results/mechanisms/mechanisms.parquet")
    assert set(meta["columns"]) == set(MECHANISM_COLUMNS)
    workspace = {k: v for k, v in config["workspace"].items() if k != "shards"}
    expected = {k: config[k] for k in ("sampling", "operating_range", "filters", "scale")}
    expected["task_points"] = config["task"]["points"]
    assert meta["settings_hash"] == settings_hash({**expected, "workspace": workspace})
    # a few rows re-evaluated from their ratios through the public API
    for _, row in table.sample(5, random_state=0).iterrows():
        again = evaluate_ratios(row[["l2", "l3", "l4", "ee_x", "ee_y"]].to_numpy(float), config)
        assert again["feasible"]
        assert again["scale"] == pytest.approx(row["scale_m"], rel=1e-9)
        assert again["eta"] == pytest.approx(row["eta"], rel=1e-9)


def test_filter_report_counts(run):
    config = effective_config(run)
    report = json.loads((run / "results/mechanisms/filter_report.json").read_text())
    s = config["sampling"]
    samples = latin_hypercube(s["n_samples"], s["bounds"], s["seed"])
    op = OperatingRange.from_degrees(config["operating_range"]["theta1_deg"], -37.5)
    _, counts = kinematic_filters(samples, op, 0.0)
    for key, value in counts.items():
        assert report[key] == value
    failures = sum(report["task_fit_failures"].values())
    assert report["task_fits"] + failures == report["task_fit_examined"]
    assert report["selected"] == 100 and report["shortfall"] == 0
    # the shards stop early; the counts cover every candidate up to the last one selected
    candidates = pd.read_parquet(run / "results/mechanisms/candidates.parquet")
    last = pd.read_parquet(run / "results/mechanisms/mechanisms.parquet")["mechanism_id"].max()
    assert len(candidates) == report["transmission_angle"]
    assert report["task_fit_examined"] == (candidates["sample_id"] <= last).sum()
    assert report["task_fit_examined"] < report["transmission_angle"]
    log = (run / "results/logs/filter_kinematics.log").read_text().splitlines()
    assert any(line.split()[-2:] == ["loop_closes", str(report["loop_closes"])] for line in log)


def test_figures_and_logs(run):
    for name in ("mechanism_examples.png", "scale_eta.png"):
        assert (run / "results/figures" / name).stat().st_size > 10_000
    assert "designs/s" in (run / "results/logs/fit_task/shard-0.log").read_text()


def test_dataset(run):
    mechanisms = read_table(run / "results/mechanisms/mechanisms.parquet")
    dataset = read_table(run / "results/dataset.parquet", DATASET_COLUMNS)
    assert list(dataset.columns) == list(DATASET_COLUMNS)
    assert list(dataset["mechanism_id"]) == list(mechanisms["mechanism_id"])
    pd.testing.assert_frame_equal(dataset[list(MECHANISM_COLUMNS)], mechanisms)
    status = json.loads((run / "results/dynamics/status.json").read_text())
    assert sum(status["status"].values()) == len(dataset) == 100
    assert status["status"] == dataset["status"].value_counts().to_dict()
    ok = dataset["status"] == "ok"
    assert (dataset.loc[ok, ["tau1_Nm", "tau2_Nm"]] > 0).all().all()
    assert (dataset.loc[ok, "tau1_Nm"] >= dataset.loc[ok, "tau1_rms_Nm"]).all()
    assert "mechanisms/s" in (run / "results/logs/dynamics/shard-0.log").read_text()
    assert (run / "results/figures/performance.png").stat().st_size > 10_000


def test_second_run_has_nothing_to_do(run):
    out = snakemake(run, "--dry-run")
    assert "Nothing to be done" in out.stdout + out.stderr


def test_same_tables_whatever_the_shard_count(run, tmp_path):
    other = copy_workflow(tmp_path / "other")
    test = yaml.safe_load((other / "config/test.yaml").read_text())
    test["workspace"]["shards"] = 3
    test["dynamics"] = {"shards": 1}
    (other / "config/test.yaml").write_text(yaml.safe_dump(test))
    snakemake(other, "gather_dataset", "--cores", "1")
    assert len(list((other / "results/mechanisms/fits").glob("shard-*.parquet"))) == 3
    assert len(list((other / "results/dynamics").glob("shard-*.parquet"))) == 1
    for name in ("mechanisms/mechanisms.parquet", "dataset.parquet"):
        a = read_table(run / "results" / name)
        b = read_table(other / "results" / name)
        pd.testing.assert_frame_equal(a, b, check_exact=True)
        hashes = {read_meta(w / "results" / name)["settings_hash"] for w in (run, other)}
        assert len(hashes) == 1


def test_task_no_design_can_reach_fails_with_the_key_named(tmp_path):
    work = copy_workflow(tmp_path / "far")
    test = yaml.safe_load((work / "config/test.yaml").read_text())
    # within the family's reach ratio (9.5 of 10.2), so the config checks pass it, but too
    # thin an annulus for any sampled design
    test["task"] = {"points": [[-0.063, 0.0], [-0.6, 0.0]]}
    (work / "config/test.yaml").write_text(yaml.safe_dump(test))
    out = snakemake(work, "select_mechanisms", check=False)
    assert out.returncode != 0
    log = (work / "results/logs/select_mechanisms.log").read_text()
    assert "task.points" in log
    # what was computed before the failing rule is kept
    assert (work / "results/mechanisms/candidates.parquet").exists()


def test_surrogate_outputs(run):
    metrics = json.loads((run / "results/surrogate/metrics.json").read_text())
    for split in ("train", "test"):
        for metric in ("r2", "mse", "rmse"):
            assert set(metrics[split][metric]) == {"eta", "tau1", "tau2", "all"}
    assert metrics["fit_seconds"] > 0
    model = load_surrogate(run / "results/surrogate/model.json")
    dataset = read_table(run / "results/dataset.parquet")
    pred = model.predict(dataset[list(INPUTS)].to_numpy())
    assert pred.shape == (len(dataset), 3) and np.isfinite(pred).all()
    assert "| test | all |" in (run / "results/surrogate/metrics.md").read_text()


@pytest.mark.parametrize("formulation", ["paper", "ratios"])
def test_verification_matches_a_direct_reevaluation(run, formulation):
    config = effective_config(run)
    folder = run / "results/optimization" / formulation
    table = read_table(folder / "verification.parquet")
    pareto = read_table(folder / "pareto.parquet")
    assert len(table) == len(pareto) > 0
    pd.testing.assert_frame_equal(table[list(pareto.columns)], pareto)
    stored = json.loads((folder / "verification.json").read_text())
    assert stored.pop("formulation") == formulation and "g1..g10" in stored.pop("constraints")
    assert stored.pop("infill")["rounds"]  # the infill's rounds: checked beside
    assert json.dumps(stored, sort_keys=True) == json.dumps(summary(table), sort_keys=True)
    fit = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    duty = duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    for _, row in table.head(3).iterrows():
        design = row[list(INPUTS)].to_numpy(float)
        direct = verify_design(
            design, fit, duty, physics.cad(config["cad"], config["material"]), 5.0
        )
        for key in ("feasible", "eta_true", "tau1_true_Nm", "tau2_true_Nm"):
            assert direct[key] == pytest.approx(row[key], rel=1e-12, nan_ok=True)
    assert stored["holds_task_share"] == table["task_contained"].mean()
    cad = physics.cad(config["cad"], config["material"])
    volume = tuple(config["printing"]["build_volume_mm"])
    printable = [all_links_fit(d, cad, volume) for d in table[list(INPUTS)].to_numpy(float)]
    assert stored["printable_share"] == pytest.approx(np.mean(printable))
    # g11 and g12 on by default: the test run's fronts truly hold the task and can be printed
    assert stored["holds_task_share"] == 1.0 and stored["printable_share"] == 1.0
    if formulation == "ratios":  # exact Stage 1: every design holds the task at its scale
        assert table["feasible"].all()
        row = table.iloc[0]
        # the ratios formulation fits the scale to the task disk grown by the g11 tolerance
        grown = copy.deepcopy(config)
        grown["scale"]["safety_margin_m"] += config["optimization"]["constraints"][
            "containment_tolerance_m"
        ]
        again = evaluate_ratios(row[["l2", "l3", "l4", "ee_x", "ee_y"]].to_numpy(float), grown)
        assert again["scale"] == pytest.approx(row["scale_m"], rel=1e-9)
        assert again["eta"] == pytest.approx(row["eta_true"], rel=1e-9)
        assert again["tau1_Nm"] == pytest.approx(row["tau1_true_Nm"], rel=1e-9)
    comparison = json.loads((run / "results/optimization/comparison.json").read_text())
    assert set(comparison["fronts"]) == {"paper", "ratios"}


def test_design_rules_outputs(run):
    config = effective_config(run)
    rules = run / "results/design_rules"
    n = config["design_rules"]["sobol_n"]
    assert read_meta(rules / "sobol.parquet")["n_evaluations"] == n * (2 * 6 + 2)
    designs = read_table(rules / "designs_400.parquet")
    front = run / "results/optimization" / config["optimization"]["formulation"]
    pareto = read_table(front / "pareto.parquet")
    gens = read_table(front / "last_generations.parquet")
    assert len(designs) == len(pareto) + len(gens)  # 400 with the paper's population
    assert gens["generation"].nunique() == 3
    splits = json.loads((rules / "tree_first_splits.json").read_text())
    assert splits["n_designs"] == len(designs)
    table = read_table(rules / "correlations.parquet")
    row = table[(table["a"] == "tau1_pred_Nm") & (table["b"] == "tau2_pred_Nm")].iloc[0]
    direct = np.corrcoef(designs["tau1_pred_Nm"], designs["tau2_pred_Nm"])[0, 1]
    assert row["pearson"] == pytest.approx(direct, rel=1e-12)
    grads = read_table(rules / "eta_derivatives.parquet")
    assert len(grads) == 100 and grads["mechanism_id"].is_unique
    assert "mechanisms/s" in (run / "results/logs/eta_derivatives/shard-0.log").read_text()
    summary_md = (rules / "summary.md").read_text()
    findings_md = summary_md.split("## Table 3 sweep")[0]
    rows = [ln for ln in findings_md.splitlines() if ln.startswith("| ") and "---" not in ln]
    assert len(rows) == 1 + 11  # header, the paper's Section 4 findings and its Table 3
    assert f"{n * 14:,} surrogate evaluations" in summary_md
    table = read_table(rules / "findings.parquet")
    # every verdict rests on an experiment of this run, whose outcome carries its numbers
    assert not table["verdict"].str.startswith("unexplained").any()
    assert table["measured outcome"].str.contains(r"\d").all()
    sweep = read_table(run / "results/study/table3_sweep.parquet")
    assert list(sweep["payload_kg"]) == config["study"]["payloads_kg"]
    lengths = read_table(run / "results/study/independent_lengths.parquet")
    assert 0 < len(lengths) <= config["study"]["n_designs"]


def test_the_cycle_is_within_the_drives_and_no_faster_than_their_top_speeds(run):
    """An independent check of results/realization/cycle.json and its trajectory: each move no
    shorter than its largest joint change over that drive's top speed, the torques within each
    drive's envelope at their speed (TOPP-RA's grid: 2 %), and MuJoCo's run within the limits."""
    real = run / "results/realization"
    cycle = json.loads((real / "cycle.json").read_text(), parse_constant=_no_constant)
    trajectory = pd.read_csv(real / "cycle_trajectory.csv")
    choice = json.loads((real / "choice.json").read_text())
    catalogue = load_catalogue()
    drives = [
        OutputEnvelope.of(catalogue, m["drive"]["motor_key"], m["drive"]["gearbox_key"])
        for m in choice["drives"]["motors"].values()
    ]
    change = np.abs(np.diff(np.radians(cycle["waypoints_deg"]), axis=0))
    top = np.array([top_speed(e) for e in drives])
    for move, least in zip(cycle["moves"], (change / top).max(axis=1), strict=True):
        assert move["time_s"] >= least
    for j, drive in enumerate(drives):
        speed = np.radians(trajectory[f"omega{j + 1}_deg_s"].to_numpy())
        tau = trajectory[f"tau{j + 1}_Nm"].to_numpy()
        assert (np.abs(speed) <= top[j] * (1 + 1e-7)).all()  # the CSV's 8 digits
        assert (np.abs(tau) <= drive.limit(tau, speed) * 1.02 + 1e-9).all()
    sim = cycle["simulation"]
    if sim["passed"]:
        assert max(u for u in sim["peak_torque_over_available"] if u is not None) <= 1.0
    assert cycle["cycles_per_hour"] == pytest.approx(3600 / cycle["cycle_time_s"])
    assert cycle["time_optimal_s"] <= cycle["cycle_time_s"]
    # each stop dwells the gripper's time, or until the arm settles where that is longer, and
    # the cycle's time counts the dwells; the trajectory's jerk stays within each move's limit
    for stop, dwell in zip(cycle["settling"], cycle["dwells_s"], strict=True):
        settle = stop["settling_s"]
        assert dwell == pytest.approx(max(cycle["dwell_s"], settle or 0.0))
    moves = sum(m["time_s"] for m in cycle["moves"])
    assert cycle["cycle_time_s"] == pytest.approx(moves + sum(cycle["dwells_s"]), abs=1e-9)
    for m in cycle["moves"]:
        peak, limit = np.asarray(m["peak_jerk_rad_s3"]), np.asarray(m["jerk_limit_rad_s3"])
        assert (peak <= limit * (1 + 1e-9)).all()  # the ramps as run reach it, to rounding


def test_each_front_design_s_cycle_is_no_faster_than_its_drives_top_speeds(run):
    """An independent check of the primary front's time-optimal cycles: each no shorter than
    the dwells plus, per move, its largest joint change over that drive's top speed; a design
    without a cycle says why, and only such a design."""
    opt = run / "results/optimization" / effective_config(run)["optimization"]["formulation"]
    verified = read_table(opt / "verification.parquet")
    cycles = read_table(opt / "cycles.parquet")
    config = effective_config(run)
    op = config["operating_range"]
    test = config["payload_test"]
    task = task_cycle(
        config["task"]["points"], config["task"]["cycle"], test["dwell_s"], test["return_to_start"]
    )
    catalogue = load_catalogue()
    planned = np.isfinite(cycles["time_optimal_cycle_s"].to_numpy())
    assert planned.any()
    assert (cycles.loc[~planned, "cycle_note"].str.len() > 0).all()
    assert (cycles.loc[planned, "cycle_note"] == "").all()
    for k in np.flatnonzero(planned):
        row = verified.iloc[k]
        d = row[list(DESIGN_COLUMNS)].to_numpy(float)
        drives = [OutputEnvelope.of(catalogue, row[f"drive{j}_motor"], row[f"drive{j}_gearbox"])
                  for j in (1, 2)]  # fmt: skip
        top = np.array([top_speed(e) for e in drives])
        angles = joint_path(d, np.asarray(task.points), op["theta1_deg"], op["theta2_min_deg"])
        least = (np.abs(np.diff(angles, axis=0)) / top).max(axis=1).sum()
        dwells = task.dwell_s * (len(task.visits) - 1)
        assert cycles["time_optimal_cycle_s"].iloc[k] >= least + dwells - 1e-9


@pytest.mark.parametrize("formulation", ["paper", "ratios"])
def test_the_infill_stays_within_its_budget_and_its_last_round_is_the_verification(
    run, formulation
):
    """surrogate.infill on the test config: at most rounds + 1 checks of the front, at most
    ``offspring`` more designs a round, every true evaluation in infill.parquet, the last
    round's whole-front errors those verify_pareto reports, and the hypervolume history one
    run of generations numbered on through the reruns."""
    budget = effective_config(run)["surrogate"]["infill"]
    opt = run / "results/optimization" / formulation
    rounds = json.loads((opt / "infill.json").read_text(), parse_constant=_no_constant)["rounds"]
    assert 1 <= len(rounds) <= budget["rounds"] + 1
    table = read_table(opt / "infill.parquet")
    assert rounds[-1]["true_evaluations"] == len(table)
    sizes = table.groupby(["round", "source"]).size()
    for r in rounds:
        assert sizes[(r["round"], "front")] == r["n_front"]
        assert sizes.get((r["round"], "offspring"), 0) <= budget["offspring"]
    history = read_table(opt / "hypervolume.parquet")["generation"].to_numpy()
    np.testing.assert_array_equal(history, np.arange(1, len(history) + 1))
    verification = json.loads((opt / "verification.json").read_text())
    assert verification["infill"]["rounds"] == rounds
    for kind in ("median_rel_error", "p90_rel_error"):
        for name, value in rounds[-1][f"front_{kind}"].items():
            assert verification[kind][name] == pytest.approx(value, rel=1e-9, abs=1e-12)


def test_the_datasheet_states_this_runs_figures(run):
    sheet = (run / "results/datasheet.md").read_text()
    summary = (run / "results/summary.md").read_text()
    real = run / "results/realization"
    selected = json.loads((real / "selected.json").read_text())
    cycle = selected["cycle"]
    assert sheet.splitlines()[2] == summary.splitlines()[2]  # the run's verdict, word for word
    assert f"| cycles per hour | {cycle['cycles_per_hour']:,.0f} on the task" in sheet
    worst = selected["stiffness"]["worst"]["error_budget_mm"]  # at most 4 significant digits
    stated = re.search(r"\| placing error \| ([0-9.]+) mm worst", sheet)
    assert stated and abs(float(stated.group(1)) - worst) <= 0.005 + 5e-4 * worst
    line = next(x for x in sheet.splitlines() if x.startswith("| placing error | "))
    total = float(line.split("| placing error | ")[1].split(" mm")[0])
    terms = [float(v) for v in re.findall(r"(?:sag|creep|motion|error|base) ([0-9.]+) mm", line)]
    assert len(terms) == 5 and sum(terms) == pytest.approx(total, abs=0.021)  # its terms add up
    assert "| quantity | value |" in sheet and "| | |" not in sheet
    limits = effective_config(run)["operating_range"]  # the reach: the farthest tool point
    (lo, hi), low = limits["theta1_deg"], limits["theta2_min_deg"]
    t1, t2 = np.meshgrid(*(np.radians(np.linspace(a, hi, 721)) for a in (lo, low)))
    inside = t2 <= t1
    tool = end_effector(selected["design_m"], t1[inside], t2[inside])
    reach = float(np.nanmax(np.hypot(*tool.T)))
    stated = float(sheet.split("| reach | ")[1].split(" m ")[0])
    assert stated == pytest.approx(reach, abs=1.5e-3)
    # every line of the table backed by this run's records, and right (the reach to the
    # datasheet's 1 mm, checked above against the grid's farthest point)
    results = check_lines(sheet, run_records(run, effective_config(run), stated))
    assert all(v == "ok" for v in results.values()), results
    bom = pd.read_csv(real / "bom.csv")
    for part in bom.loc[bom["category"] == "printed part"].itertuples():
        volume_cm3 = part.mass_kg / effective_config(run)["material"]["density_kg_m3"] * 1e6
        hours = (volume_cm3 * 1e3 / 10.0 + 600) / 3600  # the page's stated rule
        row = f"| {part.item} | {part.mass_kg * 1e3:.0f} | {volume_cm3:.0f} | {hours:.1f} |"
        assert row in sheet


def _no_constant(name):
    raise ValueError(f"not strict JSON: {name}")


def test_realization_outputs(run):
    config = effective_config(run)
    real = run / "results/realization"
    selected = json.loads((real / "selected.json").read_text())
    design = np.array(selected["design_m"])
    candidate = selected["candidate"]  # the optimiser's row, as chosen
    assert candidate["feasible"] and candidate["dynamics_status"] == "ok"
    assert selected["printable"] and selected["source"] == config["optimization"]["formulation"]
    assert all_links_fit(
        design,
        physics.cad(config["cad"], config["material"]),
        tuple(config["printing"]["build_volume_mm"]),
    )
    torques = json.loads((real / "torques.json").read_text())
    assert set(torques["before"]) >= {"tau1_Nm", "tau2_Nm"} and set(torques["after"]) >= {
        "tau1_Nm",
        "tau2_Nm",
    }
    # lighter links need less torque, and the 'before' model is the Stage 2 model of the design
    # at its realised sections (grown for the tolerance where it asks)
    assert torques["after"]["tau1_Nm"] < torques["before"]["tau1_Nm"]
    scale = list(selected["stiffness"]["built_for_tolerance"]["section_scale"].values())
    cad = physics.cad(config["cad"], config["material"])
    duty = duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    payload = config["task"]["payload_kg"]
    carried = payload + selected["tool_flange_kg"]  # the tool flange at E beside the payload
    realised = evaluate_mechanism(design, duty, cad, carried, scale)
    assert torques["before"]["tau1_Nm"] == pytest.approx(realised["tau1_Nm"], rel=1e-9)
    bare = evaluate_mechanism(design, duty, cad, payload, scale)  # the flange weighs on motor 1
    assert torques["before"]["tau1_Nm"] > bare["tau1_Nm"]
    topo = json.loads((real / "topology.json").read_text())
    for link in topo["links"].values():
        assert link["mass_after_kg"] < link["mass_before_kg"] and link["watertight"]
    checks = json.loads((real / "stl_check.json").read_text())
    for stage in ("before", "after"):
        for name, check in checks[stage].items():
            mesh = trimesh.load(run / check["path"])
            assert mesh.is_watertight and check["watertight"], name
            assert max(mesh.extents) > 50  # millimetres, not metres
    payload = json.loads((real / "payload_test.json").read_text())
    assert {"passed", "max_tracking_error_deg", "peak_torque_Nm", "limit_Nm"} <= set(payload)
    assert config["payload_test"]["torque_limits_Nm"] is None and payload["limits_from"] == "drives"
    drives = selected["drives"]["motors"]
    assert payload["drives"] == [
        f"{m['drive']['motor']} + {m['drive']['gearbox']}" for m in drives.values()
    ]
    # each drive's standstill limit covers the duty's peak torque it was chosen for
    for limit, motor in zip(payload["limit_Nm"], drives.values(), strict=True):
        assert limit >= motor["required"]["peak_torque_Nm"]
    summary_md = (run / "results/summary.md").read_text()
    assert "payload test" in summary_md and "## Stage 6" in summary_md
    # a light payload keeps its decimals in the headline
    res = run / "results"
    files = {
        "filters": "mechanisms/filter_report.json",
        "status": "dynamics/status.json",
        "metrics": "surrogate/metrics.json",
        "comparison": "optimization/comparison.json",
        "selected": "realization/selected.json",
        "torques": "realization/torques.json",
        "payload": "realization/payload_test.json",
        "topology": "realization/topology.json",
    }
    loaded = {key: json.loads((res / path).read_text()) for key, path in files.items()}
    loaded["payload"]["payload_kg"] = 0.3
    findings = pd.read_parquet(res / "design_rules/findings.parquet")
    bom = (res / "realization/bom.md").read_text()
    assert "payload test (0.3 kg)" in headline_markdown(findings=findings, bom=bom, **loaded)


def test_the_design_to_build(run):
    """Every link of the realised design has a through hole per joint (trimesh's Euler number),
    every joint a bearing whose static rating covers its peak force with the configured factor,
    a drawing and a BOM; summary.md opens with the verdict and the design to build, and calls it
    ready only when every part holds."""
    config = effective_config(run)
    real = run / "results/realization"
    selected = json.loads((real / "selected.json").read_text())
    holes = {"lower_arm": 2, "crank": 2, "coupler": 2, "upper_arm": 3}  # A-D, and E's tool hole
    for name, count in holes.items():
        solid = trimesh.load(real / f"stl/before/{name}.stl")
        assert solid.is_watertight and (2 - solid.euler_number) // 2 == count, name
        printed = trimesh.load(real / f"stl/after/{name}.stl")
        assert printed.is_watertight and (2 - printed.euler_number) // 2 >= count, name
    s0 = config["strength"]["bearing_safety_factor"]
    for joint, bearing in selected["strength"]["bearings"].items():
        assert bearing["designation"], joint
        assert 1e3 * bearing["C0_kN"] >= s0 * bearing["peak_force_N"], joint
    assert (real / "drawing.svg").read_text().count("<text") > 10
    bom = pd.read_csv(real / "bom.csv")
    assert {"bearing B", "bearing C", "bearing D", "cheek 1", "cheek 2"} <= set(bom["item"])
    assert "bearing A" not in set(bom["item"])  # the drives' output bearings carry A
    summary_md = (run / "results/summary.md").read_text()
    first = summary_md.split("\n\n")[1]
    strength = selected["strength"]
    topo = json.loads((real / "topology.json").read_text())
    ready = (
        selected["printable"]
        and strength["holds_loads"]
        and all(link["carries_loads"] for link in topo["links"].values())
        and json.loads((real / "payload_test.json").read_text())["passed"]
        and selected["stiffness"]["meets_requirements"]
        and json.loads((real / "kit/kit.json").read_text())["holds"]
    )
    assert first.startswith("**Ready to build" if ready else "**NOT READY TO BUILD")
    assert "## The design to build" in summary_md and "| bearing B |" in summary_md
    for link, r in strength["links"].items():
        assert r["holds"] == (  # with the verdict's slack of 1e-12 at the limits
            r["stress_peak_MPa"] <= r["allowable_MPa"] * (1 + 1e-12)
            and (
                r["buckling_factor"] is None
                or r["buckling_factor"]
                >= config["strength"]["buckling_safety_factor"] * (1 - 1e-12)
            )
        ), link


def test_the_builders_kit_reopens_and_adds_up(run):
    """Every STEP file of the kit reopens in the CAD kernel as one closed solid, the assembly
    as one solid per part, drive envelope and piece of hardware; every DXF reads back with
    ezdxf, with one outline and the plate's holes and openings; the BOM lists every fastener
    of the kit with quantities that add up; the budget counts the base; the summary numbers
    the steps."""
    import ezdxf
    from build123d import import_step

    kit_dir = run / "results/realization/kit"
    kit = json.loads((kit_dir / "kit.json").read_text())
    layout = kit["layout"]
    for path in (kit_dir / "step").glob("*.step"):
        shape = import_step(path)
        parts = len(layout["plates"]) + len(layout["turned"]) + len(layout["hardware"])
        expected = parts if path.stem == "assembly" else 1
        assert len(shape.solids()) == expected and shape.is_valid, path.name
        if path.stem == "assembly":  # the datasheet weighs the hardware's solids as steel
            labels = {re.sub(r"[ .]", "_", n) for n in layout["hardware"]}
            mm3 = sum(c.volume for c in shape.children if c.label in labels)
            sheet = (run / "results/datasheet.md").read_text()
            assert f"{mm3 * 7.85e-6:.2f} kg of bearings and fasteners" in sheet
            moving = {
                re.sub(r"[ .]", "_", n)
                for n in layout["hardware"]
                if layout["moves_with"][n] != "base"
            }
            mm3 = sum(c.volume for c in shape.children if c.label in moving)
            assert f"flange, {mm3 * 7.85e-6:.2f} kg of bearings and fasteners with them" in sheet
            # the dynamics after the kit carry the same moving hardware (but the tool flange's
            # screw and washer, carried at E) and the hubs, weighed here by the CAD kernel (the
            # hub's keyway and set screw's hole, a few grams, are not taken out of the hub)
            flange = {n for n in moving if "tool_flange_to" in n}
            hubs = sum(
                import_step(kit_dir / "step" / f"{h}.step").volume
                for h in layout["turned"]
                if layout["moves_with"][h] != "base" and h != "tool_flange"
            )
            kernel = sum(c.volume for c in shape.children if c.label in moving - flange)
            carried = sum(p["mass_kg"] for p in kit["moving_parts"].values())
            assert carried == pytest.approx((kernel + hubs) * 7.85e-6, rel=3e-3)
    assert {p.stem for p in (kit_dir / "step").glob("*.step")} >= set(layout["plates"])
    for name, plate in layout["plates"].items():
        doc = ezdxf.readfile(kit_dir / "dxf" / f"{name}.dxf")
        layers = [e.dxf.layer for e in doc.modelspace().query("LWPOLYLINE")]
        assert layers.count("OUTLINE") == 1 and layers.count("HOLES") == len(plate["holes"])
    bom = pd.read_csv(run / "results/realization/bom.csv")
    fasteners = bom[bom["category"].isin(["fastener", "key"])]
    pins = [p["screw"] or f"made: {p['made']}" for p in kit["pins"].values()]  # ISO 7379, or made
    assert sum(int(bom.loc[bom["item"] == s, "quantity"].iloc[0]) for s in set(pins)) == 3
    assert fasteners["quantity"].sum() > 40 and (fasteners["quantity"] > 0).all()
    inserts = bom[bom["category"] == "insert"]
    hub_side = sum(h["link_screws"]["side"] == "hub" for h in kit["hubs"])
    assert inserts["quantity"].sum() == 6 * hub_side  # six per hub bolted from its own side
    selected = json.loads((run / "results/realization/selected.json").read_text())
    base = selected["stiffness"]["per_point"]["base_mm"]
    assert base == pytest.approx([kit["base"]["tool_error_mm"]] * len(base))
    for c in kit["clearances"]:  # a head or nut: its neighbour passes beside or beyond it
        beyond = c["spacers_mm"] >= c["height_mm"] + 1.0
        assert c["holds"] == (c["clearance_mm"] >= c["needed_mm"] or beyond)
    assert len(kit["clearances"]) >= 4
    sequence = kit["assembly_sequence"]
    assert sequence["exists"] == kit["checks"]["assembly sequence"]
    assert len(sequence["steps"]) == len(kit["assembly_steps"])
    summary_md = (run / "results/summary.md").read_text()
    for k in range(1, len(kit["assembly_steps"]) + 1):
        assert f"\n{k}. " in summary_md


def test_sized_sections_are_drawn_and_built_as_checked(run, tmp_path):
    """``cad.section: sized``, Stage 6 again on the run's fronts: every link's STLs (the plate's
    thickness, the bar's width across its middle), drawing, BOM (thickness, mass of the solid
    parts) and ``topology.json`` carry the section its strength was checked with; at least one
    link is sized away from the configured 40 x 20 mm, and the verdict is ready exactly when
    every check holds."""
    work = copy_run(run, tmp_path / "sized")
    sized = tmp_path / "sized.yaml"
    sized.write_text("cad: {section: sized}")
    configs = (str(sized),)
    snakemake(work, "--forcerun", "select_design", "--rerun-triggers", "mtime", configs=configs)
    real = work / "results/realization"
    selected = json.loads((real / "selected.json").read_text())
    strength = selected["strength"]
    assert strength["section"] in ("sized", "sized and grown")  # grown where the tolerance asked
    checked = {k: (r["width_mm"], r["thickness_mm"]) for k, r in strength["links"].items()}
    assert any(not np.allclose(c, (40.0, 20.0), atol=0.5) for c in checked.values()), checked
    topo = json.loads((real / "topology.json").read_text())
    bom = pd.read_csv(real / "bom.csv").set_index("item")
    svg = (real / "drawing.svg").read_text()
    l1, l2, l3, l4 = (1e3 * v for v in selected["design_m"][:4])
    middle = {"lower_arm": l1 / 2, "crank": l2 / 2, "coupler": l3 / 2, "upper_arm": -l4 / 2}
    for name, (w, t) in checked.items():
        assert topo["parts"]["section_mm"][name] == pytest.approx([w, t], rel=1e-9), name
        assert f"{name}: section width {w:.1f} x thickness {t:.1f} mm" in svg
        assert bom.loc[name, "bbox_z_mm"] == pytest.approx(round(t, 1)), name
        for stage in ("before", "after"):
            mesh = trimesh.load(real / f"stl/{stage}/{name}.stl")
            assert mesh.extents[2] == pytest.approx(t, rel=1e-6), (stage, name)
        solid = trimesh.load(real / f"stl/before/{name}.stl")
        cut = solid.section(plane_origin=[middle[name], 0.0, 0.0], plane_normal=[1.0, 0.0, 0.0])
        assert np.ptp(cut.vertices[:, 1]) == pytest.approx(w, rel=1e-6), name
        if not bom.loc[name, "topology_optimised"]:  # the part as built: ABS-M30, its volume
            built = trimesh.load(real / f"stl/after/{name}.stl")  # with the hubs' insert holes
            assert bom.loc[name, "mass_kg"] == pytest.approx(1040.0 * built.volume * 1e-9, rel=1e-5)
    payload = json.loads((real / "payload_test.json").read_text())
    ready = (
        selected["printable"]
        and strength["holds_loads"]
        and selected["drives"]["has_drives"]
        and all(link["carries_loads"] for link in topo["links"].values())
        and all(part["fits"] for part in topo["parts"]["printer"].values())
        and payload["passed"]
        and selected["stiffness"]["meets_requirements"]
    )
    summary_md = (work / "results/summary.md").read_text()
    assert "was checked with the section" not in summary_md
    assert "sized by strength" in summary_md
    assert summary_md.split("\n\n")[1].startswith("**Ready to build" if ready else "**NOT READY")


def test_payload_test_fails_below_the_required_torque(run, tmp_path):
    work = copy_run(run, tmp_path / "weak")
    low = tmp_path / "low.yaml"
    # enough for the payload alone at rest (the config check), too little for the duty's motor 1
    low.write_text("payload_test: {torque_limits_Nm: [20.0, 20.0]}")
    assert planned_jobs(work, "payload_test", configs=(str(low),)) == {"payload_test": 1}
    snakemake(work, "payload_test", configs=(str(low),))
    payload = json.loads((work / "results/realization/payload_test.json").read_text())
    assert payload["passed"] is False and payload["saturated"] is True


def test_report_and_lint(run, tmp_path):
    work = copy_run(run, tmp_path / "report")
    snakemake(work, "--report", "results/report.html")
    html = (work / "results/report.html").read_text(errors="replace")
    for caption in ("Sobol indices", "payload test", "Pareto front"):
        assert caption in html
    # docutils writes a caption's error ("Undefined substitution referenced", ...) into the page
    for message in ("System Message", "Docutils System Messages"):
        assert message not in html
    # the Markdown results are pages of the report's first category, not download links
    assert "0. Summary" in html
    for page in ("summary", "comparison", "design_rules", "torques", "surrogate"):
        assert f"{page}.html" in html
    lint = snakemake(work, "--lint")
    assert "Congratulations" in lint.stdout + lint.stderr
    assert "Lints for" not in lint.stdout + lint.stderr


def test_a_far_heavy_task_completes_with_the_verdicts(tmp_path):
    """A far, large task with 10 kg: every design is too long for the printer and too weak for
    the load (tau1 about 150 N m); the run still completes, realises the truly feasible design
    nearest to holding and says plainly that it is not strong enough and not printable, with
    what would change that."""
    work = copy_workflow(tmp_path / "far")
    far = tmp_path / "far.yaml"
    far.write_text("task: {points: [[-1.15, 0.0], [-0.75, 0.0], [-0.95, 0.15]], payload_kg: 10}")
    snakemake(work, configs=(str(far),))
    selected = json.loads((work / "results/realization/selected.json").read_text())
    assert selected["printable"] is False and selected["candidate"]["feasible"]
    assert selected["strength"]["holds_loads"] is False
    weakest = selected["strength"]["weakest_link"].replace("_", " ")
    assert selected["verdict"].startswith(f"NOT STRONG ENOUGH: the {weakest}")
    assert "NOT PRINTABLE" in selected["verdict"]
    # both fronts and the dataset: nothing strong
    assert (
        "no truly feasible design of the fronts or the dataset holds its loads"
        in (selected["fallback"])
    )
    effective = effective_config(work)
    cad = physics.cad(effective["cad"], effective["material"])
    assert not all_links_fit(np.array(selected["design_m"]), cad, (600, 350, 350))
    # no printer advice for designs too weak: a printer would not make them hold
    assert selected["printing_advice"]["smallest_over_designs"] is None
    assert "no larger printer would help: none holds its loads" in selected["verdict"]
    assert "a printer of at least" not in selected["verdict"]
    # the payload the advice names holds, 5 % more does not (the strength check run again)
    payload = selected["strength_advice"]["payload_kg"]
    case = links.load_case_of(effective)

    def violation(kg):
        check = links.strength_check(replace(case, payload_kg=kg), effective["strength"])
        return check.violation(np.array(selected["design_m"]))[0]

    assert violation(payload) <= 0 < violation(1.05 * payload)
    checks = json.loads((work / "results/realization/stl_check.json").read_text())
    assert not all(c["fits_build_volume"] for c in checks["before"].values())
    summary_md = (work / "results/summary.md").read_text()
    assert summary_md.split("\n\n")[1].startswith("**NOT READY TO BUILD")
    assert "verdict: NOT STRONG ENOUGH" in summary_md
    payload = json.loads((work / "results/realization/payload_test.json").read_text())
    assert payload["payload_kg"] == 10.0  # the task's payload, not the paper's 5 kg
    for name in ("paper", "ratios"):
        verification = json.loads(
            (work / f"results/optimization/{name}/verification.json").read_text()
        )
        assert verification["printable_share"] == 0.0
        assert verification["holds_task_share"] == 1.0
        assert "g12 dropped" in verification["constraints"]
        assert "g13 dropped" in verification["constraints"]
    assert_one_machine(work)
    assert_plain_numbers(work / "results")  # a verdict of large numbers


def strict_json(path: Path) -> object:
    """``path`` parsed as strict JSON: NaN, Infinity and -Infinity are refused, as JavaScript's
    and jq's parsers refuse them."""

    def refuse(name: str) -> None:
        raise ValueError(f"{path}: {name} is not JSON")

    return json.loads(path.read_text(), parse_constant=refuse)


def test_every_json_output_is_strict_json(run):
    files = sorted((run / "results").rglob("*.json"))
    assert len(files) > 15
    for path in files:
        strict_json(path)


def test_a_catalogue_where_no_drive_fits_gives_valid_files_and_plain_words(tmp_path):
    """Only the stepper and its 50:1 gearhead (5 N m), 1 kg: no drive meets motor 1's duty. The
    run completes; every JSON output is strict JSON; the payload test simulates the nearest
    drive and says so, with finite figures (a motor past its drive's top speed has no peak use:
    null, and the share of steps past it says why); no numpy warning reaches a log."""
    data = ROOT / "src/qsm/embodiment/drives/data"
    folder = tmp_path / "steppers"
    folder.mkdir()
    for name in ("motors.csv", "gearboxes.csv", "compatibility.csv", "torque_speed.csv"):
        lines = (data / name).read_text().splitlines()
        keep = [x for x in lines if not x.startswith(("MM_", "TM_", "HD_"))]
        (folder / name).write_text("\n".join(keep) + "\n")
    config = tmp_path / "steppers.yaml"
    config.write_text(f"task: {{payload_kg: 1.0}}\ndrives: {{catalogue: {folder}}}\n")
    work = copy_workflow(tmp_path / "work")
    out = snakemake(work, configs=(str(config),))
    results = work / "results"
    for path in results.rglob("*.json"):
        strict_json(path)
    selected = strict_json(results / "realization/selected.json")
    assert not selected["drives"]["has_drives"] and selected["printable"]
    test = strict_json(results / "realization/payload_test.json")
    meets = [m["has_drive"] for m in selected["drives"]["motors"].values()]
    assert test["drive_meets_duty"] == meets and not all(meets)
    assert (
        "has no drive in the catalogue that meets its duty: simulated with the nearest"
        in (test["drive_note"])
    )
    uses = test["peak_torque_over_available"]
    for use, past in zip(uses, test["past_top_speed_fraction"], strict=True):
        assert (use is None) == (past > 0)
    summary_md = (results / "summary.md").read_text()
    assert "**NOT READY TO BUILD" in summary_md
    assert not re.search(r"\binf\b|\bnan\b", summary_md, re.IGNORECASE)
    assert "0 of those printable" not in summary_md  # the design is printable
    # the verdict's line for the motor says why its nearest drive does not do, with its number
    assert re.search(
        r"motor 1 \(lower arm\) has no drive in the catalogue \(the nearest exceeds its "
        r"[a-z ]+ limit by \d+ %",
        summary_md,
    )
    for log in results.rglob("*.log"):
        assert "RuntimeWarning" not in log.read_text(), log
    assert "RuntimeWarning" not in out.stderr
    assert_one_machine(work)
    assert_plain_numbers(results)


def _cells(row: str) -> list[str]:
    """The cells of a Markdown table row: split at every ``|`` that is not escaped."""
    cells, cell, chars = [], "", iter(row.strip().removeprefix("|").removesuffix("|"))
    for c in chars:
        if c == "\\":
            cell += c + next(chars, "")
        elif c == "|":
            cells.append(cell)
            cell = ""
        else:
            cell += c
    return [*cells, cell]


def test_every_markdown_table_has_as_many_cells_per_row_as_its_header(run):
    """A ``|`` inside a cell must be escaped, or it splits the cell and the row renders wrongly."""
    pages = sorted((run / "results").rglob("*.md"))
    assert {"summary.md", "comparison.md", "torques.md", "metrics.md"} <= {p.name for p in pages}
    tables = 0
    for page in pages:
        lines = page.read_text().splitlines()
        for i, line in enumerate(lines[:-1]):
            rule = lines[i + 1].strip()
            if not (line.startswith("|") and rule.startswith("|") and set(rule) <= set("|-: ")):
                continue
            tables += 1
            width = len(_cells(line))
            assert len(_cells(rule)) == width, f"{page}:{i + 2}"
            for k in range(i + 2, len(lines)):
                if not lines[k].startswith("|"):
                    break
                assert len(_cells(lines[k])) == width, f"{page}:{k + 1}: {lines[k]}"
    assert tables >= 5


def test_every_page_writes_its_numbers_for_a_person(run):
    """No list brackets, no repr, no float at full precision in any Markdown page's prose."""
    assert_plain_numbers(run / "results")


def test_the_end_of_a_run_names_the_headline_and_the_summary(run, tmp_path):
    work = copy_run(run, tmp_path / "end")
    out = snakemake(work, "--forcerun", "summary")
    text = out.stdout + out.stderr
    verdict = next(
        line
        for line in (work / "results/summary.md").read_text().splitlines()
        if line.startswith("**")
    )
    assert f"qsm: {verdict.strip('*')}" in text
    assert f"qsm: the summary: {(work / 'results/summary.md').resolve()}" in text

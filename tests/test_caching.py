"""Caching and partial reruns: a config change reruns exactly the stages that use the value."""

import json

import pytest
import yaml
from workflow_helpers import ROOT, copy_run, copy_workflow, planned_jobs, snakemake

from qsm.workflow.tables import read_table

pytestmark = pytest.mark.workflow

STAGE1 = {"sample", "filter_kinematics", "fit_task", "select_mechanisms", "plot_mechanisms"}
STAGE2 = {"dynamics", "gather_dataset", "plot_dynamics"}
STAGE3 = {"train_surrogate"}


def override(tmp_path, text):
    path = tmp_path / "override.yaml"
    path.write_text(text)
    return (str(path),)


def test_second_run_does_nothing(run):
    assert planned_jobs(run) == {}


def test_generations_rerun_only_the_optimization_and_after(run, tmp_path):
    jobs = planned_jobs(run, configs=override(tmp_path, "optimization: {generations: 16}"))
    assert jobs["optimize"] == 2 and jobs["verify_pareto"] == 2 and "compare_fronts" in jobs
    assert not (STAGE1 | STAGE2 | STAGE3 | {"sobol", "eta_derivatives"}) & set(jobs)


def test_a_dynamics_setting_reruns_the_shards_and_after_not_stage1(run, tmp_path):
    text = "dynamics: {duty: {peak_speed_deg_s: 50.0}}"
    jobs = planned_jobs(run, configs=override(tmp_path, text))
    assert jobs["dynamics"] == 3 and {"gather_dataset", "train_surrogate", "optimize"} <= set(jobs)
    assert not STAGE1 & set(jobs)


def test_payload_reruns_dynamics_but_not_the_workspace(run, tmp_path):
    jobs = planned_jobs(run, configs=override(tmp_path, "task: {payload_kg: 4.0}"))
    assert "dynamics" in jobs and not STAGE1 & set(jobs)


def test_choosing_the_primary_front_does_not_rerun_the_optimization(run, tmp_path):
    jobs = planned_jobs(run, configs=override(tmp_path, "optimization: {formulation: ratios}"))
    assert "decision_trees" in jobs and "design_rules_summary" in jobs
    assert not {"optimize", "verify_pareto", "train_surrogate"} & set(jobs)


def test_g11_switch_reruns_only_the_paper_front(run, tmp_path):
    text = "optimization: {constraints: {containment: false}}"
    jobs = planned_jobs(run, configs=override(tmp_path, text))
    assert jobs["optimize"] == 1 and jobs["verify_pareto"] == 1
    assert not (STAGE1 | STAGE2 | STAGE3) & set(jobs)


def test_printer_reruns_the_optimization_when_g12_is_on(run, tmp_path):
    text = "printing: {build_volume_mm: [700, 400, 400]}"
    jobs = planned_jobs(run, configs=override(tmp_path, text))
    assert jobs["optimize"] == 2 and "select_design" in jobs
    assert not (STAGE1 | STAGE2 | STAGE3) & set(jobs)


def test_the_default_task_from_a_points_file_reruns_nothing(run, tmp_path):
    """task.points_file is read into task.points: the same points plan no job; a file that
    cannot be read stops the run before any job, naming the key and the file."""
    points = tmp_path / "points.csv"
    points.write_text("x_m,y_m\n-0.53,0.17\n-0.70,0.02\n-0.60,0.02\n-0.70,0.12\n-0.60,0.12\n")
    assert planned_jobs(run, configs=override(tmp_path, f"task: {{points_file: '{points}'}}")) == {}
    points.unlink()
    configs = override(tmp_path, f"task: {{points_file: '{points}'}}")
    out = snakemake(run, "--dry-run", check=False, configs=configs)
    assert out.returncode != 0
    message = f"config key 'task.points_file': file '{points}' cannot be read"
    assert message in out.stdout + out.stderr


def test_forcerun_until_reruns_one_rule_alone(run):
    assert planned_jobs(run, "--forcerun", "train_surrogate", "--until", "train_surrogate") == {
        "train_surrogate": 1
    }


def test_a_single_target_file_builds_alone(tmp_path):
    work = copy_workflow(tmp_path / "fresh")
    assert planned_jobs(work, "results/mechanisms/samples.parquet") == {"sample": 1}
    snakemake(work, "results/mechanisms/samples.parquet")
    assert sorted(p.name for p in (work / "results").rglob("*.parquet")) == ["samples.parquet"]


def test_every_rule_gets_its_config_through_params():
    """No script reads snakemake.config: such a value would not trigger a rerun."""
    for script in (ROOT / "workflow" / "scripts").glob("*.py"):
        assert "snakemake.config" not in script.read_text(), script.name
    config = yaml.safe_load((ROOT / "config" / "test.yaml").read_text())
    assert config["dynamics"]["shards"] == 3  # the tests above count three dynamics jobs


def test_editing_a_library_module_reruns_exactly_the_rules_that_import_it(run, tmp_path):
    work = copy_run(run, tmp_path / "edited")
    module = work / "src/qsm/design_rules/findings.py"
    module.write_text(module.read_text() + "\n# an edit\n")
    jobs = planned_jobs(work)
    # and the report pages of the Markdown they rewrite; "default" is the checkout's target rule
    assert set(jobs) - {"default"} == {"design_rules_summary", "summary", "markdown_pages"}
    kinematics = work / "src/qsm/physics/kinematics.py"
    kinematics.write_text(kinematics.read_text() + "\n# an edit\n")
    assert {"sample", "fit_task", "dynamics", "payload_test"} <= set(planned_jobs(work))


def test_editing_the_drive_check_reruns_the_selection_and_the_payload_test(run, tmp_path):
    """select_design reaches the drive check only through a function's import in the settings
    layer: an edit of it still reruns the selection and everything after it."""
    work = copy_run(run, tmp_path / "edited")
    module = work / "src/qsm/embodiment/drives/drive_checks.py"
    module.write_text(module.read_text() + "\n# an edit\n")
    jobs = planned_jobs(work)
    assert {"select_design", "payload_test", "topology_optimize", "accuracy_budget"} <= set(jobs)
    selected = work / "results/realization/choice.json"
    test = work / "results/realization/payload_test.json"
    before = selected.stat().st_mtime_ns, test.stat().st_mtime_ns
    snakemake(work, "--until", "payload_test")
    assert selected.stat().st_mtime_ns > before[0] and test.stat().st_mtime_ns > before[1]


def _front_meta(work, formulation):
    path = work / f"results/optimization/{formulation}/verification.json"
    return json.loads(path.read_text())


def test_a_tolerance_g15_can_meet_keeps_every_front_within_it(run, tmp_path):
    """task.tolerance_mm reaches g15: the optimisation and what follows rerun, Stages 1 to 3
    stand. At the test config's 5 mm no design of the dataset meets g15 and the label says so
    with the dataset's least sag; at 30 mm every design of each front meets it (true values, every
    task point)."""
    dataset = read_table(run / "results/dataset.parquet")
    least = float(dataset.loc[dataset["status"].eq("ok"), "tool_sag_mm"].min())
    assert least > 5.0  # the premise of the first half
    dropped = "g15 dropped: no design of the dataset keeps the tool's sag within 5 mm (least "
    for formulation in ("paper", "ratios"):
        assert dropped + f"{least:.1f} mm" in _front_meta(run, formulation)["constraints"]
    configs = override(tmp_path, "task: {tolerance_mm: 30.0}")
    jobs = planned_jobs(run, configs=configs)
    assert {"optimize", "verify_pareto", "select_design", "accuracy_budget"} <= set(jobs)
    assert not {"sample", "fit_task", "dynamics", "train_surrogate"} & set(jobs)
    work = copy_run(run, tmp_path / "work")
    snakemake(work, configs=configs)
    for formulation in ("paper", "ratios"):
        table = read_table(work / f"results/optimization/{formulation}/verification.parquet")
        label = _front_meta(work, formulation)["constraints"]
        assert "g15 tool sag within 30 mm" in label and "g15 dropped" not in label
        assert len(table) and (table["tool_sag_mm"] <= 30.0).all()
        assert _front_meta(work, formulation)["within_tolerance_share"] == 1.0


def test_turning_the_study_off_reruns_the_summary_alone_and_its_verdicts_follow(run, tmp_path):
    """The findings table follows the config: without the study no experiment backs a verdict."""
    configs = override(tmp_path, "study: {enabled: false}")
    assert planned_jobs(run, configs=configs) == {
        "design_rules_summary": 1,
        "summary": 1,
        "markdown_pages": 1,
        "default": 1,
    }
    work = copy_run(run, tmp_path / "work")
    snakemake(work, configs=configs)
    before = read_table(run / "results/design_rules/findings.parquet")
    after = read_table(work / "results/design_rules/findings.parquet")
    assert len(after) == len(before) - 1  # no Table 3 row without its sweep
    assert (after["experiment"] == "").all()
    disagree = after["agree"] == "disagree"
    assert after.loc[disagree, "verdict"].str.startswith("unexplained").all()
    assert (after.loc[~disagree, "verdict"] == "agrees in this run").all()

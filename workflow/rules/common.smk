# Shared definitions: the conda environment, code provenance and the settings rules depend on.
import functools

from qsm.config.sections import (
    cycles_section,
    dataset_provenance,
    dataset_section,
    drives_section,
    iso_section,
    mechanisms_section,
    optimization_section,
    realization_section,
    surrogate_section,
)
from qsm.physics.task_points import design_task, task_cycle
from qsm.workflow.provenance import source_hash
from qsm.workflow.sharding import shard_count

ENV = "../envs/qsm.yaml"
RESULTS = "results"
# The result folders of Stages 4 and 6, and the fronts Stage 4 makes (rule files share these).
OPT = f"{RESULTS}/optimization"
REAL = f"{RESULTS}/realization"
FORMULATIONS = config["optimization"]["formulations"]
# The task every stage designs for: the user's points, or their mirror image through x = 0 when
# the task lies at x > 0 (qsm.physics.mirror); of a task of more than 8 points only the 8 the
# payload test visits, whose enclosing disk is the task's, so that rule parameters stay short
# (qsm.physics.task_points.design_task). The outputs say so and keep the user's points.
MIRRORED, TASK_POINTS = design_task(config["task"]["points"])
# The task as a pick-and-place cycle: the visited point numbers, their design points and the dwell
# (qsm.physics.task_points.task_cycle; task.cycle, else the payload test's visits).
CYCLE = task_cycle(
    config["task"]["points"],
    config["task"]["cycle"],
    config["payload_test"]["dwell_s"],
    config["payload_test"]["return_to_start"],
)._asdict()
# The rule scripts, found from this file (workflow/rules) whether the workflow runs from the
# checkout or as a module of another workflow.
SCRIPTS = Path(str(workflow.current_basedir)).parent / "scripts"
# Stage 6's settings, resolved once: the realisation's share of the config, in its shape
# (qsm.config.sections.realization_section). The realisation's rules take it as one param and
# build their settings from it as `qsm export` does from the whole config (realization_of).
REALIZATION = realization_section(config)
# Stage 1's share, resolved once (qsm.config.sections.mechanisms_section): the scale-up's rules
# take it as one param, and the mechanism table records it.
MECHANISMS = mechanisms_section(config)


@functools.cache
def drive_settings():
    """``drives`` with a digest of the catalogue's values (qsm.config.sections.drives_section):
    editing the catalogue reruns the rules that choose drives. Hashed once per run."""
    return drives_section(config)


def jerk_time_s():
    """task.cycle.jerk_time_s: the time (s) each cycle move ramps its acceleration over; None:
    one period of the arm's first mode (qsm.app.cycle_inputs.JerkTime)."""
    return (config["task"]["cycle"] or {}).get("jerk_time_s")


def primary_front(name):
    """A file of the front that feeds the later stages (optimization.formulation)."""
    return f"{RESULTS}/optimization/{config['optimization']['formulation']}/{name}"


def code(script):
    """Hash of the qsm sources ``script`` runs: editing any of them reruns the rule."""
    return source_hash(SCRIPTS / script)


def study_inputs(wildcards):
    """The study's outputs (workflow/rules/study.smk) for the findings table; none when the
    study is off."""
    if not config["study"]["enabled"]:
        return {}
    return {
        "lengths": rules.study_lengths.output.outcome,
        "table3": rules.study_table3.output.table,
        "designs": rules.decision_trees.output.designs,
        "torques": rules.topology_optimize.output.torques,
    }


def print_headline(summary, started):
    """At the end of a run: the verdict (the first bold line of ``summary``) and its path.

    Says so when ``summary`` is older than the run (``started``, seconds since the epoch), i.e.
    the run asked for something else and the summary may not describe the current settings."""
    path = Path(summary)
    if not path.exists():
        return
    verdict = next(
        (
            line.strip().strip("*")
            for line in path.read_text().splitlines()
            if line.startswith("**")
        ),
        "",
    )
    stale = "" if path.stat().st_mtime >= started else " (from an earlier run)"
    logger.info(f"qsm: {verdict}\nqsm: the summary{stale}: {path.resolve()}")

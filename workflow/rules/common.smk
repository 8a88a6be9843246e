# Shared definitions: the conda environment, code provenance and the settings rules depend on.
from qsm.provenance import source_hash

ENV = "../envs/qsm.yaml"
RESULTS = "results"


def stage1_settings():
    """The config sections Stage 1 results depend on (its metadata hash); not the shard count."""
    return {
        "sampling": config["sampling"],
        "operating_range": config["operating_range"],
        "filters": config["filters"],
        "task_points": config["task"]["points"],
        "scale": config["scale"],
        "workspace": fit_workspace(),
    }


def stage2_settings():
    """What the dataset depends on beyond Stage 1 (its metadata hash); not the shard count."""
    return {
        **stage1_settings(),
        "duty": config["dynamics"]["duty"],
        "cad": config["cad"],
        "payload_kg": config["task"]["payload_kg"],
    }


def optimization_settings():
    """What an NSGA-II run uses; the choice of the primary front is not among it."""
    return {k: v for k, v in config["optimization"].items() if k != "formulation"}


def primary_front(name):
    """A file of the front that feeds the later stages (optimization.formulation)."""
    sub = "" if config["optimization"]["formulation"] == "paper" else "ratios/"
    return f"{RESULTS}/optimization/{sub}{name}"


def code(script):
    """Hash of the qsm sources ``script`` runs: editing any of them reruns the rule."""
    return source_hash(Path(workflow.basedir) / "workflow" / "scripts" / script)


def fit_workspace():
    """The workspace settings of the scale-up (slicing and scale scan), not the shard count."""
    return {k: config["workspace"][k] for k in ("n_delta", "n_levels", "n_scan")}

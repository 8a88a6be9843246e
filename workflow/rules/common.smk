# Shared definitions: the conda environment and the per-stage targets.
ENV = "../envs/qsm.yaml"
RESULTS = "results"


def stage1_settings():
    """The config sections Stage 1 results depend on (its metadata hash); not the shard count."""
    workspace = {k: v for k, v in config["workspace"].items() if k != "shards"}
    return {
        "sampling": config["sampling"],
        "operating_range": config["operating_range"],
        "filters": config["filters"],
        "task_points": config["task"]["points"],
        "scale": config["scale"],
        "workspace": workspace,
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

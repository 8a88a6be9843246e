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
        "task": config["task"],
        "scale": config["scale"],
        "workspace": workspace,
    }

# qsm-design: generative design of quasi-serial manipulators (Lee, Yang, Kang).
# The logic lives in the `qsm` package (src/qsm); rules are in workflow/rules, one file per stage.
import os
import sys
from pathlib import Path

from snakemake.utils import min_version

min_version("9.0")

# The Snakefile imports qsm from this checkout; jobs find it through the installed package or,
# in a bare conda environment, through the link workflow/scripts/qsm (the scripts' directory is on
# their sys.path).
sys.path.insert(0, str(Path(workflow.basedir) / "src"))

from qsm.config import read_config_file, validate_config  # noqa: E402
from qsm.config_checks import config_warnings  # noqa: E402

# Jobs draw figures without a display; the library leaves the backend to its caller.
os.environ.setdefault("MPLBACKEND", "Agg")


# Snakemake reports a YAML error in a config file without its line; read the default one first so
# that an edit of it that breaks the YAML is named with file, line and column (a file given with
# --configfile is read by Snakemake before this file runs: `python -m qsm check-config FILE...`).
if Path("config/config.yaml").exists():
    read_config_file("config/config.yaml")


configfile: "config/config.yaml"


report: "workflow/report/workflow.rst"


validate_config(config)
for message in config_warnings(config):
    logger.warning(f"qsm config warning: {message}")


include: "workflow/rules/common.smk"
include: "workflow/rules/mechanisms.smk"
include: "workflow/rules/dynamics.smk"
include: "workflow/rules/surrogate.smk"
include: "workflow/rules/optimization.smk"
include: "workflow/rules/design_rules.smk"
include: "workflow/rules/realization.smk"
include: "workflow/rules/study.smk"
include: "workflow/rules/summary.smk"
include: "workflow/rules/exploration.smk"


# Light rules (tables, gathers, plots, summaries: seconds at the paper's scale) run on the
# submitting host under a cluster executor instead of as cluster jobs of their own (README).
localrules:
    select_mechanisms,
    plot_mechanisms,
    gather_dataset,
    plot_dynamics,
    compare_fronts,
    decision_trees,
    correlations,
    eta_derivatives,
    design_rules_summary,
    select_design,
    summary,
    pareto_html,
    task_motion,


rule all:
    default_target: True
    input:
        STAGE1_OUTPUTS,
        STAGE2_OUTPUTS,
        STAGE3_OUTPUTS,
        STAGE4_OUTPUTS,
        STAGE5_OUTPUTS,
        STAGE6_OUTPUTS,
        EXPLORATION_OUTPUTS,
        f"{RESULTS}/summary.md",

# Stage 1: Latin-hypercube designs, kinematic filters, workspace, scale factor and eta.

STAGE1_SHARDS = range(config["workspace"]["shards"])
STAGE1_OUTPUTS = [
    f"{RESULTS}/mechanisms/mechanisms.parquet",
    f"{RESULTS}/mechanisms/filter_report.json",
    f"{RESULTS}/figures/mechanism_examples.png",
    f"{RESULTS}/figures/scale_eta.png",
]


rule sample:
    output:
        f"{RESULTS}/mechanisms/samples.parquet",
    log:
        f"{RESULTS}/logs/sample.log",
    benchmark:
        f"{RESULTS}/benchmarks/sample.tsv"
    conda:
        ENV
    params:
        code=code("sample.py"),
        sampling=config["sampling"],
    script:
        "../scripts/sample.py"


rule filter_kinematics:
    input:
        rules.sample.output[0],
    output:
        candidates=f"{RESULTS}/mechanisms/candidates.parquet",
        counts=f"{RESULTS}/mechanisms/kinematic_filters.json",
    log:
        f"{RESULTS}/logs/filter_kinematics.log",
    benchmark:
        f"{RESULTS}/benchmarks/filter_kinematics.tsv"
    conda:
        ENV
    params:
        code=code("filter_kinematics.py"),
        operating_range=config["operating_range"],
        filters=config["filters"],
    script:
        "../scripts/filter_kinematics.py"


rule fit_task:
    input:
        rules.filter_kinematics.output.candidates,
    output:
        f"{RESULTS}/mechanisms/fits/shard-{{shard}}.parquet",
    log:
        f"{RESULTS}/logs/fit_task/shard-{{shard}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/fit_task/shard-{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    conda:
        ENV
    params:
        code=code("fit_task.py"),
        shards=config["workspace"]["shards"],
        n_mechanisms=config["sampling"]["n_mechanisms"],
        mechanisms=MECHANISMS,
    script:
        "../scripts/fit_task.py"


rule select_mechanisms:
    input:
        fits=expand(f"{RESULTS}/mechanisms/fits/shard-{{shard}}.parquet", shard=STAGE1_SHARDS),
        counts=rules.filter_kinematics.output.counts,
        candidates=rules.filter_kinematics.output.candidates,
    output:
        mechanisms=f"{RESULTS}/mechanisms/mechanisms.parquet",
        report=f"{RESULTS}/mechanisms/filter_report.json",
    log:
        f"{RESULTS}/logs/select_mechanisms.log",
    benchmark:
        f"{RESULTS}/benchmarks/select_mechanisms.tsv"
    conda:
        ENV
    params:
        code=code("select_mechanisms.py"),
        n_mechanisms=config["sampling"]["n_mechanisms"],
        mechanisms=MECHANISMS,
    script:
        "../scripts/select_mechanisms.py"


rule plot_mechanisms:
    input:
        rules.select_mechanisms.output.mechanisms,
    output:
        examples=report(
            f"{RESULTS}/figures/mechanism_examples.png",
            caption="../report/mechanism_examples.rst",
            category="1. Mechanisms",
        ),
        distributions=report(
            f"{RESULTS}/figures/scale_eta.png",
            caption="../report/scale_eta.rst",
            category="1. Mechanisms",
        ),
    log:
        f"{RESULTS}/logs/plot_mechanisms.log",
    benchmark:
        f"{RESULTS}/benchmarks/plot_mechanisms.tsv"
    conda:
        ENV
    params:
        code=code("plot_mechanisms.py"),
        operating_range=config["operating_range"],
        task_points=TASK_POINTS,
        figures=config["figures"],
    script:
        "../scripts/plot_mechanisms.py"

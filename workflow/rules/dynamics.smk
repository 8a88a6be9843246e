# Stage 2: link solids, MuJoCo models and closed-chain inverse dynamics, in shards of at most
# dynamics.rows_per_shard mechanisms (qsm.workflow.sharding.shard_count).

DYNAMICS_SHARDS = range(
    shard_count(
        config["sampling"]["n_mechanisms"],
        config["dynamics"]["shards"],
        config["dynamics"]["rows_per_shard"],
    )
)
STAGE2_OUTPUTS = [
    f"{RESULTS}/dataset.parquet",
    f"{RESULTS}/dynamics/status.json",
    f"{RESULTS}/figures/performance.png",
]


rule dynamics:
    input:
        rules.select_mechanisms.output.mechanisms,
    output:
        f"{RESULTS}/dynamics/shard-{{shard}}.parquet",
    log:
        f"{RESULTS}/logs/dynamics/shard-{{shard}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/dynamics/shard-{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("dynamics_shard.py"),
        shards=len(DYNAMICS_SHARDS),
        dataset=dataset_section(config),
    script:
        "../scripts/dynamics_shard.py"


rule gather_dataset:
    input:
        mechanisms=rules.select_mechanisms.output.mechanisms,
        shards=expand(f"{RESULTS}/dynamics/shard-{{shard}}.parquet", shard=DYNAMICS_SHARDS),
    output:
        dataset=f"{RESULTS}/dataset.parquet",
        status=f"{RESULTS}/dynamics/status.json",
    log:
        f"{RESULTS}/logs/gather_dataset.log",
    benchmark:
        f"{RESULTS}/benchmarks/gather_dataset.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("gather_dataset.py"),
        settings=dataset_provenance(config, drive_settings()),
    script:
        "../scripts/gather_dataset.py"


rule plot_dynamics:
    input:
        rules.gather_dataset.output.dataset,
    output:
        report(
            f"{RESULTS}/figures/performance.png",
            caption="../report/performance.rst",
            category="2. Dynamics",
        ),
    log:
        f"{RESULTS}/logs/plot_dynamics.log",
    benchmark:
        f"{RESULTS}/benchmarks/plot_dynamics.tsv"
    conda:
        ENV
    params:
        code=code("plot_dynamics.py"),
    script:
        "../scripts/plot_dynamics.py"

# Stage 5: design rules from Sobol indices, decision trees, correlations and eta derivatives.

RULES_DIR = f"{RESULTS}/design_rules"
RULE_SHARDS = range(config["design_rules"]["shards"])
STAGE5_OUTPUTS = [f"{RULES_DIR}/summary.md"]


rule sobol:
    input:
        model=rules.train_surrogate.output.model,
        dataset=rules.gather_dataset.output.dataset,
    output:
        indices=f"{RULES_DIR}/sobol.parquet",
        figure=report(
            f"{RESULTS}/figures/sobol.png",
            caption="../report/sobol.rst",
            category="5. Design rules",
        ),
    log:
        f"{RESULTS}/logs/sobol.log",
    benchmark:
        f"{RESULTS}/benchmarks/sobol.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("sobol.py"),
        sobol_n=config["design_rules"]["sobol_n"],
        seed=config["design_rules"]["seed"],
        bounds=config["optimization"]["bounds"],
    script:
        "../scripts/sobol.py"


rule decision_trees:
    input:
        pareto=primary_front("pareto.parquet"),
        generations=primary_front("last_generations.parquet"),
    output:
        designs=f"{RULES_DIR}/designs_400.parquet",
        rules=f"{RULES_DIR}/tree_rules.txt",
        first_splits=f"{RULES_DIR}/tree_first_splits.json",
        figure=report(
            f"{RESULTS}/figures/decision_trees.png",
            caption="../report/decision_trees.rst",
            category="5. Design rules",
        ),
    log:
        f"{RESULTS}/logs/decision_trees.log",
    benchmark:
        f"{RESULTS}/benchmarks/decision_trees.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("decision_trees.py"),
        tree_depth=config["design_rules"]["tree_depth"],
        seed=config["design_rules"]["seed"],
    script:
        "../scripts/decision_trees.py"


rule correlations:
    input:
        designs=rules.decision_trees.output.designs,
    output:
        table=f"{RULES_DIR}/correlations.parquet",
        figure=report(
            f"{RESULTS}/figures/correlations.png",
            caption="../report/correlations.rst",
            category="5. Design rules",
        ),
    log:
        f"{RESULTS}/logs/correlations.log",
    benchmark:
        f"{RESULTS}/benchmarks/correlations.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("correlations.py"),
        alpha=config["design_rules"]["alpha"],
    script:
        "../scripts/correlations.py"


rule eta_derivatives_shard:
    input:
        rules.select_mechanisms.output.mechanisms,
    output:
        f"{RULES_DIR}/eta_derivatives/shard-{{shard}}.parquet",
    log:
        f"{RESULTS}/logs/eta_derivatives/shard-{{shard}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/eta_derivatives/shard-{{shard}}.tsv"
    wildcard_constraints:
        shard=r"\d+",
    priority: 5  # long side jobs: into the cores the critical path leaves free, before plots
    conda:
        ENV
    params:
        code=code("eta_derivatives_shard.py"),
        shards=config["design_rules"]["shards"],
        step=config["design_rules"]["derivative_step"],
        most_designs=config["design_rules"]["derivative_designs"],
        seed=config["design_rules"]["seed"],
        operating_range=config["operating_range"],
        task_points=TASK_POINTS,
        resolution={k: config["workspace"][k] for k in ("n_delta", "n_levels")},
    script:
        "../scripts/eta_derivatives_shard.py"


rule eta_derivatives:
    input:
        expand(f"{RULES_DIR}/eta_derivatives/shard-{{shard}}.parquet", shard=RULE_SHARDS),
    output:
        table=f"{RULES_DIR}/eta_derivatives.parquet",
        figure=report(
            f"{RESULTS}/figures/eta_derivatives.png",
            caption="../report/eta_derivatives.rst",
            category="5. Design rules",
        ),
    log:
        f"{RESULTS}/logs/eta_derivatives.log",
    benchmark:
        f"{RESULTS}/benchmarks/eta_derivatives.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("eta_derivatives.py"),
    script:
        "../scripts/eta_derivatives.py"


rule design_rules_summary:
    input:
        unpack(study_inputs),
        sobol=rules.sobol.output.indices,
        first_splits=rules.decision_trees.output.first_splits,
        correlations=rules.correlations.output.table,
        derivatives=rules.eta_derivatives.output.table,
        pareto=primary_front("pareto.parquet"),
        dataset=rules.gather_dataset.output.dataset,
    output:
        summary=f"{RULES_DIR}/summary.md",  # in the report as a page (rule markdown_pages)
        table=f"{RULES_DIR}/findings.parquet",
    log:
        f"{RESULTS}/logs/design_rules_summary.log",
    benchmark:
        f"{RESULTS}/benchmarks/design_rules_summary.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("design_rules_summary.py"),
        alpha=config["design_rules"]["alpha"],
        primary=config["optimization"]["formulation"],
        payload_kg=config["task"]["payload_kg"],
    script:
        "../scripts/design_rules_summary.py"

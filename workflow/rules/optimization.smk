# Stage 4: NSGA-II on the surrogate, one folder per formulation, checked against the physics.

STAGE4_OUTPUTS = [
    *expand(f"{OPT}/{{formulation}}/verification.json", formulation=FORMULATIONS),
    *expand(f"{RESULTS}/figures/{{formulation}}/pareto_3d.png", formulation=FORMULATIONS),
    f"{OPT}/comparison.md",
]


wildcard_constraints:
    formulation="paper|ratios",


rule optimize:
    input:
        model=rules.train_surrogate.output.model,
        dataset=rules.gather_dataset.output.dataset,
    output:
        pareto=f"{OPT}/{{formulation}}/pareto.parquet",
        generations=f"{OPT}/{{formulation}}/last_generations.parquet",
        hypervolume=f"{OPT}/{{formulation}}/hypervolume.parquet",
        front_3d=report(
            f"{RESULTS}/figures/{{formulation}}/pareto_3d.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="{formulation} formulation",
        ),
        front_pairs=report(
            f"{RESULTS}/figures/{{formulation}}/pareto_pairs.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="{formulation} formulation",
        ),
        designs=report(
            f"{RESULTS}/figures/{{formulation}}/pareto_designs.png",
            caption="../report/pareto_designs.rst",
            category="4. Optimisation",
            subcategory="{formulation} formulation",
        ),
        infill=f"{OPT}/{{formulation}}/infill.parquet",
        rounds=f"{OPT}/{{formulation}}/infill.json",
        infill_figure=report(
            f"{RESULTS}/figures/{{formulation}}/infill.png",
            caption="../report/infill.rst",
            category="4. Optimisation",
            subcategory="{formulation} formulation",
        ),
    log:
        f"{RESULTS}/logs/optimize/{{formulation}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/optimize/{{formulation}}.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("optimize.py"),
        formulation=lambda w: w.formulation,
        front=lambda w: optimization_section(config, w.formulation),
    script:
        "../scripts/optimize.py"


rule verify_pareto:
    input:
        pareto=rules.optimize.output.pareto,
        rounds=rules.optimize.output.rounds,
        infill=rules.optimize.output.infill,
    output:
        table=f"{OPT}/{{formulation}}/verification.parquet",
        summary=f"{OPT}/{{formulation}}/verification.json",
    log:
        f"{RESULTS}/logs/verify_pareto/{{formulation}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/verify_pareto/{{formulation}}.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("verify_pareto.py"),
        formulation=lambda w: w.formulation,
        front=lambda w: optimization_section(config, w.formulation),
    script:
        "../scripts/verify_pareto.py"


rule compare_fronts:
    input:
        fronts=expand(f"{OPT}/{{formulation}}/verification.parquet", formulation=FORMULATIONS),
        dataset=rules.gather_dataset.output.dataset,
    output:
        summary=f"{OPT}/comparison.md",  # in the report as a page (rule markdown_pages)
        data=f"{OPT}/comparison.json",
    log:
        f"{RESULTS}/logs/compare_fronts.log",
    benchmark:
        f"{RESULTS}/benchmarks/compare_fronts.tsv"
    conda:
        ENV
    params:
        code=code("compare_fronts.py"),
        formulations=FORMULATIONS,
        primary=config["optimization"]["formulation"],
    script:
        "../scripts/compare_fronts.py"

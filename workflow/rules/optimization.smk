# Stage 4: NSGA-II on the surrogate (paper and ratios formulations), checked against the physics.

OPT = f"{RESULTS}/optimization"
STAGE4_OUTPUTS = [
    f"{OPT}/verification.json",
    f"{OPT}/ratios/verification.json",
    f"{OPT}/comparison.md",
    f"{RESULTS}/figures/pareto_3d.png",
    f"{RESULTS}/figures/ratios/pareto_3d.png",
]


rule optimize:
    input:
        model=rules.train_surrogate.output.model,
        dataset=rules.gather_dataset.output.dataset,
    output:
        pareto=f"{OPT}/pareto.parquet",
        generations=f"{OPT}/last_generations.parquet",
        hypervolume=f"{OPT}/hypervolume.parquet",
        front_3d=report(
            f"{RESULTS}/figures/pareto_3d.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="paper formulation",
        ),
        front_pairs=report(
            f"{RESULTS}/figures/pareto_pairs.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="paper formulation",
        ),
        designs=report(
            f"{RESULTS}/figures/pareto_designs.png",
            caption="../report/pareto_designs.rst",
            category="4. Optimisation",
            subcategory="paper formulation",
        ),
    params:
        code=code("optimize.py"),
        formulation="paper",
        optimization=optimization_settings(),
        ratio_bounds=config["sampling"]["bounds"],
        operating_range=config["operating_range"],
        task_points=config["task"]["points"],
        scale=config["scale"],
        workspace=fit_workspace(),
        filters=config["filters"],
    log:
        f"{RESULTS}/logs/optimize.log",
    benchmark:
        f"{RESULTS}/benchmarks/optimize.tsv"
    conda:
        ENV
    script:
        "../scripts/optimize.py"


use rule optimize as optimize_ratios with:
    output:
        pareto=f"{OPT}/ratios/pareto.parquet",
        generations=f"{OPT}/ratios/last_generations.parquet",
        hypervolume=f"{OPT}/ratios/hypervolume.parquet",
        front_3d=report(
            f"{RESULTS}/figures/ratios/pareto_3d.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="ratios formulation",
        ),
        front_pairs=report(
            f"{RESULTS}/figures/ratios/pareto_pairs.png",
            caption="../report/pareto.rst",
            category="4. Optimisation",
            subcategory="ratios formulation",
        ),
        designs=report(
            f"{RESULTS}/figures/ratios/pareto_designs.png",
            caption="../report/pareto_designs.rst",
            category="4. Optimisation",
            subcategory="ratios formulation",
        ),
    params:
        code=code("optimize.py"),
        formulation="ratios",
        optimization=optimization_settings(),
        ratio_bounds=config["sampling"]["bounds"],
        operating_range=config["operating_range"],
        task_points=config["task"]["points"],
        scale=config["scale"],
        workspace=fit_workspace(),
        filters=config["filters"],
    log:
        f"{RESULTS}/logs/optimize_ratios.log",
    benchmark:
        f"{RESULTS}/benchmarks/optimize_ratios.tsv"


rule verify_pareto:
    input:
        pareto=rules.optimize.output.pareto,
    output:
        table=f"{OPT}/verification.parquet",
        summary=f"{OPT}/verification.json",
    params:
        code=code("verify_pareto.py"),
        operating_range=config["operating_range"],
        task_points=config["task"]["points"],
        scale=config["scale"],
        workspace=fit_workspace(),
        filters=config["filters"],
        cad=config["cad"],
        duty=config["dynamics"]["duty"],
        payload_kg=config["task"]["payload_kg"],
        ratio_bounds=config["sampling"]["bounds"],
    log:
        f"{RESULTS}/logs/verify_pareto.log",
    benchmark:
        f"{RESULTS}/benchmarks/verify_pareto.tsv"
    conda:
        ENV
    script:
        "../scripts/verify_pareto.py"


use rule verify_pareto as verify_pareto_ratios with:
    input:
        pareto=rules.optimize_ratios.output.pareto,
    output:
        table=f"{OPT}/ratios/verification.parquet",
        summary=f"{OPT}/ratios/verification.json",
    log:
        f"{RESULTS}/logs/verify_pareto_ratios.log",
    benchmark:
        f"{RESULTS}/benchmarks/verify_pareto_ratios.tsv"


rule compare_fronts:
    input:
        paper=rules.verify_pareto.output.table,
        ratios=rules.verify_pareto_ratios.output.table,
        dataset=rules.gather_dataset.output.dataset,
    output:
        summary=report(
            f"{OPT}/comparison.md",
            caption="../report/comparison.rst",
            category="4. Optimisation",
        ),
        data=f"{OPT}/comparison.json",
    params:
        code=code("compare_fronts.py"),
        primary=config["optimization"]["formulation"],
    log:
        f"{RESULTS}/logs/compare_fronts.log",
    conda:
        ENV
    script:
        "../scripts/compare_fronts.py"

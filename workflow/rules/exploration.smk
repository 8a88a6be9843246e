# Looking at the results: the interactive fronts and the selected design in motion.

EXPLORATION_OUTPUTS = [
    *expand(f"{OPT}/{{formulation}}/pareto.html", formulation=FORMULATIONS),
    f"{OPT}/{config['optimization']['formulation']}/cycles.parquet",
    f"{REAL}/task_motion.gif",
]


rule front_cycles:
    input:
        verification=f"{OPT}/{{formulation}}/verification.parquet",
    output:
        cycles=f"{OPT}/{{formulation}}/cycles.parquet",
    log:
        f"{RESULTS}/logs/front_cycles/{{formulation}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/front_cycles/{{formulation}}.tsv"
    conda:
        ENV
    params:
        code=code("front_cycles.py"),
        cycles=cycles_section(config),
        cycle=CYCLE,
    script:
        "../scripts/front_cycles.py"


rule pareto_html:
    input:
        verification=f"{OPT}/{{formulation}}/verification.parquet",
        # the time-optimal cycles of the front the later stages use
        cycles=lambda w: (
            f"{OPT}/{w.formulation}/cycles.parquet"
            if w.formulation == config["optimization"]["formulation"]
            else []
        ),
        selected=rules.select_design.output.choice,
    output:
        html=report(
            f"{OPT}/{{formulation}}/pareto.html",
            caption="../report/pareto_html.rst",
            category="4. Optimisation",
            subcategory="{formulation} formulation",
        ),
    log:
        f"{RESULTS}/logs/pareto_html/{{formulation}}.log",
    benchmark:
        f"{RESULTS}/benchmarks/pareto_html/{{formulation}}.tsv"
    conda:
        ENV
    params:
        code=code("pareto_html.py"),
        formulation=lambda w: w.formulation,
    script:
        "../scripts/pareto_html.py"


rule task_motion:
    input:
        selected=rules.select_design.output.choice,
        payload=rules.payload_test.output.result,
        series=rules.payload_test.output.series,
    output:
        gif=f"{REAL}/task_motion.gif",
        frames=f"{REAL}/task_motion.json",
        viewer=report(
            f"{REAL}/task_motion.html",
            caption="../report/task_motion.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/task_motion.log",
    benchmark:
        f"{RESULTS}/benchmarks/task_motion.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("task_motion.py"),
        task_points=TASK_POINTS,
        mirrored=MIRRORED,
        operating_range=config["operating_range"],
    script:
        "../scripts/task_motion.py"

# Looking at the results: the interactive fronts and the selected design in motion.

EXPLORATION_OUTPUTS = [
    *expand(f"{OPT}/{{formulation}}/pareto.html", formulation=FORMULATIONS),
    f"{REAL}/task_motion.gif",
]


rule pareto_html:
    input:
        verification=f"{OPT}/{{formulation}}/verification.parquet",
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

# The study: experiments that test why this run's design rules and Table 3 differ from the paper's.

STUDY = f"{RESULTS}/study"


rule study_lengths:
    input:
        dataset=rules.gather_dataset.output.dataset,
    output:
        table=f"{STUDY}/independent_lengths.parquet",
        outcome=f"{STUDY}/independent_lengths.json",
        figure=report(
            f"{RESULTS}/figures/study_lengths.png",
            caption="../report/study_lengths.rst",
            category="5. Design rules",
            subcategory="Study",
        ),
    log:
        f"{RESULTS}/logs/study_lengths.log",
    benchmark:
        f"{RESULTS}/benchmarks/study_lengths.tsv"
    priority: 5  # long side jobs: into the cores the critical path leaves free, before plots
    conda:
        ENV
    params:
        code=code("study_lengths.py"),
        study={k: config["study"][k] for k in ("n_designs", "seed")},
        tree_depth=config["design_rules"]["tree_depth"],
        cad=config["cad"],
        material=config["material"],
        duty=config["dynamics"]["duty"],
        operating_range=config["operating_range"],
        payload_kg=config["task"]["payload_kg"],
    script:
        "../scripts/study_lengths.py"


rule study_table3:
    input:
        selected=rules.select_design.output.choice,
        links=rules.topology_optimize.output.links,
    output:
        table=f"{STUDY}/table3_sweep.parquet",
        figure=report(
            f"{RESULTS}/figures/study_table3.png",
            caption="../report/study_table3.rst",
            category="5. Design rules",
            subcategory="Study",
        ),
    log:
        f"{RESULTS}/logs/study_table3.log",
    benchmark:
        f"{RESULTS}/benchmarks/study_table3.tsv"
    priority: 5  # the design rules' chain to the summary: ahead of the figures, not last alone
    conda:
        ENV
    params:
        code=code("study_table3.py"),
        payloads_kg=config["study"]["payloads_kg"],
        payload_kg=config["task"]["payload_kg"],
        cad=config["cad"],
        material=config["material"],
        duty=config["dynamics"]["duty"],
        operating_range=config["operating_range"],
    script:
        "../scripts/study_table3.py"

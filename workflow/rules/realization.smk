# Stage 6: printable design, topology-optimised links, STL files and a simulated payload test.

LINKS = ["lower_arm", "crank", "coupler", "upper_arm"]
STAGE6_OUTPUTS = [
    f"{REAL}/torques.json",
    f"{REAL}/payload_test.json",
    f"{REAL}/selected.json",
    f"{REAL}/kit/exploded.png",
]


rule select_design:
    input:
        fronts=expand(f"{OPT}/{{formulation}}/verification.parquet", formulation=FORMULATIONS),
        dataset=rules.gather_dataset.output.dataset,
        # the fronts' cycles only when the selection ranks by them
        cycles=(
            f"{OPT}/{config['optimization']['formulation']}/cycles.parquet"
            if config["printing"]["selection_rule"] == "fastest"
            else []
        ),
    output:
        choice=f"{REAL}/choice.json",
        machine=f"{REAL}/machine.json",  # the realised machine: later rules never realise again
        figure=report(
            f"{RESULTS}/figures/selected_design.png",
            caption="../report/selected_design.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/select_design.log",
    benchmark:
        f"{RESULTS}/benchmarks/select_design.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("select_design.py"),
        realization=REALIZATION,
        selection_rule=config["printing"]["selection_rule"],
        primary=config["optimization"]["formulation"],
        formulations=FORMULATIONS,
    script:
        "../scripts/select_design.py"


rule topology_optimize:
    input:
        machine=rules.select_design.output.machine,
    output:
        torques=f"{REAL}/torques.json",
        table=f"{REAL}/torques.md",  # in the report as a page (rule markdown_pages)
        topology=f"{REAL}/topology.json",
        links=f"{REAL}/optimised_links.json",
        stl_check=f"{REAL}/stl_check.json",
        stl_before=expand(f"{REAL}/stl/before/{{link}}.stl", link=LINKS),
        stl_after=expand(f"{REAL}/stl/after/{{link}}.stl", link=LINKS),
        drawing=report(
            f"{REAL}/drawing.svg", caption="../report/drawing.rst", category="6. Realisation"
        ),
        drawing_png=f"{REAL}/drawing.png",
        bom_csv=f"{REAL}/bom.csv",
        bom_md=f"{REAL}/bom.md",
        kit=f"{REAL}/kit/kit.json",
        figure=report(
            f"{RESULTS}/figures/topology_links.png",
            caption="../report/topology_links.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/topology_optimize.log",
    benchmark:
        f"{RESULTS}/benchmarks/topology_optimize.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("topology_optimize.py"),
        realization=REALIZATION,
        topology=config["topology"],
    script:
        "../scripts/topology_optimize.py"


rule kit_files:
    input:
        kit=rules.topology_optimize.output.kit,
    output:
        step=directory(f"{REAL}/kit/step"),
        dxf=directory(f"{REAL}/kit/dxf"),
        exploded=report(
            f"{REAL}/kit/exploded.png",
            caption="../report/kit_exploded.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/kit_files.log",
    benchmark:
        f"{RESULTS}/benchmarks/kit_files.tsv"
    conda:
        ENV
    params:
        code=code("kit_files.py"),
    script:
        "../scripts/kit_files.py"


rule payload_test:
    input:
        selected=rules.select_design.output.choice,
        links=rules.topology_optimize.output.links,
        kit=rules.topology_optimize.output.kit,
    output:
        result=f"{REAL}/payload_test.json",
        series=f"{REAL}/payload_test_series.parquet",
        figure=report(
            f"{RESULTS}/figures/payload_test.png",
            caption="../report/payload_test.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/payload_test.log",
    benchmark:
        f"{RESULTS}/benchmarks/payload_test.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("payload_test.py"),
        realization=REALIZATION,
        payload_test=config["payload_test"],
    script:
        "../scripts/payload_test.py"


rule cycle_time:
    input:
        choice=rules.select_design.output.choice,
        machine=rules.select_design.output.machine,
        links=rules.topology_optimize.output.links,
        topology=rules.topology_optimize.output.topology,
        kit=rules.topology_optimize.output.kit,
        payload=rules.payload_test.output.result,
    output:
        cycle=f"{REAL}/cycle.json",
        trajectory=f"{REAL}/cycle_trajectory.csv",
        figure=report(
            f"{RESULTS}/figures/cycle_torques.png",
            caption="../report/cycle_torques.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/cycle_time.log",
    benchmark:
        f"{RESULTS}/benchmarks/cycle_time.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("cycle_time.py"),
        jerk_time_s=jerk_time_s(),
        settling=config["settling"],
        realization=REALIZATION,
        payload_test=config["payload_test"],
        cycle=CYCLE,
    script:
        "../scripts/cycle_time.py"


rule standard_cycle:
    input:
        choice=rules.select_design.output.choice,
        machine=rules.select_design.output.machine,
        links=rules.topology_optimize.output.links,
        topology=rules.topology_optimize.output.topology,
        kit=rules.topology_optimize.output.kit,
        payload=rules.payload_test.output.result,
    output:
        cycle=f"{REAL}/standard_cycle.json",
    log:
        f"{RESULTS}/logs/standard_cycle.log",
    benchmark:
        f"{RESULTS}/benchmarks/standard_cycle.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("standard_cycle.py"),
        jerk_time_s=jerk_time_s(),
        realization=REALIZATION,
        payload_test=config["payload_test"],
    script:
        "../scripts/standard_cycle.py"


rule accuracy_budget:
    input:
        choice=rules.select_design.output.choice,
        machine=rules.select_design.output.machine,
        links=rules.topology_optimize.output.links,
        topology=rules.topology_optimize.output.topology,
        kit=rules.topology_optimize.output.kit,
        payload=rules.payload_test.output.result,
        cycle=rules.cycle_time.output.cycle,
        standard=rules.standard_cycle.output.cycle,
    output:
        selected=f"{REAL}/selected.json",
        figure=report(
            f"{RESULTS}/figures/accuracy_budget.png",
            caption="../report/accuracy_budget.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/accuracy_budget.log",
    benchmark:
        f"{RESULTS}/benchmarks/accuracy_budget.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("accuracy_budget.py"),
        realization=REALIZATION,
        iso=iso_section(config),
    script:
        "../scripts/accuracy_budget.py"

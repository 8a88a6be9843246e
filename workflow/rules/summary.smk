# The headline numbers of the run in one Markdown page.


rule summary:
    input:
        filters=rules.select_mechanisms.output.report,
        status=rules.gather_dataset.output.status,
        metrics=rules.train_surrogate.output.metrics,
        comparison=rules.compare_fronts.output.data,
        findings=rules.design_rules_summary.output.table,
        selected=rules.select_design.output.selected,
        torques=rules.topology_optimize.output.torques,
        payload=rules.payload_test.output.result,
        topology=rules.topology_optimize.output.topology,
        bom=rules.topology_optimize.output.bom_md,
    output:
        report(f"{RESULTS}/summary.md", caption="../report/summary.rst", category="0. Summary"),
    log:
        f"{RESULTS}/logs/summary.log",
    conda:
        ENV
    params:
        code=code("summary.py"),
    script:
        "../scripts/summary.py"

# The headline numbers of the run in one Markdown page.


rule summary:
    input:
        filters=rules.select_mechanisms.output.report,
        status=rules.gather_dataset.output.status,
        metrics=rules.train_surrogate.output.metrics,
        comparison=rules.compare_fronts.output.data,
        findings=rules.design_rules_summary.output.table,
        selected=rules.accuracy_budget.output.selected,
        torques=rules.topology_optimize.output.torques,
        payload=rules.payload_test.output.result,
        topology=rules.topology_optimize.output.topology,
        bom=rules.topology_optimize.output.bom_md,
        bom_csv=rules.topology_optimize.output.bom_csv,
        kit=rules.topology_optimize.output.kit,
    output:
        summary=f"{RESULTS}/summary.md",  # in the report as a page (rule markdown_pages)
        datasheet=f"{RESULTS}/datasheet.md",  # the same
        envelope=report(
            f"{RESULTS}/figures/envelope.png",
            caption="../report/envelope.rst",
            category="6. Realisation",
        ),
    log:
        f"{RESULTS}/logs/summary.log",
    benchmark:
        f"{RESULTS}/benchmarks/summary.tsv"
    conda:
        ENV
    params:
        code=code("summary.py"),
        density_kg_m3=config["material"]["density_kg_m3"],
        theta1_deg=config["operating_range"]["theta1_deg"],
        theta2_min_deg=config["operating_range"]["theta2_min_deg"],
    script:
        "../scripts/summary.py"


# The Markdown results as HTML pages: Snakemake's report shows HTML outputs inline and Markdown
# ones only as download links. Each page: (Markdown file, caption, title).
MARKDOWN_PAGES = {
    "summary": (f"{RESULTS}/summary.md", "summary.rst", "Summary of the run"),
    "datasheet": (f"{RESULTS}/datasheet.md", "datasheet.rst", "Datasheet of the design"),
    "comparison": (f"{OPT}/comparison.md", "comparison.rst", "The fronts side by side"),
    "design_rules": (
        f"{RULES_DIR}/summary.md",
        "design_rules_summary.rst",
        "Design rules against the paper",
    ),
    "torques": (f"{REAL}/torques.md", "torques.rst", "Torques before and after topology"),
    "surrogate": (
        f"{RESULTS}/surrogate/metrics.md",
        "surrogate_metrics.rst",
        "Surrogate accuracy",
    ),
}
SUMMARY_OUTPUTS = [f"{RESULTS}/html/{name}.html" for name in MARKDOWN_PAGES]


rule markdown_pages:
    input:
        **{name: page[0] for name, page in MARKDOWN_PAGES.items()},
    output:
        **{
            name: report(
                f"{RESULTS}/html/{name}.html",
                caption=f"../report/{page[1]}",
                category="0. Summary",
            )
            for name, page in MARKDOWN_PAGES.items()
        },
    log:
        f"{RESULTS}/logs/markdown_pages.log",
    benchmark:
        f"{RESULTS}/benchmarks/markdown_pages.tsv"
    conda:
        ENV
    params:
        code=code("markdown_pages.py"),
        titles={name: page[2] for name, page in MARKDOWN_PAGES.items()},
    script:
        "../scripts/markdown_pages.py"

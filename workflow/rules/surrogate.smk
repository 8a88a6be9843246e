# Stage 3: the MLP surrogate from the 6 scaled lengths to (eta, tau1, tau2).

STAGE3_OUTPUTS = [
    f"{RESULTS}/surrogate/model.json",
    f"{RESULTS}/surrogate/metrics.json",
    f"{RESULTS}/surrogate/metrics.md",
    f"{RESULTS}/figures/surrogate_parity.png",
]


rule train_surrogate:
    input:
        rules.gather_dataset.output.dataset,
    output:
        model=f"{RESULTS}/surrogate/model.json",
        metrics=f"{RESULTS}/surrogate/metrics.json",
        table=f"{RESULTS}/surrogate/metrics.md",  # in the report as a page (markdown_pages)
        parity=report(
            f"{RESULTS}/figures/surrogate_parity.png",
            caption="../report/surrogate_parity.rst",
            category="3. Surrogate",
        ),
    log:
        f"{RESULTS}/logs/train_surrogate.log",
    benchmark:
        f"{RESULTS}/benchmarks/train_surrogate.tsv"
    priority: 10  # the critical path: ahead of the design-rule shards
    conda:
        ENV
    params:
        code=code("train_surrogate.py"),
        surrogate=surrogate_section(config),
    script:
        "../scripts/train_surrogate.py"

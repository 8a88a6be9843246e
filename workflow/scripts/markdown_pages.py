"""Rule markdown_pages: the run's Markdown results as HTML pages for the report."""

from qsm.report.markdown_pages import write_markdown_html
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:  # noqa: F821
    titles = snakemake.params.titles  # noqa: F821
    for key, source in snakemake.input.items():  # noqa: F821
        write_markdown_html(source, snakemake.output[key], titles[key])  # noqa: F821
        log.info(f"{source} -> {snakemake.output[key]}")  # noqa: F821

"""Rule markdown_pages: the run's Markdown results as HTML pages for the report."""

from qsm.report.markdown_pages import write_markdown_html
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    titles = snakemake.params.titles
    for key, source in snakemake.input.items():
        write_markdown_html(source, snakemake.output[key], titles[key])
        log.info(f"{source} -> {snakemake.output[key]}")

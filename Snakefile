# qsm-design: the entry point `snakemake --cores 2` finds in the checkout. The workflow itself is
# workflow/Snakefile (the layout of the Snakemake workflow catalog); this file includes it, so
# paths inside it stay relative to workflow/ and results go to the working directory.


include: "workflow/Snakefile"


# Snakemake takes the default target from this file, never from an included one: everything that
# workflow/Snakefile's `all` asks for.
rule default:
    default_target: True
    input:
        rules.all.input,

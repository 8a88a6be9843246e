"""Rule kit_files: the builder's kit's STEP and DXF files and its exploded assembly view."""

import json

from qsm.realization.kit.kit_files import exploded_view, write_dxf, write_step
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:
    out = snakemake.output
    with open(snakemake.input.kit) as fh:
        kit = json.load(fh)
    layout = kit["layout"]
    steps = write_step(layout, out.step)
    log.info("STEP: %s", ", ".join(sorted(steps)))
    dxf = write_dxf(layout, out.dxf)
    log.info("DXF: %s", ", ".join(sorted(dxf)))
    exploded_view(layout, kit["step_of"], out.exploded)

"""Rule task_motion: the selected design moving through the payload test, as a GIF and a page
that plays it with play/pause and a slider."""

import json

from qsm.config.settings import physics
from qsm.physics.task import min_enclosing_circle
from qsm.report.animation import frames_record, write_task_motion
from qsm.report.motion_page import write_viewer_html
from qsm.workflow.json_files import write_json
from qsm.workflow.logs import logged
from qsm.workflow.tables import read_table

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    inp = snakemake.input
    out = snakemake.output
    with open(inp.selected) as fh:
        selected = json.load(fh)
    with open(inp.payload) as fh:
        payload = json.load(fh)
    series = read_table(inp.series)
    design = selected["design_m"]
    verdict = "passed" if payload["passed"] else f"FAILED ({payload['reason']})"
    title = (
        f"selected design ({selected['formulation']}): l1 {design[0]:.3f} m, "
        f"payload {payload['payload_kg']:g} kg, test {verdict}"
        + (", mirrored (x > 0)" if p.mirrored else "")
    )
    result = write_task_motion(
        design,
        series,
        p.task_points,
        min_enclosing_circle(p.task_points),
        physics.operating_range(p.operating_range),
        payload["limit_Nm"],
        out.gif,
        title=title,
        mirrored=p.mirrored,
    )
    record = frames_record(result, design)
    write_json(out.frames, record)
    peak = payload["peak_torque_Nm"]
    lines = [
        f"{record['n_frames']} frames at {record['fps']:g} frames/s: the payload test's "
        f"{payload['duration_s']:.2f} s in real time (results/realization/task_motion.gif)",
        "lengths l1, l2, l3, l4, EE_x, EE_y (mm): " + ", ".join(f"{1e3 * v:.1f}" for v in design),
        f"peak requested torques {peak[0]:.1f} / {peak[1]:.1f} N m against the limits "
        f"{payload['limit_Nm'][0]:g} / {payload['limit_Nm'][1]:g} N m "
        f"({'the drives at standstill' if payload.get('drives') else 'fixed'}); largest tracking "
        "error "
        f"{payload['max_tracking_error_deg']:.3f} deg",
    ]
    write_viewer_html(out.gif, out.viewer, title, lines, record["fps"])
    log.info("%d frames; %s", record["n_frames"], "; ".join(lines))

"""Rule payload_test: forward simulation of the optimised design carrying the task payload."""

import json

import numpy as np

from qsm.mechanisms.dataset import cad_settings
from qsm.realisation.export import props_from_json
from qsm.realisation.payload import PayloadSettings, payload_test, plot_payload_test, summary
from qsm.workflow.logs import logged

with logged(snakemake.log[0]) as log:  # noqa: F821
    p = snakemake.params  # noqa: F821
    inp = snakemake.input  # noqa: F821
    out = snakemake.output  # noqa: F821
    with open(inp.selected) as fh:
        design = np.asarray(json.load(fh)["design_m"])
    with open(inp.links) as fh:
        props = props_from_json(json.load(fh))
    s = p.payload_test
    settings = PayloadSettings(
        payload_kg=p.payload_kg,
        torque_limits_Nm=tuple(s["torque_limits_Nm"]),
        segment_duration_s=s["segment_duration_s"],
        dwell_s=s["dwell_s"],
        return_to_start=s["return_to_start"],
        kp_Nm_rad=tuple(s["kp_Nm_rad"]),
        kd_Nms_rad=tuple(s["kd_Nms_rad"]),
        tracking_tolerance_deg=s["tracking_tolerance_deg"],
        plant_mass_error=s["plant_mass_error"],
        theta1_range_deg=tuple(p.operating_range["theta1_deg"]),
        theta2_min_deg=p.operating_range["theta2_min_deg"],
    )
    result = payload_test(design, p.task_points, cad_settings(p.cad), props, settings)
    scalars = summary(result)
    with open(out.result, "w") as fh:
        json.dump(scalars, fh, indent=2, default=lambda v: np.asarray(v).tolist())
    plot_payload_test(result, out.figure)
    log.info(
        "payload test: passed %s, max tracking error %.4f deg, peak torque %s N m",
        scalars["passed"],
        scalars["max_tracking_error_deg"],
        scalars["peak_torque_Nm"],
    )

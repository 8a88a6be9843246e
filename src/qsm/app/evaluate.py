"""Evaluate one design the way the workflow does (for the command line and notebooks)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from qsm.config.settings import physics
from qsm.embodiment.parts.printing import all_links_fit
from qsm.mechanisms.filters import kinematic_checks
from qsm.mechanisms.scale import fit_design
from qsm.physics.duty import duty_cycle
from qsm.physics.dynamics import evaluate_mechanism
from qsm.physics.kinematics import DESIGN_NAMES, RATIO_NAMES
from qsm.physics.mirror import is_mirrored


def _checked(
    values: Sequence[float], names: Sequence[str], what: str, unit: str = ""
) -> np.ndarray:
    """``values`` as an array of ``len(names)``; ``ValueError`` naming any that is not finite
    and positive."""
    v = np.asarray(values, dtype=float)
    if v.shape != (len(names),):
        raise ValueError(f"give the {len(names)} {what} {', '.join(names)}; got {v.size} values")
    bad = [f"{n}={x}" for n, x in zip(names, v, strict=True) if not (np.isfinite(x) and x > 0)]
    if bad:
        raise ValueError(f"{what} must be finite and positive{unit}: {', '.join(bad)}")
    return v


def checked_ratios(ratios: Sequence[float]) -> np.ndarray:
    """The 5 ratios as an array; ``ValueError`` naming any that is not finite and positive."""
    return _checked(ratios, RATIO_NAMES, "ratios")


def evaluate_ratios(ratios: Sequence[float], config: Mapping[str, Any]) -> dict[str, Any]:
    """Stages 1 and 2 for one unit design ``(l2, l3, l4, ee_x, ee_y)`` under a validated config.

    Returns the filter outcomes, ``mirrored`` (a task at x > 0, designed as its mirror image:
    :mod:`qsm.physics.mirror`), ``feasible``, ``scale`` (m), ``workspace_area_m2``, ``eta``, the
    scaled lengths (m) and, from the MuJoCo dynamics over the configured duty, ``tau1_Nm``,
    ``tau2_Nm`` and ``dynamics_status``; values that do not exist for an infeasible design are
    None.
    """
    r = checked_ratios(ratios)
    fit_settings = physics.fit(
        config["operating_range"], config["task"]["points"], config["scale"], config["workspace"]
    )
    checks = {
        name: bool(ok[0])
        for name, ok in kinematic_checks(
            r, fit_settings.op, config["filters"]["min_transmission_angle_deg"]
        ).items()
    }
    out: dict[str, Any] = {"ratios": dict(zip(RATIO_NAMES, r.tolist(), strict=True)), **checks}
    out["mirrored"] = is_mirrored(config["task"]["points"])  # designed as the mirror image
    out["task_disk"] = {
        "centre_m": list(fit_settings.disk.centre),
        "radius_m": fit_settings.disk.radius,
    }
    fit = fit_design(r, fit_settings) if all(checks.values()) else None
    out["feasible"] = bool(fit and fit["feasible"])
    out["reason"] = (
        fit["reason"] if fit else ", ".join(k for k, ok in checks.items() if not ok) + " failed"
    )
    scale = fit["scale_m"] if out["feasible"] else None
    out["scale"] = scale
    out["workspace_area_m2"] = fit["workspace_area_m2"] if out["feasible"] else None
    out["eta"] = fit["eta"] if out["feasible"] else None
    out["design_m"] = (
        dict(zip(DESIGN_NAMES, [scale, *(r * scale).tolist()], strict=True)) if scale else None
    )
    out.update(tau1_Nm=None, tau2_Nm=None, dynamics_status=None)
    if out["design_m"] is not None:
        dyn = evaluate_mechanism(
            list(out["design_m"].values()),
            duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"])),
            physics.cad(config["cad"], config["material"]),
            config["task"]["payload_kg"],
        )
        ok = dyn["status"] == "ok"
        out["tau1_Nm"] = dyn["tau1_Nm"] if ok else None
        out["tau2_Nm"] = dyn["tau2_Nm"] if ok else None
        out["dynamics_status"] = dyn["status"] + (f": {dyn['status_reason']}" if not ok else "")
    return out


#: The longest link (m) a printed arm's length can mean; longer reads as a length in millimetres.
LONGEST_LINK_M = 5.0


def checked_lengths(lengths: Sequence[float]) -> np.ndarray:
    """The 6 lengths (m) as an array; ``ValueError`` naming any that is not finite and
    positive, or longer than :data:`LONGEST_LINK_M` (millimetres given for metres)."""
    d = _checked(lengths, DESIGN_NAMES, "lengths", " (m)")
    if (d > LONGEST_LINK_M).any():
        k = int(np.flatnonzero(d > LONGEST_LINK_M)[0])
        raise ValueError(
            f"{DESIGN_NAMES[k]} = {d[k]:g} m is longer than any printed arm's link "
            f"({LONGEST_LINK_M:g} m): lengths are in metres ({d[k]:g} mm is {d[k] / 1e3:g} m)"
        )
    return d


#: ``--lengths`` answers with ``--ratios``' keys: the verification's true values renamed.
TRUE_KEYS = {"eta_true": "eta", "tau1_true_Nm": "tau1_Nm", "tau2_true_Nm": "tau2_Nm"}
#: The verification's columns that one design's evaluation does not fill (the front's own).
UNSET = (
    "in_table1",
    "print_excess_mm",
    "needed_volume_long_mm",
    "needed_volume_mid_mm",
    "needed_volume_short_mm",
    "tool_sag_mm",
    "within_tolerance",
)


def evaluate_lengths(lengths: Sequence[float], config: Mapping[str, Any]) -> dict[str, Any]:
    """One design given as its 6 lengths (m), at that scale (no refit), under a validated config:
    the true kinematics, task containment and clearance, eta and the MuJoCo torques of the
    optimisation's verification (under :func:`evaluate_ratios`' keys ``eta``, ``tau1_Nm``,
    ``tau2_Nm``), whether its links fit the configured printer, each link's strength and each
    joint's bearing, and each motor's drive. JSON-friendly (NaN as None)."""
    from qsm.config.settings.dataset import dataset_of
    from qsm.embodiment.drives.report import report_json
    from qsm.embodiment.strength.record import strength_json, strength_record
    from qsm.optimization.verify import verify_design

    d = checked_lengths(lengths)
    fit_settings = physics.fit_of(config)
    duty = physics.duty(config["dynamics"]["duty"], config["operating_range"])
    cad, payload = physics.cad(config["cad"], config["material"]), config["task"]["payload_kg"]
    out: dict[str, Any] = {
        "design_m": dict(zip(DESIGN_NAMES, d.tolist(), strict=True)),
        "mirrored": is_mirrored(config["task"]["points"]),
    }
    stage2 = dataset_of(config)  # the dataset's checks, as the rule dynamics builds them
    check = stage2.strength
    sized = check.section_scales(d)
    scale = None if sized is None else sized.scale
    true = verify_design(
        d, fit_settings, duty_cycle(duty), cad, payload, None if scale is None else scale[0]
    )
    true = {TRUE_KEYS.get(k, k): v for k, v in true.items() if k not in UNSET}
    out.update(
        {k: (None if isinstance(v, float) and not np.isfinite(v) else v) for k, v in true.items()}
    )
    volume = tuple(config["printing"]["build_volume_mm"])
    out["printable"] = bool(all_links_fit(d, cad, volume))
    if out["loop_closes"]:
        out["strength"] = strength_json(strength_record(d, check))
        out["drives"] = report_json(stage2.drives.report(d, scale))
    return out

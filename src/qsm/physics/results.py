"""The columns the dynamics gives each mechanism (Stage 2's first columns), with their units.

Light on purpose (no MuJoCo): :mod:`qsm.physics.dynamics` fills these keys and
:mod:`qsm.dataset.columns` documents the dataset with them.
"""

from __future__ import annotations

#: Each key of :func:`qsm.physics.dynamics.evaluate_mechanism`'s result and what it holds.
DYNAMICS_COLUMNS: dict[str, str] = {
    "tau1_Nm": "peak |torque| of motor 1 (lower arm) over the duty (N m)",
    "tau2_Nm": "peak |torque| of motor 2 (crank) over the duty (N m)",
    "theta1_at_tau1_peak_deg": "theta1 where |tau1| peaks (deg)",
    "theta2_at_tau1_peak_deg": "theta2 where |tau1| peaks (deg)",
    "theta1_at_tau2_peak_deg": "theta1 where |tau2| peaks (deg)",
    "theta2_at_tau2_peak_deg": "theta2 where |tau2| peaks (deg)",
    "tau1_rms_Nm": "time-weighted RMS torque of motor 1 over the moving duty (N m)",
    "tau2_rms_Nm": "time-weighted RMS torque of motor 2 over the moving duty (N m)",
    "coupler_force_peak_N": "peak coupler force at D, the D bearing load (N)",
    "transmission_angle_min_deg": "smallest transmission angle at D, folded into [0, 90] (deg)",
    "mass_lower_arm_kg": "lower arm mass (kg)",
    "mass_crank_kg": "crank mass (kg)",
    "mass_coupler_kg": "coupler mass (kg)",
    "mass_upper_arm_kg": "upper arm mass without payload (kg)",
    "status": "ok, or the failure: cad_invalid, loop_open, singular, nonfinite, error",
    "status_reason": "why a mechanism failed (empty when ok)",
}

"""The drive check's columns with their units, as Stage 2 adds them to the dataset
(:mod:`qsm.dataset.columns` collects every domain's)."""

from __future__ import annotations

#: The motors: index (1, 2) and what each drives.
MOTORS: dict[int, str] = {1: "lower arm", 2: "crank"}
#: Limits of a drive checked over the duty (:data:`qsm.embodiment.drives.utilization.CHECKS`).
DRIVE_CHECKS: tuple[str, ...] = ("motor_peak", "motor_rms", "motor_speed", "gear_peak", "gear_rms")
#: Columns of the drive check (:mod:`qsm.embodiment.drives.drive_checks`) that Stage 2 adds. Each
#: motor's drive columns describe the drive chosen for it or, when no drive of the catalogue
#: meets its duty, the one that comes nearest (its violation is then > 0).
DRIVE_COLUMNS: dict[str, str] = {
    **{
        key.format(j=j): text.format(j=j, motor=motor)
        for j, motor in MOTORS.items()
        for key, text in {
            "drive{j}_peak_torque_Nm": "peak |output torque| motor {j} ({motor}) must give over "
            "the duty, its drive's reflected inertia included (N m)",
            "drive{j}_rms_torque_Nm": "time-weighted RMS output torque of motor {j} (N m)",
            "drive{j}_peak_speed_rad_s": "peak |output speed| of motor {j} (rad/s)",
            "drive{j}_peak_power_W": "peak |torque x speed| at the output of motor {j} (W)",
            "drive{j}_motor": "catalogue key of the motor of drive {j} (chosen, or nearest)",
            "drive{j}_gearbox": "catalogue key of the gearbox of drive {j}",
            "drive{j}_ratio": "gear ratio of drive {j} (-)",
            "drive{j}_mass_kg": "mass of drive {j}, motor and gearbox (kg)",
            "drive{j}_reflected_inertia_kgm2": "(J_motor + J_gear,in) ratio^2 of drive {j}, "
            "the joint armature (kg m^2)",
            **{
                f"drive{{j}}_margin_{c}": f"1 - utilisation of drive {{j}}'s {c.replace('_', ' ')} "
                "limit (-, < 0 exceeded)"
                for c in DRIVE_CHECKS
            },
            "drive{j}_violation": "largest utilisation - 1 of drive {j} (<= 0: it meets the "
            "duty; > 0: no drive of the catalogue does)",
        }.items()
    },
    "drive_mass_kg": "mass of both drives (kg)",
    "drive_violation": "g14: the larger of the two motors' violations (<= 0: each motor has a "
    "drive in the catalogue)",
    "has_drives": "each motor has a drive in the catalogue that meets its duty (-)",
}

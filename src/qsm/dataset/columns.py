"""Stage 2's columns with their units: dynamics, strength, drives and stiffness.

Light on purpose (no MuJoCo, no trimesh): most later rules read the dataset through it and
:mod:`qsm.dataset.gathering`."""

from __future__ import annotations

from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.kinematics import LINK_NAMES
from qsm.physics.results import DYNAMICS_COLUMNS

#: Joints whose peak force the tables report: column suffix and :class:`JointLoads` field.
JOINT_COLUMNS: dict[str, str] = {
    "A_lower_arm": "a_lower",
    "A_crank": "a_crank",
    "B": "b",
    "C": "c",
    "D": "d",
    "E": "e",
}
#: Columns of the strength check (:mod:`qsm.embodiment.strength.link_checks`) that Stage 2 adds.
STRENGTH_COLUMNS: dict[str, str] = {
    **{f"stress_peak_{k}_MPa": f"peak stress in the {k} over the duty (MPa)" for k in LINK_NAMES},
    **{f"safety_factor_{k}": f"yield strength / peak stress of the {k} (-)" for k in LINK_NAMES},
    **{
        f"buckling_factor_{k}": f"Euler load / peak compression of the {k} (-, inf: never "
        "compressed)"
        for k in LINK_NAMES
    },
    **{
        f"bearing_{j}": f"bearing at joint {j}: the smallest of the catalogue whose static rating "
        "covers its peak force (empty: none fits the boss)"
        for j in ("A", "B", "C", "D")
    },
    "bearing_violation": "largest over the joints of what the joint needs (s0 x peak force, and "
    "the pin or shaft's bore) over what the catalogue's best bearing for it offers, less 1; "
    "<= 0: every joint has a bearing (-)",
    "bearing_utilisation": "largest over the joints of the chosen bearing's s0 x peak force / C0 "
    "and needed / actual bore (1 + bearing_violation where none fits) (-)",
    "strength_utilisation": "largest over the links of stress x safety factor / yield and "
    "compression x buckling factor / Euler load, and over the bearings of s0 x force / C0; "
    "<= 1 holds (-)",
    "holds_loads": "every link and bearing holds its loads with the required factors (-)",
    "weakest_link": "the link (or bearing) with the largest utilisation",
    "weakest_check": "where the weakest link is most loaded (a cut, a bore, buckling, or a "
    "bearing's static load rating)",
    **{
        f"section_{dim}_{k}_mm": f"{dim} of the {k}'s section (mm): cad.{dim}_m, or sized by "
        "strength (cad.section: sized)"
        for k in LINK_NAMES
        for dim in ("width", "thickness")
    },
    "section_iterations": "loads -> sections -> masses iterations the sized sections took (0: "
    "fixed section)",
    **{
        key: text
        for j in JOINT_COLUMNS
        for key, text in (
            (
                f"joint_force_peak_{j}_N",
                f"peak force through joint {j.replace('_', ' of the ')} (N)",
            ),
            (f"joint_force_peak_{j}_theta1_deg", f"theta1 where the force at {j} peaks (deg)"),
            (f"joint_force_peak_{j}_theta2_deg", f"theta2 where the force at {j} peaks (deg)"),
        )
    },
}

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


#: The stiffness column Stage 2 adds (:class:`qsm.embodiment.stiffness.sag_check.SagCheck`).
STIFFNESS_COLUMNS: dict[str, str] = {
    "tool_sag_mm": "largest sag of the tool under the payload's weight at the task points: solid "
    "links of the configured section, rigid drives (mm; g15 compares it with task.tolerance_mm)",
}


DATASET_COLUMNS: dict[str, str] = {
    **MECHANISM_COLUMNS,
    **DYNAMICS_COLUMNS,
    **STRENGTH_COLUMNS,
    **DRIVE_COLUMNS,
    **STIFFNESS_COLUMNS,
}

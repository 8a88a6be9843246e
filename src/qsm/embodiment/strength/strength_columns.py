"""The strength check's columns with their units, as Stage 2 adds them to the dataset
(:mod:`qsm.dataset.columns` collects every domain's)."""

from __future__ import annotations

from qsm.physics.kinematics import LINK_NAMES

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

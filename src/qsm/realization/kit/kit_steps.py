"""The kit's numbered assembly steps, each naming its parts and fasteners, and each part's step
(the exploded view's labels)."""

from __future__ import annotations

from typing import Any

#: Each part's assembly step (the exploded view's labels).
STEP_OF = {
    "base_plate": 1,
    "cheek_1": 2,
    "drive_1": 2,
    "hub_1": 3,
    "lower_arm": 5,
    "upper_arm": 6,
    "coupler": 7,
    "crank": 8,
    "cheek_2": 9,
    "drive_2": 9,
    "hub_2": 9,
    "tool_flange": 10,
}


def _named(lines: list[tuple[str, int, str]], where: str) -> str:
    """The fasteners of ``lines`` whose place starts with ``where``: "n x name, ..."."""
    found = [f"{q} x {n}" for n, q, w in lines if w.startswith(where)]
    return ", ".join(found) or "none"


def assembly_steps(
    record: dict[str, Any], lines: list[tuple[str, int, str]], bearings: dict[str, Any]
) -> list[str]:
    """The numbered assembly steps (:data:`STEP_OF`), each naming its parts and fasteners."""
    drives = record["drives"]
    pins = record["pins"]
    hubs = {h["motor"]: h for h in record["hubs"]}

    def hub(k: int) -> str:
        h = hubs[k]
        fix = (
            f"its key ({_named(lines, f'drive {k} to hub')})"
            if h["output"] == "shaft"
            else _named(lines, f"hub {k} to drive")
        )
        return f"hub {k} onto drive {k}'s {h['output']} with {fix}"

    def pin(j: str) -> str:
        a, b = pins[j]["plates"]
        fill = pins[j]["fill_spacers"]
        rest = (
            f", {fill} more {pins[j]['spacer']} on the shoulder beyond the bearing" if fill else ""
        )
        return (
            f"{pins[j]['screw'] or pins[j]['made']} through the {b.replace('_', ' ')}, "
            f"the {pins[j]['spacer']} spacer and the bearing in the {a.replace('_', ' ')}{rest}; "
            f"{pins[j]['nut']} on an ISO 7089 washer"
        )

    return [
        f"Bolt the base plate (dxf/base_plate.dxf) to the table: {_named(lines, 'base plate')}.",
        f"Bolt cheek 1 to the base plate ({_named(lines, 'cheek 1')}) and drive 1 "
        f"({drives[0]['drive']}) to its outer face ({_named(lines, 'drive 1 to cheek')}).",
        f"Fit {hub(1)}.",
        "Press the bearings into their seats, each flush with the face toward the plate it "
        "joins (the pins' check takes them there): "
        + ", ".join(f"{b['designation']} at {j}" for j, b in bearings.items() if j != "A")
        + ".",
        f"Press the hubs' heat-set inserts into the lower arm and the crank from the face "
        f"toward their cheeks ({_named(lines, 'hub 1: in the')}, {_named(lines, 'hub 2: in the')})"
        f"; bolt the lower arm to hub 1, its bore at A on the hub's spigot: "
        f"{_named(lines, 'hub 1 to the')}, with washers.",
        f"Join the upper arm to the lower arm at B: {pin('B')}.",
        f"Join the coupler to the upper arm at D: {pin('D')}.",
        f"Join the crank to the coupler at C: {pin('C')}.",
        f"Bolt drive 2 ({drives[1]['drive']}) to cheek 2 ({_named(lines, 'drive 2 to cheek')}), "
        f"fit {hub(2)}, bolt the crank to hub 2 ({_named(lines, 'hub 2 to the')}) and cheek 2 "
        f"to the base plate ({_named(lines, 'cheek 2')}).",
        f"Fix the tool flange at E ({_named(lines, 'tool flange')}); the tool bolts to its "
        f"{record['tool_flange'].get('pattern') or 'pattern (none holds)'}.",
    ]

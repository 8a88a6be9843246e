"""The kit's numbered assembly steps as a person reads them, and each part's step (the exploded
view's labels), both from the assembly sequence's record
(:func:`qsm.realization.kit.kit_sequence.record_of`)."""

from __future__ import annotations

from typing import Any


def assembly_steps(sequence: dict[str, Any]) -> list[str]:
    """Each step's sentence with its tool and, for a screw, its tightening torque; where no
    order exists, none."""
    out = []
    for s in sequence["steps"]:
        tool = "" if s["tool"] == "by hand" else f" Tool: {s['tool']}"
        torque = "" if s["torque_Nm"] is None else f", {s['torque_Nm']:.3g} N m"
        bench = "On the bench: " if s["on_the_bench"] else ""
        out.append(f"{bench}{s['text']}{tool}{torque}{'.' if tool else ''}")
    return out


def step_of(sequence: dict[str, Any]) -> dict[str, int]:
    """The number of the first step that puts each part in place (on the bench, for a module's
    parts)."""
    out: dict[str, int] = {}
    for s in sequence["steps"]:
        for part in s["places"]:
            out.setdefault(part, s["step"])
    out.pop("table", None)
    return out

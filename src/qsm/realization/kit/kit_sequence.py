"""The kit's assembly sequence, found and checked: ordered steps, each placing one part (or a
module made on the bench) or making one joint, with the direction it goes in, the tool it
needs (ISO 2936 key, spanner, press) and each screw's tightening torque.

Each step says which space must be free when it is done (:mod:`~qsm.realization.kit.kit_solids`):
the room a part passes through on its way in, and a straight key's path from a screw's head along
its axis for the key's long arm, with the short arm turning at its end. A step must come before
every part, or piece of hardware (a screw's head, a nut, a washer), that would stand in that
space: at the pose of the arm (of five over the operating range) where the fewest do, for a
spanner on a nut in the best of four directions. A bearing or insert pressed into a part on
the bench stands in the way once that part is placed. With
the steps each needs first (a hub on its drive, a link on its hub), these relations order the
steps; a cycle means that no order exists, and the sequence names the steps that form it.
A step on the bench (a drive bolted to its cheek before the module goes on) is checked against
the parts of its module only.
"""

from __future__ import annotations

import graphlib
import heapq
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import shapely
from shapely import affinity

from qsm.realization.kit.kit_solids import Prism, blockers, disc

#: The direction a part moves along the axis toward motor k's drive: motor 1's at lower z.
TOWARD = {1: -1.0, 2: 1.0}


#: The tools of the steps that press a part into another on the bench (a bearing, a heat-set
#: insert): the part stands where it goes once its carrier does.
PRESSED = ("press", "soldering iron")


@dataclass(frozen=True)
class Tool:
    """What a step needs: ``kind`` (hexagon key, spanner, press, hand), its order line, and the
    tightening torque (N m) of the screw it turns (None: no screw)."""

    kind: str
    name: str
    torque_Nm: float | None = None


@dataclass(frozen=True)
class Step:
    """One assembly step: ``key`` (unique), the ``text`` a person reads, the parts it
    ``places`` (the layout's names), the steps it ``needs`` first, the unit ``direction`` (x, y,
    z) its part or screw moves in (a key comes from the other side), its ``tool``, the
    ``reach`` alternatives (pose index, the prisms that must be free), the ``group``: the key of
    the step that places the module it is made in on the bench ("": on the arm), and the parts
    it may be swung ``aside`` of on its way in (the links it is pinned to later: until the pin
    is in, either turns freely)."""

    key: str
    text: str
    places: tuple[str, ...]
    needs: tuple[str, ...]
    direction: tuple[float, float, float]
    tool: Tool
    reach: tuple[tuple[int, tuple[Prism, ...]], ...] = ()
    group: str = ""
    aside: tuple[str, ...] = ()


@dataclass(frozen=True)
class Precedence:
    """``first`` must be done before ``then``, and ``why``."""

    first: str
    then: str
    why: str


@dataclass(frozen=True)
class AssemblySequence:
    """The steps in the order found (all of them, or none when no order exists), the relations
    that ordered them, each step's chosen pose, and what blocks (empty: a sequence exists)."""

    steps: tuple[Step, ...]
    precedences: tuple[Precedence, ...]
    poses: Mapping[str, int] = field(default_factory=dict)
    blocked: tuple[str, ...] = ()

    @property
    def exists(self) -> bool:
        """Whether an order exists in which every step's space is free."""
        return not self.blocked


def _choose(
    step: Step,
    placed: Sequence[Mapping[str, Sequence[Prism]]],
    group_parts: set[str],
    skip: tuple[str, ...],
):
    """The reach alternative (pose, blocking parts) with the fewest blocking parts, ``skip``
    aside; a bench step's blockers are only those of its group."""
    best: tuple[int, list[str]] | None = None
    for pose, prisms in step.reach or ((0, ()),):
        solids = placed[pose]
        if step.group:
            solids = {k: v for k, v in solids.items() if k in group_parts}
        hit = blockers(prisms, solids, skip=skip)
        if best is None or len(hit) < len(best[1]):
            best = (pose, hit)
    return best


def precedences(
    steps: Sequence[Step],
    placed: Sequence[Mapping[str, Sequence[Prism]]],
    hardware: Mapping[str, tuple[str, str]],
) -> tuple[list[Precedence], dict[str, int]]:
    """Every "must come first" relation of ``steps``, given each pose's solids ``placed``
    (pose index: part name: prisms), among them the ``hardware`` (name: the key of the step
    that puts it in, and the part that carries it; a step's own parts bring theirs, and a part
    pressed into another stands in the way once that one is placed), and each step's chosen
    pose."""
    groups = {s.key: s.group for s in steps}
    arm = {part: s.key for s in steps if not s.group for part in s.places}
    pressed = {s.key for s in steps if s.tool.kind in PRESSED}
    for name, (key, carrier) in hardware.items():  # a pressed part goes in with its carrier
        arm[name] = arm[carrier] if key in pressed and carrier in arm else groups.get(key) or key
    bench: dict[str, dict[str, str]] = {}
    for s in steps:
        if s.group:
            bench.setdefault(s.group, {}).update(dict.fromkeys(s.places, s.key))
    modules = {s.key: set(s.places) for s in steps if not s.group}
    out, poses = [], {}
    for s in steps:
        out += [Precedence(n, s.key, "the second needs the first in place") for n in s.needs]
        own = s.places + s.aside
        skip = own + tuple(name for name, (_, carrier) in hardware.items() if carrier in own)
        pose, hit = _choose(s, placed, modules.get(s.group, set()), skip)
        poses[s.key] = pose
        placer = bench.get(s.group, {}) if s.group else arm
        for part in hit:
            if placer.get(part) not in (None, s.key):
                out.append(Precedence(s.key, placer[part], f"{part} would stand in its way"))
    return out, poses


def order(steps: Sequence[Step], relations: Sequence[Precedence]) -> tuple[list[Step], list[str]]:
    """``steps`` in an order that keeps every relation (Kahn's sort; ties in the listed order),
    and, when none does, a cycle of relations (:func:`cycle_of`)."""
    index = {s.key: i for i, s in enumerate(steps)}
    after: dict[str, list[str]] = {s.key: [] for s in steps}
    count = dict.fromkeys(index, 0)
    for r in relations:
        after[r.first].append(r.then)
        count[r.then] += 1
    ready = [(index[k], k) for k, n in count.items() if n == 0]
    heapq.heapify(ready)
    done: list[Step] = []
    while ready:
        _, key = heapq.heappop(ready)
        done.append(steps[index[key]])
        for nxt in after[key]:
            count[nxt] -= 1
            if count[nxt] == 0:
                heapq.heappush(ready, (index[nxt], nxt))
    return done, cycle_of(relations) if len(done) < len(steps) else []


def cycle_of(relations: Sequence[Precedence]) -> list[str]:
    """One cycle of ``relations`` (graphlib finds it), each of its relations with its reason."""
    graph: dict[str, set[str]] = {}
    for r in relations:
        graph.setdefault(r.then, set()).add(r.first)
    try:
        graphlib.TopologicalSorter(graph).prepare()
    except graphlib.CycleError as err:
        nodes = err.args[1]
        why = {(r.first, r.then): r.why for r in relations}
        return [
            f"'{a}' must come before '{b}' ({why[(a, b)]})" for a, b in itertools.pairwise(nodes)
        ]
    return []


def sequence(
    steps: Sequence[Step],
    placed: Sequence[Mapping[str, Sequence[Prism]]],
    hardware: Mapping[str, tuple[str, str]] | None = None,
):
    """The :class:`AssemblySequence` of ``steps`` with the solids ``placed`` at each pose
    (the ``hardware`` among them as :func:`precedences` takes it)."""
    relations, poses = precedences(steps, placed, hardware or {})
    done, cycle = order(steps, relations)
    if cycle:
        return AssemblySequence((), tuple(relations), poses, tuple(cycle))
    return AssemblySequence(tuple(done), tuple(relations), poses)


def key_path(x: float, y: float, z: float, sign: float, key: Any) -> tuple[Prism, ...]:
    """A straight ISO 2936 key (``key``: :class:`qsm.embodiment.kit.fasteners.HexKey`) in a
    socket whose top is at (x, y, z) mm, its long arm along ``sign`` z, the short arm's circle at
    its end."""
    corners = key.key_mm / 0.866 + 1.0
    end = z + sign * key.long_arm_mm
    arm = Prism("z", disc(x, y, corners), min(z, end), max(z, end))
    turn = Prism("z", disc(x, y, 2 * key.short_arm_mm), min(end, end + sign * corners),
                 max(end, end + sign * corners))  # fmt: skip
    return arm, turn


def short_key_path(
    x: float, y: float, z: float, sign: float, key: Any, angle: float
) -> tuple[Prism, ...]:
    """An ISO 2936 key turned the other way: its short arm in a socket whose top is at (x, y,
    z) mm, along ``sign`` z, and its long arm as a handle in the plane at the short arm's end,
    out at ``angle`` rad (turned in strokes about it)."""
    corners = key.key_mm / 0.866 + 1.0
    end = z + sign * key.short_arm_mm
    arm = Prism("z", disc(x, y, corners), min(z, end), max(z, end))
    return arm, spanner_slab(x, y, end, end + sign * corners, corners, angle, 0.0, key.long_arm_mm)


def spanner_slab(
    x: float,
    y: float,
    z0: float,
    z1: float,
    across: float,
    angle: float,
    start: float = 0.0,
    length: float = 100.0,
) -> Prism:
    """A tool's room in the plane at (x, y) mm between ``z0`` and ``z1``: a strip ``across``
    wide, from ``start`` to ``start`` + ``length`` mm out at ``angle`` rad (an open spanner on
    a nut, a key to a set screw in a boss of radius ``start``, a key's handle)."""
    strip = shapely.box(start, -across / 2, start + length, across / 2)
    strip = affinity.rotate(strip, angle, origin=(0, 0), use_radians=True)
    return Prism("z", affinity.translate(strip, x, y), min(z0, z1), max(z0, z1))


def record_of(found: AssemblySequence, hardware_step: Mapping[str, str]) -> dict[str, Any]:
    """``kit.json``'s ``assembly_sequence``: the steps in order (text, parts, the solids of
    ``assembly.step`` each puts in (its parts and the hardware ``hardware_step`` gives it),
    direction, tool and torque, what each must follow), or the relations that block."""
    follows: dict[str, list[str]] = {}
    for r in found.precedences:
        follows.setdefault(r.then, []).append(f"{r.first}: {r.why}")
    hardware: dict[str, list[str]] = {}
    for name, key in hardware_step.items():
        hardware.setdefault(key, []).append(name)
    return {
        "exists": found.exists,
        "blocked": list(found.blocked),
        "steps": [
            {
                "step": n,
                "key": s.key,
                "text": s.text,
                "places": list(s.places),
                "solids": [p for p in s.places if p != "table"] + hardware.get(s.key, []),
                "direction": list(s.direction),
                "tool": s.tool.name,
                "torque_Nm": s.tool.torque_Nm,
                "on_the_bench": s.group or None,
                "after": follows.get(s.key, []),
                "pose": found.poses.get(s.key, 0),
            }
            for n, s in enumerate(found.steps, 1)
        ],
    }

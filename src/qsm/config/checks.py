"""Checks of a schema-valid configuration across keys, and plausibility checks with likely causes.

:func:`check_config` raises :class:`ConfigError` for values no run can use (every message names
the key, the value, what is valid and, where one is likely, the unit slip behind it);
:func:`config_warnings` lists what a run can use but the user should know. config/README.md says
which is which and why. Lengths in metres, angles in degrees, masses in kg.
"""

from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np

from qsm.config.drive_limits import check_drives, check_payload
from qsm.config.errors import ConfigError
from qsm.physics.task import min_enclosing_circle
from qsm.physics.task_points import MAX_VISITED_POINTS

#: Smallest radius (m) of the task circle: below it eta (task area / workspace area) is ~0.
MIN_TASK_RADIUS_M = 1e-3
#: Narrowest theta1 range (deg): a range written in radians spans at most 2 pi = 6.28.
MIN_THETA1_SPAN_DEG = 6.3
#: Designs needed on each side of the surrogate's train/test split: two give a test R^2 and a
#: spread (standard deviation) of the training labels.
MIN_SPLIT_DESIGNS = 2
#: Grid cells a side over which :func:`reach_ratio_bound` bounds the reach ratio.
REACH_GRID_CELLS = 256
#: A motor angle (deg) past this, either way, is past a full turn.
FULL_TURN_DEG = 360.0
#: Smallest printer side (mm); a build volume written in metres has every side below it.
MIN_PRINTER_SIDE_MM = 10.0
#: A task point from this distance (m) up is reported as millimetres when it is out of reach.
MILLIMETRES_FROM_M = 50.0
#: Material floors below every printable solid: (key, floor, its unit, the unit a value below
#: looks like, that unit in the key's).
MATERIAL_FLOORS = (
    (("material", "density_kg_m3"), 100.0, "kg/m^3", "g/cm^3", 1e3),
    (("material", "youngs_modulus_pa"), 1e6, "Pa", "GPa", 1e9),
    (("material", "yield_strength_pa"), 1e5, "Pa", "MPa", 1e6),
)


def check_config(config: dict[str, Any]) -> None:
    """Raise :class:`ConfigError` for the first cross-key or plausibility error of ``config``
    (schema-valid, defaults filled)."""
    _check_sampling(config["sampling"], config["surrogate"]["test_fraction"])
    _check_operating_range(config["operating_range"])
    _check_task(config)
    _check_cycle(config["task"])
    _check_cad(config)
    _check_materials(config)
    check_drives(config)
    check_payload(config)
    _check_first_mode(config)
    _check_printer(config)
    _check_sized(config)
    _check_optimization(config)
    _check_torque_margin(config)


def config_warnings(config: dict[str, Any]) -> list[str]:
    """What a valid ``config`` leaves for the user to know (empty for the defaults)."""
    out = []
    points = np.asarray(config["task"]["points"], dtype=float)
    if len(points) > MAX_VISITED_POINTS:
        out.append(
            f"config key 'task.points': {len(points)} points; the task region is their enclosing "
            f"disk, and the payload test and its animation visit {MAX_VISITED_POINTS} of them "
            f"(the first, those on the disk's edge, then the farthest apart; README, 'Your own "
            f"task')"
        )
    centre = min_enclosing_circle(points).centre
    side = "x > 0" if centre[0] > 0 else "x <= 0"
    if centre[0] > 0:
        out.append(
            f"config key 'task.points': the task's enclosing disk has its centre at "
            f"{_point(centre)}, at x > 0 (this family's workspace lies at x < 0 with the "
            f"paper's operating range); it is designed as its mirror image through x = 0, and "
            f"selected.json, summary.md and qsm export describe the mirrored arm to build "
            f"(README, 'Your own task')"
        )
    if (points[:, 0] < 0).any() and (points[:, 0] > 0).any():
        out.append(
            f"config key 'task.points': the points lie on both sides of the base (x < 0 and "
            f"x > 0); the task is designed on the side of its enclosing disk's centre ({side}), "
            f"and a design must hold the whole disk"
        )
    return out


def _point(p: Any) -> str:
    return f"({p[0]:.4g}, {p[1]:.4g})"


def largest_reach(bounds: dict[str, list[float]]) -> float:
    """Largest distance from the base joint A of any end effector of the sampled ranges, in units
    of l1: |AE| <= |AB| + |BE| = 1 + hypot(ee_x, ee_y) (E sits ee_x along and ee_y across the upper
    arm from its pivot B)."""
    return 1.0 + math.hypot(bounds["ee_x"][1], bounds["ee_y"][1])


def smallest_dataset(test_fraction: float) -> int:
    """The fewest mechanisms whose train/test split (scikit-learn's: ceil(fraction n) held out)
    leaves :data:`MIN_SPLIT_DESIGNS` designs in each part."""
    n = 2 * MIN_SPLIT_DESIGNS
    while (
        math.ceil(test_fraction * n) < MIN_SPLIT_DESIGNS
        or n - math.ceil(test_fraction * n) < MIN_SPLIT_DESIGNS
    ):
        n += 1
    return n


def folded_arm_applies(bounds: dict[str, list[float]]) -> bool:
    """Whether the folded-arm bound of :func:`reach_ratio_bound` holds for the sampled ranges: the
    angle from BA to the upper arm's line BD stays below pi (the crank-rocker condition and a loop
    that closes over the whole range, which Stage 1 demands) and above -asin(l2), so the end
    effector never comes nearer A than with the arm folded back on AB, as long as 2 atan2(ee_y,
    ee_x) + asin(l2) <= pi for every design of the ranges."""
    gamma = math.atan2(bounds["ee_y"][1], bounds["ee_x"][0])
    return 2 * gamma + math.asin(min(1.0, bounds["l2"][1])) <= math.pi


def reach_ratio_bound(bounds: dict[str, list[float]], cells: int = REACH_GRID_CELLS) -> float:
    """An upper bound on the largest ratio of the farthest to the nearest end-effector distance
    from A, over the designs of the sampled ranges (inf where none exists).

    Per design (l1 = 1, e = hypot(ee_x, ee_y)): |AE| <= 1 + e, and |AE| > hypot(ee_x - 1, ee_y)
    (the arm folded back on AB) where :func:`folded_arm_applies`, else |AE| >= e - 1. The ratio
    of the two is bounded over the ranges of ee_x and ee_y cell by cell of a grid (the largest
    numerator over the smallest denominator of each cell), so the bound is rigorous; with 256
    cells a side it is within 0.5 % of the supremum on the default ranges (10.15)."""
    (x0, x1), (y0, y1) = bounds["ee_x"], bounds["ee_y"]
    xs, ys = np.linspace(x0, x1, cells + 1), np.linspace(y0, y1, cells + 1)
    far = 1.0 + np.hypot(xs[1:, None], ys[None, 1:])
    if folded_arm_applies(bounds):
        dx = np.clip(np.maximum(1.0 - xs[1:], xs[:-1] - 1.0), 0.0, None)
        near = np.hypot(dx[:, None], ys[None, :-1])
    else:
        near = np.clip(np.hypot(xs[:-1, None], ys[None, :-1]) - 1.0, 0.0, None)
    with np.errstate(divide="ignore"):
        return float(np.where(near > 0, far / np.where(near > 0, near, 1.0), np.inf).max())


def _check_sampling(sampling: dict[str, Any], test_fraction: float) -> None:
    bounds = sampling["bounds"]
    for name, (lo, hi) in bounds.items():
        if lo <= 0:
            raise ConfigError(
                f"config key 'sampling.bounds.{name}': min {lo} is not positive; the bounds are "
                f"ratios of link lengths to l1 = 1 and must lie above 0"
            )
        if not lo < hi:
            raise ConfigError(
                f"config key 'sampling.bounds.{name}': min {lo} is not below max {hi}"
            )
    if bounds["l2"][0] + bounds["l3"][0] >= 1.0 + bounds["l4"][1]:
        raise ConfigError(
            f"config key 'sampling.bounds': no sample can be a crank-rocker (l2 + l3 < l1 + l4 "
            f"with l1 = 1): the smallest l2 + l3 = {bounds['l2'][0]} + {bounds['l3'][0]} is not "
            f"below 1 + the largest l4 = {1.0 + bounds['l4'][1]:g}; lower l2 or l3, or raise l4"
        )
    smallest = smallest_dataset(test_fraction)
    if sampling["n_mechanisms"] < smallest:
        raise ConfigError(
            f"config key 'sampling.n_mechanisms': {sampling['n_mechanisms']} is too few; the "
            f"surrogate holds out surrogate.test_fraction = {test_fraction:g} of them to test "
            f"on, and needs at least {MIN_SPLIT_DESIGNS} designs in each part (a test R^2, and the "
            f"spread of the training labels that bounds NSGA-II's g5-g10): at least {smallest}"
        )
    if sampling["n_mechanisms"] > sampling["n_samples"]:
        raise ConfigError(
            f"config key 'sampling.n_mechanisms': {sampling['n_mechanisms']} exceeds "
            f"sampling.n_samples = {sampling['n_samples']}"
        )


def _check_operating_range(op: dict[str, Any]) -> None:
    lo, hi = op["theta1_deg"]
    key = "config key 'operating_range.theta1_deg'"
    for value in (lo, hi):  # theta2_min_deg's schema keeps it within [-180, 180]
        if abs(value) > FULL_TURN_DEG:
            raise ConfigError(
                f"{key}: {value:g} deg is past a full turn "
                f"(beyond -{FULL_TURN_DEG:g} or {FULL_TURN_DEG:g} deg); motor angles are "
                f"degrees within one turn (the paper's theta1 [45, 180], theta2 from -37.5)"
            )
    if not lo < hi:
        raise ConfigError(f"{key}: min {lo} is not below max {hi}")
    if hi - lo > 360:
        raise ConfigError(f"{key}: [{lo}, {hi}] spans {hi - lo:g} deg, more than a turn (360 deg)")
    if hi - lo < MIN_THETA1_SPAN_DEG:
        cause = (
            "; looks like radians: operating_range is in degrees (the paper's [45, 180])"
            if max(abs(lo), abs(hi)) <= 2 * math.pi
            else ""
        )
        raise ConfigError(
            f"{key}: [{lo}, {hi}] spans {hi - lo:.3g} deg; motor 1 must turn through at least "
            f"{MIN_THETA1_SPAN_DEG} deg to sweep a workspace{cause}"
        )
    if op["theta2_min_deg"] >= lo:
        raise ConfigError(
            f"config key 'operating_range.theta2_min_deg': {op['theta2_min_deg']} must be below "
            f"theta1's minimum {lo} (operating_range.theta1_deg): theta2 runs from theta2_min_deg "
            f"to theta1, so at theta1 = {lo} deg its range would be empty"
        )


def _check_task(config: dict[str, Any]) -> None:
    """Task points spanning a circle of :data:`MIN_TASK_RADIUS_M`, within the family's reach."""
    points = np.asarray(config["task"]["points"], dtype=float)
    radius = min_enclosing_circle(points).radius
    if radius < MIN_TASK_RADIUS_M:
        raise ConfigError(
            f"config key 'task.points': the points span a circle of radius {radius:.2g} m "
            f"(a single point); eta = task area / workspace area would be zero for every design "
            f"and could not rank them. Give the region the tool must cover: at least two points "
            f"{2e3 * MIN_TASK_RADIUS_M:g} mm or more apart (e.g. the point and the edge of its "
            f"positioning tolerance)"
        )
    scale, margin = config["scale"]["max_m"], config["scale"]["safety_margin_m"]
    reach = largest_reach(config["sampling"]["bounds"])
    dist = np.hypot(*points.T)
    far = points[int(np.argmax(dist))]
    need = float(dist.max()) + margin
    if need <= scale * reach:
        _check_task_near_base(points, margin, config["sampling"]["bounds"])
        return
    basis = (
        f"no design of the sampled ranges reaches farther than {scale * reach:.3g} m from the "
        f"base (scale.max_m {scale} m x the largest reach 1 + hypot(ee_x, ee_y) = {reach:.3g} of "
        f"sampling.bounds), but task point {_point(far)} lies {dist.max():.3g} m away"
        + (f" (plus scale.safety_margin_m {margin} m)" if margin else "")
    )
    if dist.max() >= MILLIMETRES_FROM_M and 1e-3 * dist.max() + margin <= scale * reach:
        raise ConfigError(
            f"config key 'task.points': {basis}; looks like millimetres: task.points are in metres"
        )
    raise ConfigError(
        f"config key 'scale.max_m': {scale} m is too small for the task: {basis}; scale.max_m must "
        f"be at least {need / reach:.3g} m, or task.points nearer the base"
    )


def _check_cycle(task: dict[str, Any]) -> None:
    """``task.cycle.order``: point numbers of ``task.points``, consecutive visits distinct."""
    order = (task.get("cycle") or {}).get("order") or []
    n = len(task["points"])
    if bad := [k for k in order if k > n]:
        raise ConfigError(
            f"config key 'task.cycle.order': point numbers {bad} are not among the {n} task "
            f"points (1 to {n})"
        )
    if repeats := [a for a, b in itertools.pairwise(order) if a == b]:
        raise ConfigError(
            f"config key 'task.cycle.order': point {repeats[0]} follows itself; give each "
            f"point once per visit (task.cycle.dwell_s is the stop there)"
        )


def _check_task_near_base(points: np.ndarray, margin: float, bounds: dict[str, Any]) -> None:
    """The task's enclosing disk (grown by ``scale.safety_margin_m``) neither covers the base
    joint nor spans a range of distances from it wider than any design can
    (:func:`reach_ratio_bound`): no scale then makes a design hold it."""
    disk = min_enclosing_circle(points)
    centre = float(np.hypot(*disk.centre))
    near, far = centre - disk.radius - margin, centre + disk.radius + margin
    ratio = reach_ratio_bound(bounds)
    grown = f" grown by scale.safety_margin_m {margin:g} m" if margin else ""
    where = (
        f"the task's enclosing disk (centre {_point(disk.centre)} m, radius {disk.radius:.3g} m"
        f"{grown})"
    )
    nearest = (
        "hypot(ee_x - 1, ee_y), the upper arm folded back,"
        if folded_arm_applies(bounds)
        else "hypot(ee_x, ee_y) - 1"
    )
    if near <= 0 and np.isfinite(ratio):
        raise ConfigError(
            f"config key 'task.points': {where} covers the base joint (0, 0); every design of "
            f"sampling.bounds keeps its end effector at least {nearest} times l1 from the base. "
            f"Move task.points away from the base"
        )
    if near > 0 and far / near > ratio:
        raise ConfigError(
            f"config key 'task.points': {where} reaches from {near:.3g} to {far:.3g} m from the "
            f"base, a ratio of {far / near:.3g}; no design of sampling.bounds holds it at any "
            f"scale: its end effector stays between {nearest} and 1 + hypot(ee_x, ee_y) times l1 "
            f"from the base, a ratio of at most {ratio:.3g}. Move "
            f"the task away from the base (its nearest point at least {far / ratio:.3g} m from "
            f"it) or make it smaller"
        )


def _check_cad(config: dict[str, Any]) -> None:
    """A section that some design of the sampled ranges, at the largest scale, can carry."""
    cad = config["cad"]
    lengths = {k: cad[k] for k in ("width_m", "thickness_m", "boss_radius_m")}
    cause = (
        "; looks like millimetres: cad lengths are in metres"
        if max(lengths.values()) >= 1.0
        else ""
    )
    if not cad["boss_radius_m"] > cad["width_m"] / 2:
        raise ConfigError(
            f"config key 'cad.boss_radius_m': {cad['boss_radius_m']} m must exceed half the bar "
            f"width cad.width_m = {cad['width_m']} m{cause}"
        )
    bounds, scale = config["sampling"]["bounds"], config["scale"]["max_m"]
    longest = min(1.0, bounds["l2"][1], bounds["l3"][1])
    needed = 2 * math.sqrt(cad["boss_radius_m"] ** 2 - (cad["width_m"] / 2) ** 2)
    if scale * longest <= needed:
        raise ConfigError(
            f"config key 'cad.boss_radius_m': bosses of radius {cad['boss_radius_m']} m on bars "
            f"{cad['width_m']} m wide need links longer than {needed:.3g} m, but at scale.max_m "
            f"{scale} m the sampled ranges give a crank or coupler of at most {scale * longest:.3g}"
            f" m: smaller bosses, or scale.max_m above {needed / longest:.3g} m{cause}"
        )


def first_mode_bound_hz(config: dict[str, Any]) -> float:
    """An upper bound (Hz) on the loaded arm's first mode at the farthest task point: the
    payload alone (no link, tool flange or rotor mass) on four bars in parallel, each of the
    largest section the realisation may take (``cad``'s, or ``cad.sized``'s largest) and as
    long as that point's distance from the base, in pure tension (no bending, rigid gearboxes):
    sqrt(4 E A / (r m)) / 2 pi. Four links carry the tool, and every path through them to the
    base is at least that long."""
    cad = config["cad"]
    area = max(cad["width_m"], cad["sized"]["width_m"][1]) * max(
        cad["thickness_m"], cad["sized"]["thickness_m"][1]
    )
    reach = float(np.hypot(*np.asarray(config["task"]["points"], dtype=float).T).max())
    stiffness = 4 * config["material"]["youngs_modulus_pa"] * area / reach
    return math.sqrt(stiffness / config["task"]["payload_kg"]) / (2 * math.pi)


def _check_first_mode(config: dict[str, Any]) -> None:
    """A ``task.min_first_mode_hz`` that some arm could reach (:func:`first_mode_bound_hz`)."""
    wanted = config["task"].get("min_first_mode_hz")
    if wanted is None:
        return
    bound = first_mode_bound_hz(config)
    if wanted > bound:
        raise ConfigError(
            f"config key 'task.min_first_mode_hz': {wanted:g} Hz is more than any arm of this "
            f"task can reach: even the {config['task']['payload_kg']:g} kg payload alone on four "
            f"bars of the largest section (cad, cad.sized) in tension, as long as the farthest "
            f"task point is from the base, with rigid gearboxes, rings at {bound:.0f} Hz. Ask for "
            f"less than that"
        )


def _check_materials(config: dict[str, Any]) -> None:
    for (section, name), floor, unit, slip, factor in MATERIAL_FLOORS:
        value = config[section][name]
        if value < floor:
            raise ConfigError(
                f"config key '{section}.{name}': {value} {unit} is below {floor:g} {unit}, less "
                f"than any printable solid; looks like {slip}: {section}.{name} is in {unit} "
                f"({value} {slip} = {value * factor:g} {unit})"
            )


def _check_torque_margin(config: dict[str, Any]) -> None:
    """The drives' torque limits must leave room for the payload test's heavier plant."""
    margin = config["kit"]["torque_limit_margin"]
    heavier = 1.0 + config["payload_test"]["plant_mass_error"]
    if margin < heavier:
        raise ConfigError(
            f"config key 'kit.torque_limit_margin': {margin:g} is below 1 + "
            f"payload_test.plant_mass_error ({heavier:g}): the payload test's plant, that much "
            "heavier than the model, could not be driven within the drives' torque limits"
        )


def _check_printer(config: dict[str, Any]) -> None:
    sides = config["printing"]["build_volume_mm"]
    key = f"config key 'printing.build_volume_mm': {sides} mm"
    if min(sides) < MIN_PRINTER_SIDE_MM:
        cause = (
            "; looks like metres: printing.build_volume_mm is in millimetres"
            if max(sides) < MIN_PRINTER_SIDE_MM
            else ""
        )
        raise ConfigError(f"{key} has a side below {MIN_PRINTER_SIDE_MM:g} mm{cause}")
    cad = config["cad"]
    end = sorted([1e3 * cad["thickness_m"], 2e3 * cad["boss_radius_m"], 2e3 * cad["boss_radius_m"]])
    if any(s < e for s, e in zip(sorted(sides), end, strict=True)):
        raise ConfigError(
            f"{key} fits no link: the shortest link's box is at least {end[0]:g} x {end[1]:g} x "
            f"{end[2]:g} mm (cad.thickness_m, twice cad.boss_radius_m), so no design is printable"
        )


def _check_sized(config: dict[str, Any]) -> None:
    """Sizing bounds that are ordered, meet the section at one scale and fit the printer."""
    cad, height = config["cad"], config["printing"]["build_volume_mm"][2]
    sized = cad["sized"]
    for key in ("width_m", "thickness_m"):
        lo, hi = sized[key]
        if lo > hi:
            raise ConfigError(f"config key 'cad.sized.{key}': min {lo} m is above max {hi} m")
    if 1e3 * sized["thickness_m"][1] > height:
        raise ConfigError(
            f"config key 'cad.sized.thickness_m': max {sized['thickness_m'][1]} m is above the "
            f"printer's height printing.build_volume_mm[2] = {height:g} mm"
        )
    w, t = sized["width_m"], sized["thickness_m"]
    lo = max(w[0] / cad["width_m"], t[0] / cad["thickness_m"])
    hi = min(w[1] / cad["width_m"], t[1] / cad["thickness_m"])
    if cad["section"] == "sized" and lo > hi:
        raise ConfigError(
            f"config key 'cad.sized': no scale of the {cad['width_m']} x {cad['thickness_m']} m "
            f"section (cad.width_m x cad.thickness_m) has its width within {w} and its thickness "
            f"within {t}: the sized section keeps the configured proportions"
        )


def _check_optimization(config: dict[str, Any]) -> None:
    opt = config["optimization"]
    if opt["formulation"] not in opt["formulations"]:
        raise ConfigError(
            f"config key 'optimization.formulation': '{opt['formulation']}' is not among "
            f"optimization.formulations = {opt['formulations']}"
        )
    if opt["objectives"] == "drive_mass" and not opt["constraints"]["drives"]:
        raise ConfigError(
            "config key 'optimization.objectives': drive_mass takes its drives from g14's "
            "check; set optimization.constraints.drives: true"
        )
    ratios, scale = config["sampling"]["bounds"], config["scale"]["max_m"]
    for name, interval in opt["bounds"].items():
        if interval is None:
            continue
        lo, hi = interval
        key = f"config key 'optimization.bounds.{name}': [{lo}, {hi}]"
        if lo <= 0:
            raise ConfigError(f"{key}: min {lo} is not positive; lengths in metres lie above 0")
        if not lo < hi:
            raise ConfigError(f"{key}: min {lo} is not below max {hi}")
        longest = scale * (1.0 if name == "l1_m" else ratios[name.removesuffix("_m")][1])
        if lo > longest:
            cause = (
                "; looks like millimetres: optimization.bounds are in metres"
                if 1e-3 * lo <= longest
                else ""
            )
            raise ConfigError(
                f"{key}: min {lo} m exceeds the longest {name} of any dataset design, "
                f"{longest:.3g} m (scale.max_m x the largest ratio of sampling.bounds), so the "
                f"surrogate would only extrapolate{cause}"
            )

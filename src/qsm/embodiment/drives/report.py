"""A design's drives as a typed record
(:meth:`qsm.embodiment.drives.drive_checks.DriveCheck.report`): per motor what its duty requires
and the drive it is built with, the chosen one or, where none of the catalogue meets the duty,
the nearest (least violation) with what fails; turned into JSON and back here. Torques in N m
at the joint, speeds in rad/s, powers in W.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, field, fields
from typing import Any


@dataclass(frozen=True)
class DriveRequirement:
    """What a motor's duty asks at the joint: peak and RMS torque, peak speed and power."""

    peak_torque_Nm: float
    rms_torque_Nm: float
    peak_speed_rad_s: float
    peak_power_W: float


@dataclass(frozen=True)
class CatalogueDrive:
    """One motor-gearbox pair of the catalogue: names and keys, ratio, mass (kg), reflected
    inertia at the joint (kg m^2), the gearbox's backlash (arcmin) and torsional stiffness
    (N m/rad) and where each comes from."""

    motor: str
    gearbox: str
    motor_key: str
    gearbox_key: str
    ratio: float
    mass_kg: float
    reflected_inertia_kgm2: float
    backlash_arcmin: float
    torsional_stiffness_Nm_rad: float
    backlash_from: str
    stiffness_from: str


@dataclass(frozen=True)
class DriveOffer:
    """What a drive offers at the joint: peak torque at standstill and continuous torque, and
    its top speed (None: the catalogue states no limit)."""

    peak_torque_Nm: float
    cont_torque_Nm: float
    top_speed_rad_s: float | None


@dataclass(frozen=True)
class MotorReport:
    """One motor: ``label`` (the link it drives), whether a drive meets its duty and g14's
    violation, what the duty requires, the ``drive`` it is built with (the chosen, else the
    nearest) and its margins (1 - utilisation per check); where none meets the duty, the
    ``failing`` limits (utilisation - 1), whether any drive was stiff enough for the tolerance,
    and the strongest drive with what it offers."""

    has_drive: bool
    violation: float
    required: DriveRequirement
    drive: CatalogueDrive
    margins: Mapping[str, float]
    failing: Mapping[str, float] | None = None
    stiff_enough: bool | None = None
    strongest: CatalogueDrive | None = None
    strongest_offer: DriveOffer | None = None
    label: str = ""


@dataclass(frozen=True)
class TaskMotionNeed:
    """What the task's motion asks of the motors (per motor, N m; over ``duration_s``), where
    the design's loop closes along it (``defined``)."""

    defined: bool
    peak_torque_Nm: tuple[float, ...] | None = None
    rms_torque_Nm: tuple[float, ...] | None = None
    duration_s: float | None = None


@dataclass(frozen=True)
class DriveReport:
    """A design's drives by the catalogue's ``rule``: per motor (``motor1``, ``motor2``) its
    :class:`MotorReport`, none where the design's loop is undefined; whether the check counts
    the rotors' reflected inertia, and what the task's motion asks (None: no task motion)."""

    defined: bool
    rule: str
    motors: Mapping[str, MotorReport] = field(default_factory=dict)
    reflected_inertia: bool = False
    task_motion: TaskMotionNeed | None = None

    @property
    def has_drives(self) -> bool:
        """Each motor has a drive of the catalogue that meets its duty."""
        return self.defined and all(m.has_drive for m in self.motors.values())


def motor_json(motor: MotorReport) -> dict[str, Any]:
    """One motor's entry: the drive under ``drive`` where it was chosen, else ``best_drive``
    with what fails and the strongest drive's offer."""
    out: dict[str, Any] = {
        "drives": motor.label,
        "has_drive": motor.has_drive,
        "violation": motor.violation,
        "required": asdict(motor.required),
        "drive" if motor.has_drive else "best_drive": asdict(motor.drive),
        "margins": dict(motor.margins),
    }
    if not motor.has_drive:
        out["failing"] = dict(motor.failing or {})
        out["stiff_enough"] = motor.stiff_enough
        out["strongest_drive"] = asdict(motor.strongest) | asdict(motor.strongest_offer)
    return out


def drive_of(motor: Mapping[str, Any]) -> dict[str, Any]:
    """The drive one motor is built with, from its entry as JSON (:func:`motor_json`, as in
    ``selected.json``'s ``drives.motors``): its ``drive`` (chosen) or ``best_drive`` (the
    nearest), with ``chosen`` marking which; ``{}`` where the entry has neither. The outputs
    that read the JSON take the drive from here; a :class:`MotorReport` holds it as ``drive``."""
    drive = motor.get("drive") or motor.get("best_drive")
    if not drive:
        return {}
    return dict(drive) | {"chosen": bool(motor.get("has_drive")) and "drive" in motor}


def report_json(report: DriveReport) -> dict[str, Any]:
    """``report`` as JSON-ready values."""
    out: dict[str, Any] = {
        "has_drives": report.has_drives,
        "defined": report.defined,
        "rule": report.rule,
    }
    if report.defined:
        out["reflected_inertia"] = report.reflected_inertia
    out["motors"] = {name: motor_json(m) for name, m in report.motors.items()}
    need = report.task_motion
    if need is not None:
        out["task_motion"] = {"defined": need.defined}
        if need.defined:
            out["task_motion"] |= {
                "peak_torque_Nm": list(need.peak_torque_Nm or ()),
                "rms_torque_Nm": list(need.rms_torque_Nm or ()),
                "duration_s": need.duration_s,
            }
    return out


def _of(cls: type, data: Mapping[str, Any]) -> Any:
    return cls(**{f.name: data[f.name] for f in fields(cls)})


def motor_of(data: Mapping[str, Any]) -> MotorReport:
    """The :class:`MotorReport` that :func:`motor_json` wrote."""
    strongest = data.get("strongest_drive")
    return MotorReport(
        has_drive=bool(data["has_drive"]),
        violation=float(data["violation"]),
        required=_of(DriveRequirement, data["required"]),
        drive=_of(CatalogueDrive, data.get("drive") or data["best_drive"]),
        margins=dict(data["margins"]),
        failing=data.get("failing"),
        stiff_enough=data.get("stiff_enough"),
        strongest=None if strongest is None else _of(CatalogueDrive, strongest),
        strongest_offer=None if strongest is None else _of(DriveOffer, strongest),
        label=str(data["drives"]),
    )


def report_of(data: Mapping[str, Any]) -> DriveReport:
    """The :class:`DriveReport` that :func:`report_json` wrote."""
    need = data.get("task_motion")
    if need is not None:
        need = (
            TaskMotionNeed(True, tuple(need["peak_torque_Nm"]), tuple(need["rms_torque_Nm"]),
                           need["duration_s"])
            if need["defined"] else TaskMotionNeed(False)
        )  # fmt: skip
    return DriveReport(
        defined=bool(data["defined"]),
        rule=str(data["rule"]),
        motors={name: motor_of(m) for name, m in data["motors"].items()},
        reflected_inertia=bool(data.get("reflected_inertia", False)),
        task_motion=need,
    )

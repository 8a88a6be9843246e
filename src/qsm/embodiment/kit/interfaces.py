"""The drives' mechanical interfaces: how each bolts to the base and how its output turns a hub.

Optional catalogue files ``interfaces.csv`` and ``*_interfaces.csv`` in the drive catalogue's
folder or its subfolders (one row per gearbox key, :data:`COLUMNS`): the output (``shaft``:
diameter and DIN 6885 key; ``flange``: pilot, bolt circle, bolt count and thread), the mounting
face (pilot, bolt circle or square, bolt count and thread) and the body (diameter or square
side, length). ``status`` says whether a row is the maker's (``published``) or assumed, and
``source`` names the document or the basis.

Where a catalogue has no row for a gearbox, or a row lacks values, :func:`interface_of`
assumes them from the peak torque and the body (:func:`completed`) and says what it assumed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

from qsm.embodiment.drives.catalogue import catalogue_folder, table_files, table_rows
from qsm.embodiment.kit import fasteners as fs

COLUMNS: tuple[str, ...] = (
    "key",
    "output",
    "shaft_d_mm",
    "shaft_length_mm",
    "key_w_mm",
    "key_h_mm",
    "flange_pilot_mm",
    "flange_pcd_mm",
    "flange_bolts",
    "flange_thread",
    "mount_pilot_mm",
    "mount_pcd_mm",
    "mount_bolts",
    "mount_thread",
    "body_d_mm",
    "body_length_mm",
    "status",
    "source",
)
#: DIN 748-1 shaft diameters (mm) an assumed output shaft is rounded up to.
SHAFT_SERIES_MM = (6, 8, 10, 12, 14, 16, 19, 20, 22, 24, 25, 28, 30, 32, 35, 38, 40, 42, 45, 50)
#: Allowable torsional shear (MPa) of an assumed steel output shaft (keyway included).
ASSUMED_SHAFT_SHEAR_MPA = 60.0


@dataclass(frozen=True)
class DriveInterface:
    """A drive's output and mounting face (mm), as in :data:`COLUMNS`; ``assumed`` names what
    was assumed (empty: every value from the catalogue)."""

    key: str
    output: str
    shaft_d_mm: float
    shaft_length_mm: float
    key_w_mm: float
    key_h_mm: float
    flange_pilot_mm: float
    flange_pcd_mm: float
    flange_bolts: int
    flange_thread: str
    mount_pilot_mm: float
    mount_pcd_mm: float
    mount_bolts: int
    mount_thread: str
    body_d_mm: float
    body_length_mm: float
    status: str
    source: str
    assumed: str = ""


def din6885_key(shaft_d_mm: float) -> tuple[float, float]:
    """Width and height (mm) of the DIN 6885-1 parallel key of a shaft of ``shaft_d_mm`` (the
    largest of the table's above its range)."""
    rows = fs.table("din6885")
    row = next((r for r in rows if shaft_d_mm <= float(r["shaft_d_max_mm"])), rows[-1])
    return float(row["w_mm"]), float(row["h_mm"])


def _number(text: str, where: str) -> float:
    """A cell's number (0 where empty); ``where`` names the file, line and column."""
    try:
        value = float(text) if text.strip() else 0.0
    except ValueError:
        raise ValueError(f"{where}: {text!r} is not a number (mm, without its unit)") from None
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"{where}: {text!r} must be a finite number, 0 or more")
    return value


def interface_files(folder: str | Path | None = None) -> list[Path]:
    """The ``interfaces.csv`` and ``*_interfaces.csv`` files under the drive catalogue
    ``folder`` (None: the default catalogue), in subfolders too, as the other tables are found."""
    return table_files(catalogue_folder(folder), "interfaces", required=False)


def read_interfaces(folder: str | Path | None = None) -> dict[str, DriveInterface]:
    """The rows of the catalogue's interface files (:func:`interface_files`) by gearbox key; {}
    where there are none. A key given twice, in one file or two, is refused."""
    return {key: row for key, (_, _, row) in interface_rows(folder).items()}


def interface_rows(folder: str | Path | None = None) -> dict[str, tuple[Path, int, DriveInterface]]:
    """:func:`read_interfaces` with each row's file and line."""
    out: dict[str, tuple[Path, int, DriveInterface]] = {}
    for path in interface_files(folder):
        for key, (line, row) in read_interface_file(path).items():
            if key in out:
                raise ValueError(f"{path}, line {line}: key {key!r} has a row above already")
            out[key] = (path, line, row)
    return out


def read_interface_file(path: Path) -> dict[str, tuple[int, DriveInterface]]:
    """One interface file's rows by gearbox key, each with its line, read as the catalogue's
    tables are (:func:`qsm.embodiment.drives.catalogue.table_rows`: a byte-order mark read
    through, blank and ``#`` lines skipped, cells stripped); an error names the file, the line
    and the column."""
    rows = table_rows(path)
    _, header = next(rows, (1, []))
    missing = [c for c in COLUMNS if c not in header]
    if missing:
        raise ValueError(f"{path}: column {missing[0]!r} missing")
    out: dict[str, tuple[int, DriveInterface]] = {}
    for k, cells in rows:
        row = dict(zip(header, cells + [""] * (len(header) - len(cells)), strict=False))
        if row["key"] in out:
            raise ValueError(f"{path}, line {k}: key {row['key']!r} has a row above already")
        out[row["key"]] = (k, DriveInterface(**_values(row, f"{path}, line {k}")))
    return out


def _values(row: dict[str, str], where: str) -> dict[str, Any]:
    """A row's values, each checked: sizes numbers (mm), bolts whole numbers, threads of ISO
    4762's table, the output ``shaft`` or ``flange``; ``where`` names the file and line."""
    values: dict[str, Any] = {c: row[c] or "" for c in COLUMNS}
    if values["output"] not in ("shaft", "flange"):
        raise ValueError(f"{where}, column 'output': 'shaft' or 'flange', got {row['output']!r}")
    threads = [r["thread"] for r in fs.table("iso4762")]
    for c in COLUMNS:
        at = f"{where}, column {c!r}"
        if c.endswith("_mm") or c.endswith("_bolts"):
            values[c] = _number(values[c], at)
        if c.endswith("_bolts"):
            if values[c] != int(values[c]):
                raise ValueError(f"{at}: a whole number of bolts, got {row[c]!r}")
            values[c] = int(values[c])
        if c.endswith("_thread") and values[c] and values[c] not in threads:
            raise ValueError(f"{at}: {row[c]!r} is not in ISO 4762's table ({', '.join(threads)})")
    return values


def _assumed_shaft_mm(peak_torque_Nm: float) -> float:
    """The smallest :data:`SHAFT_SERIES_MM` diameter with ``16 T / (pi d^3)`` within
    :data:`ASSUMED_SHAFT_SHEAR_MPA` at ``peak_torque_Nm``."""
    need = (16 * peak_torque_Nm / (math.pi * ASSUMED_SHAFT_SHEAR_MPA * 1e6)) ** (1 / 3) * 1e3
    return next((float(s) for s in SHAFT_SERIES_MM if s >= need), float(SHAFT_SERIES_MM[-1]))


def _thread_for(size_mm: float) -> str:
    """An M thread of about a tenth of ``size_mm`` (M3 to M12)."""
    return f"M{min((3, 4, 5, 6, 8, 10, 12), key=lambda m: abs(m - size_mm / 10))}"


def _filled(row: DriveInterface, values: dict[str, Any], notes: list[str], text: str) -> None:
    """Put each of ``values`` that ``row`` lacks (0 or "") into ``notes``' assumptions."""
    lacking = {k: v for k, v in values.items() if not getattr(row, k)}
    if lacking:
        notes.append(text.format(**{k: getattr(row, k) or v for k, v in values.items()}))
        values.clear()
        values.update(lacking)
    else:
        values.clear()


def completed(row: DriveInterface, peak_torque_Nm: float) -> DriveInterface:
    """``row`` with every value it lacks assumed, and ``assumed`` saying which and how: a
    shaft's diameter from the peak torque (:func:`_assumed_shaft_mm`), its length 2 d and its
    DIN 6885-1 key; a flange's six bolts on 0.4 of the body's diameter around a pilot of 0.3;
    the mounting face's four bolts (a thread of about d / 12) on 0.8 of it around a pilot of 0.5;
    a body 4 d x 5 d."""
    notes: list[str] = []
    shaft = row.shaft_d_mm or _assumed_shaft_mm(peak_torque_Nm)
    body = {"body_d_mm": 4 * shaft, "body_length_mm": 5 * shaft}
    _filled(row, body, notes, "body {body_d_mm:g} x {body_length_mm:g} mm")
    row = replace(row, **body)
    if row.output == "shaft":
        w, h = din6885_key(shaft)
        out = {"shaft_d_mm": shaft, "shaft_length_mm": 2 * shaft, "key_w_mm": w, "key_h_mm": h}
        text = "shaft {shaft_d_mm:g} x {shaft_length_mm:g} mm, key {key_w_mm:g} x {key_h_mm:g}"
    else:
        d = row.body_d_mm
        out = {
            "flange_pilot_mm": round(0.3 * d),
            "flange_pcd_mm": round(0.4 * d),
            "flange_bolts": 6,
            "flange_thread": _thread_for(0.4 * d),
        }
        text = (
            "output flange {flange_bolts} x {flange_thread} on {flange_pcd_mm:g} mm, "
            "pilot {flange_pilot_mm:g}"
        )
    _filled(row, out, notes, text)
    row = replace(row, **out)
    d = row.body_d_mm
    face = {
        "mount_pilot_mm": round(0.5 * d),
        "mount_pcd_mm": round(0.8 * d),
        "mount_bolts": 4,
        "mount_thread": _thread_for(d / 1.2),
    }
    text = "mounting face {mount_bolts} x {mount_thread} on {mount_pcd_mm:g} mm, "
    text += "pilot {mount_pilot_mm:g}"
    _filled(row, face, notes, text)
    row = replace(row, **face)
    return replace(row, assumed="; ".join(filter(None, [row.assumed, *notes])))


def assumed_interface(key: str, peak_torque_Nm: float) -> DriveInterface:
    """An interface for gearbox ``key`` without a catalogue row: a keyed shaft and a face,
    every value assumed (:func:`completed`)."""
    blank = DriveInterface(
        key,
        "shaft",
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0,
        "",
        0.0,
        0.0,
        0,
        "",
        0.0,
        0.0,
        "assumed",
        "no row in interfaces.csv",
    )
    return completed(blank, peak_torque_Nm)


def interface_of(
    key: str, peak_torque_Nm: float, folder: str | Path | None = None
) -> DriveInterface:
    """The catalogue's interface of gearbox ``key`` completed for ``peak_torque_Nm``
    (:func:`completed`), or one assumed whole."""
    row = read_interfaces(folder).get(key)
    return completed(row, peak_torque_Nm) if row else assumed_interface(key, peak_torque_Nm)

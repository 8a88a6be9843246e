"""Read a drive catalogue: motors, gearboxes and their compatibility in MGDB's CSV format.

MGDB (the Motor-Gearbox DataBase, github.com/ekrimsk/MGDB) keeps every value in SI units:
volts, N m/A, ohms, henries, kg, kg m^2, rad/s, amperes, N m, watts. A folder holds any number of
``*_motors.csv``, ``*_gearboxes.csv`` and ``*_compatibility.csv`` files, found recursively;
qsm also accepts the bare names ``motors.csv`` etc. and ``*_torque_speed.csv`` tables (pull-out
torque against speed, for motors the DC model does not describe, such as steppers). Extra columns
are kept, and lines starting with ``#`` are comments. An empty cell takes the default MGDB's
README gives for its column (``nan`` or ``inf``); a column without a default reads as ``nan``,
and a drive that needs such a value is never chosen.

Compatibility rows hold no header: a motor key, then the keys of the gearboxes that fit it. A key
ending in ``*`` is a prefix that matches every gearbox whose key starts with it. Unlike MGDB's
Matlab reader, no direct-drive gearbox is added implicitly: write a gearbox of ratio 1 for that.
"""

from __future__ import annotations

import csv
import functools
import hashlib
import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np
import pandas as pd

MOTOR_COLUMNS = (
    "key", "manufacturer", "ID", "type", "V", "k_t", "R", "L", "mass", "inertia", "omega_nl",
    "I_nl", "I_nom", "max_int_torque", "max_int_speed", "max_cont_speed", "max_cont_power",
)  # fmt: skip
GEARBOX_COLUMNS = (
    "key", "manufacturer", "ID", "type", "stages", "ratio", "mass", "inertia", "efficiency",
    "direction", "max_int_torque", "max_cont_torque",
)  # fmt: skip
TORQUE_SPEED_COLUMNS = ("motor", "speed_rad_s", "torque_Nm")
TEXT_COLUMNS = frozenset({"key", "manufacturer", "ID", "type", "motor"})
#: Motor types the DC model describes (a straight torque-speed line from k_t, V, R and omega_nl);
#: a motor of any other type (a stepper, say) needs a torque-speed table.
DC_MODEL_TYPES = frozenset({"DC", "BLDC"})

# Values MGDB's README gives for a value a datasheet does not state (an empty cell).
_MOTOR_DEFAULTS = {
    "I_nl": np.nan, "I_nom": np.nan, "max_int_torque": np.inf, "max_int_speed": np.inf,
    "max_cont_speed": np.inf, "max_cont_power": np.inf,
}  # fmt: skip
_GEARBOX_DEFAULTS = {
    "stages": 1.0, "mass": np.nan, "efficiency": np.nan, "direction": 1.0,
    "max_int_torque": np.inf, "max_cont_torque": np.inf,
}  # fmt: skip
_NON_NEGATIVE = frozenset(
    {"V", "k_t", "R", "L", "mass", "inertia", "omega_nl", "I_nom", "max_int_torque",
     "max_int_speed", "max_cont_speed", "max_cont_torque", "backlash_arcmin",
     "torsional_stiffness_Nm_rad", "encoder_counts"}
)  # fmt: skip
# Extra MGDB columns that hold numbers; any other extra column (e.g. source, note) is text.
_NUMERIC_EXTRA = frozenset(
    {"k_e", "diameter", "length", "coulomb_friction", "viscous_friction", "Rth1", "Rth2",
     "backlash_arcmin", "torsional_stiffness_Nm_rad", "encoder_counts"}
)  # fmt: skip


class CatalogueError(ValueError):
    """A catalogue file that cannot be used; the message names the file, line and column."""


@dataclass(frozen=True)
class Catalogue:
    """Motors and gearboxes (indexed by key) and one row per compatible pair (``drives``).

    ``drives`` columns: motor, gearbox (keys), ratio (-), efficiency (-), mass (kg, motor plus
    gearbox), reflected_inertia (kg m^2 at the output: (J_motor + J_gear,in) ratio^2, the MuJoCo
    joint ``armature`` of the drive). ``torque_speed`` maps a motor key to (speed rad/s, torque N m)
    arrays of its pull-out curve, speeds increasing.
    """

    motors: pd.DataFrame
    gearboxes: pd.DataFrame
    drives: pd.DataFrame
    torque_speed: dict[str, tuple[np.ndarray, np.ndarray]]


def default_catalogue_folder() -> Path:
    """The folder of the catalogue shipped with qsm (built from makers' datasheets)."""
    return Path(str(resources.files("qsm.embodiment.drives") / "data"))


def catalogue_folder(folder: str | Path | None) -> Path:
    """``drives.catalogue``'s folder: ``folder``, or the one shipped with qsm when None (the one
    place that default is decided)."""
    return default_catalogue_folder() if folder is None else Path(folder)


def load_catalogue(folder: str | Path | None = None) -> Catalogue:
    """The catalogue of :func:`catalogue_folder`, read once per process while its CSV files keep
    their modification times (config validation, the settings and the checks share it)."""
    path = catalogue_folder(folder)
    files = sorted(path.rglob("*.csv")) if path.is_dir() else []
    return _cached(str(path), tuple((str(f), f.stat().st_mtime_ns) for f in files))


@functools.lru_cache(maxsize=8)
def _cached(folder: str, stamp: tuple[tuple[str, int], ...]) -> Catalogue:
    return read_catalogue(folder)


def read_catalogue(folder: str | Path) -> Catalogue:
    """Read and validate every catalogue file under ``folder`` (for example an MGDB checkout).

    Raises CatalogueError on a missing column, a non-numeric or negative value, a ratio or
    efficiency out of range, a duplicate key, an unknown compatibility key or a bad torque-speed
    table, or a motor that is neither described by the DC model nor given a torque-speed table;
    FileNotFoundError when ``folder`` is a file, or holds no motors, gearboxes or compatibility.
    """
    folder = Path(folder)
    if folder.is_file():
        raise FileNotFoundError(
            f"drive catalogue {folder} is a file: give the folder that holds motors.csv, "
            f"gearboxes.csv and compatibility.csv"
        )
    if not folder.is_dir():
        raise FileNotFoundError(f"drive catalogue folder {folder} does not exist")
    motors = _read_table(table_files(folder, "motors"), MOTOR_COLUMNS, _MOTOR_DEFAULTS)
    gearboxes = _read_table(table_files(folder, "gearboxes"), GEARBOX_COLUMNS, _GEARBOX_DEFAULTS)
    pairs = _read_compatibility(table_files(folder, "compatibility"), motors, gearboxes)
    table = _read_torque_speed(table_files(folder, "torque_speed", required=False), motors)
    _check_described(motors, table, folder)
    m = motors.loc[pairs[:, 0]]
    g = gearboxes.loc[pairs[:, 1]]
    ratio = g["ratio"].to_numpy()
    drives = pd.DataFrame(
        {
            "motor": pairs[:, 0],
            "gearbox": pairs[:, 1],
            "ratio": ratio,
            "efficiency": g["efficiency"].to_numpy(),
            "mass": m["mass"].to_numpy() + g["mass"].to_numpy(),
            "reflected_inertia": (m["inertia"].to_numpy() + g["inertia"].to_numpy()) * ratio**2,
        }
    )
    return Catalogue(motors, gearboxes, drives, table)


def _check_described(
    motors: pd.DataFrame, table: dict[str, tuple[np.ndarray, np.ndarray]], folder: Path
) -> None:
    """Every motor is one the DC model describes (:data:`DC_MODEL_TYPES`) or has a torque-speed
    table: CatalogueError naming the motor, its file and line otherwise."""
    for key, kind in motors["type"].items():
        if str(kind).upper() not in DC_MODEL_TYPES and key not in table:
            raise CatalogueError(
                f"{motors.attrs['origin'][key]}, column 'type': motor {key!r} is of type "
                f"{kind!r}, which the DC model (types {', '.join(sorted(DC_MODEL_TYPES))}) cannot "
                f"describe; give its pull-out torque against speed in a torque_speed.csv under "
                f"{folder} (columns motor, speed_rad_s, torque_Nm)"
            )


def table_files(folder: Path, kind: str, required: bool = True) -> list[Path]:
    """The catalogue's ``kind`` tables under ``folder``, in subfolders too: ``kind.csv`` and
    ``*_kind.csv``; FileNotFoundError where a ``required`` kind has none."""
    found = sorted(
        {*folder.rglob(f"{kind}.csv"), *folder.rglob(f"*_{kind}.csv")}, key=lambda p: str(p)
    )
    if required and not found:
        raise FileNotFoundError(f"no {kind}.csv or *_{kind}.csv under {folder}")
    return found


def table_rows(path: Path):
    """Yield (line number, cells) of a CSV file, skipping blank and ``#`` lines; text that is
    not UTF-8 raises :class:`CatalogueError` naming the file."""
    with path.open(newline="", encoding="utf-8-sig") as f:
        reader = csv.reader(f)
        try:
            for cells in reader:
                cells = [c.strip() for c in cells]
                if not any(cells) or cells[0].startswith("#"):
                    continue
                yield reader.line_num, cells
        except UnicodeDecodeError as exc:
            raise CatalogueError(
                f"{path}: not UTF-8 text ({exc.reason} at byte {exc.start}); save it as UTF-8"
            ) from None


def catalogue_digest(folder: str | Path) -> str:
    """SHA-256 (hex) of the catalogue's tables under ``folder`` (:func:`table_files`: motors,
    gearboxes, compatibility, torque-speed and interface files) as they are read: each file's
    path in the folder and the cells of its rows (:func:`table_rows`). A re-save that changes
    only a byte-order mark, the line ends, blank or ``#`` lines or the spaces around cells keeps
    the digest; a CSV file no reader reads does not enter it."""
    folder = Path(folder)
    digest = hashlib.sha256()
    kinds = ("motors", "gearboxes", "compatibility", "torque_speed", "interfaces")
    for path in sorted({p for kind in kinds for p in table_files(folder, kind, required=False)}):
        digest.update(str(path.relative_to(folder).as_posix()).encode() + b"\0")
        for _, cells in table_rows(path):
            digest.update(json.dumps(cells).encode() + b"\n")
    return digest.hexdigest()


#: The heaviest motor or gearbox (kg) a printed arm's catalogue can mean: more reads as grams.
HEAVIEST_KG = 100.0


def _number(text: str, default: float, where: str, optional: bool = True) -> float:
    """A cell's number, ``default`` where empty; a written number must be finite (an empty cell
    is how the catalogue says the maker gives none, where the cell is ``optional``)."""
    if text == "":
        return default
    try:
        value = float(text)
    except ValueError:
        raise CatalogueError(f"{where}: {text!r} is not a number") from None
    if not np.isfinite(value):
        hint = " (leave the cell empty when the maker gives none)" if optional else ""
        raise CatalogueError(f"{where}: {text!r} is not a finite number{hint}")
    return value


def _read_table(
    paths: list[Path], columns: tuple[str, ...], defaults: dict[str, float]
) -> pd.DataFrame:
    """Read files with a header row into one frame indexed by key, validating every cell."""
    records: list[dict] = []
    origin: dict[str, str] = {}
    for path in paths:
        rows = table_rows(path)
        header_line, header = next(rows, (1, []))
        missing = [c for c in columns if c not in header]
        if missing:
            raise CatalogueError(f"{path}, line {header_line}: missing column {missing[0]!r}")
        for line, cells in rows:
            cells = cells + [""] * (len(header) - len(cells))
            rec = {}
            for name, text in zip(header, cells, strict=False):
                where = f"{path}, line {line}, column {name!r}"
                if name in TEXT_COLUMNS or (name not in columns and name not in _NUMERIC_EXTRA):
                    rec[name] = text
                    continue
                value = _number(text, defaults.get(name, np.nan), where)
                if name in _NON_NEGATIVE and value < 0:
                    raise CatalogueError(f"{where}: {value} is negative")
                rec[name] = value
            _check_row(rec, f"{path}, line {line}")
            if rec["key"] in origin:
                raise CatalogueError(
                    f"{path}, line {line}, column 'key': {rec['key']!r} already defined at "
                    f"{origin[rec['key']]}"
                )
            origin[rec["key"]] = f"{path}, line {line}"
            records.append(rec)
    frame = pd.DataFrame.from_records(records, columns=_all_columns(records, columns))
    frame = frame.set_index("key", drop=False)
    frame.attrs["origin"] = origin  # key -> "file, line N"
    return frame


def _check_row(rec: dict, where: str) -> None:
    if rec["key"] == "":
        raise CatalogueError(f"{where}, column 'key': empty key")
    if rec.get("mass", 0.0) > HEAVIEST_KG:
        raise CatalogueError(
            f"{where}, column 'mass': {rec['mass']:g} kg is more than any drive of a printed arm "
            f"({HEAVIEST_KG:g} kg): the column is in kg ({rec['mass']:g} g is "
            f"{rec['mass'] / 1e3:g} kg)"
        )
    if "direction" in rec and rec["direction"] not in (1.0, -1.0):
        raise CatalogueError(
            f"{where}, column 'direction': 1 (output turns as the input) or -1, "
            f"got {rec['direction']:g}"
        )
    if "stages" in rec and not (rec["stages"] >= 1 and float(rec["stages"]).is_integer()):
        raise CatalogueError(f"{where}, column 'stages': a whole number, 1 or more, got "
                             f"{rec['stages']:g}")  # fmt: skip
    if "ratio" in rec and not rec["ratio"] > 0:
        raise CatalogueError(f"{where}, column 'ratio': ratio must be positive, got {rec['ratio']}")
    eff = rec.get("efficiency", np.nan)
    if not np.isnan(eff) and not 0 < eff <= 1:
        raise CatalogueError(f"{where}, column 'efficiency': must lie in (0, 1], got {eff}")
    if rec.get("torsional_stiffness_Nm_rad", np.nan) == 0:
        raise CatalogueError(
            f"{where}, column 'torsional_stiffness_Nm_rad': must be positive (leave it empty "
            f"when the maker gives none)"
        )


def _all_columns(records: list[dict], columns: tuple[str, ...]) -> list[str]:
    extra = [c for r in records for c in r if c not in columns]
    return [*columns, *dict.fromkeys(extra)]


def _read_compatibility(
    paths: list[Path], motors: pd.DataFrame, gearboxes: pd.DataFrame
) -> np.ndarray:
    """Compatible (motor key, gearbox key) pairs, (P, 2), in file order without duplicates."""
    gb_keys = list(gearboxes.index)
    pairs: dict[tuple[str, str], None] = {}
    for path in paths:
        for line, cells in table_rows(path):
            if cells[0] not in motors.index:
                raise CatalogueError(
                    f"{path}, line {line}, column 1: unknown motor key {cells[0]!r}"
                )
            for col, key in enumerate(cells[1:], start=2):
                if key == "":
                    continue
                if key.endswith("*"):
                    matches = [k for k in gb_keys if k.startswith(key[:-1])]
                else:
                    matches = [key] if key in gearboxes.index else []
                if not matches:
                    raise CatalogueError(
                        f"{path}, line {line}, column {col}: unknown gearbox key {key!r}"
                    )
                pairs.update(dict.fromkeys((cells[0], k) for k in matches))
    if not pairs:
        raise CatalogueError(f"{paths}: no compatible motor-gearbox pair")
    return np.array(list(pairs), dtype=object).reshape(-1, 2)


def _read_torque_speed(
    paths: list[Path], motors: pd.DataFrame
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Pull-out curves by motor key; each needs two or more points at increasing speeds."""
    points: dict[str, list[tuple[float, float]]] = {}
    where_of: dict[str, str] = {}
    for path in paths:
        frame = _read_points(path)
        for line, motor, speed, torque in frame:
            if motor not in motors.index:
                raise CatalogueError(
                    f"{path}, line {line}, column 'motor': unknown motor key {motor!r}"
                )
            pts = points.setdefault(motor, [])
            if pts and speed <= pts[-1][0]:
                raise CatalogueError(
                    f"{path}, line {line}, column 'speed_rad_s': speeds of {motor!r} must increase"
                )
            pts.append((speed, torque))
            where_of[motor] = f"{path}, line {line}"
    for motor, pts in points.items():
        if len(pts) < 2:
            raise CatalogueError(f"{where_of[motor]}, column 'motor': {motor!r} needs two points")
    return {m: (np.array(v)[:, 0], np.array(v)[:, 1]) for m, v in points.items()}


def _read_points(path: Path) -> list[tuple[int, str, float, float]]:
    rows = table_rows(path)
    header_line, header = next(rows, (1, []))
    missing = [c for c in TORQUE_SPEED_COLUMNS if c not in header]
    if missing:
        raise CatalogueError(f"{path}, line {header_line}: missing column {missing[0]!r}")
    i_m, i_s, i_t = (header.index(c) for c in TORQUE_SPEED_COLUMNS)
    out = []
    for line, cells in rows:
        cells = cells + [""] * (len(header) - len(cells))
        vals = []
        for i, name in ((i_s, "speed_rad_s"), (i_t, "torque_Nm")):
            where = f"{path}, line {line}, column {name!r}"
            value = _number(cells[i], np.nan, where, optional=False)
            if not value >= 0:
                raise CatalogueError(f"{where}: needs a value >= 0, got {cells[i]!r}")
            vals.append(value)
        out.append((line, cells[i_m], vals[0], vals[1]))
    return out

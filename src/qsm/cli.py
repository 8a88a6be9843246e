"""Command line: ``python -m qsm evaluate ...`` and ``python -m qsm export-mjcf ...``."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from qsm import settings
from qsm.config import ConfigError, load_config, validate_config
from qsm.evaluate import checked_ratios, evaluate_ratios
from qsm.mechanisms.scale import MECHANISM_COLUMNS
from qsm.physics.cad import export_stl
from qsm.physics.kinematics import DESIGN_NAMES
from qsm.physics.mjcf import mjcf_xml
from qsm.workflow.tables import read_table


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m qsm", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    ev = sub.add_parser("evaluate", help="evaluate one design; prints one JSON object")
    ev.add_argument(
        "--ratios",
        nargs=5,
        type=float,
        required=True,
        metavar=("L2", "L3", "L4", "EEX", "EEY"),
        help="link ratios to l1 (l1 = 1)",
    )
    ev.add_argument(
        "--task-points",
        nargs="+",
        type=float,
        metavar="X Y",
        help="task points x1 y1 x2 y2 ... in metres (default: the config's task.points)",
    )
    ev.add_argument("--config", help="config YAML (default: built-in defaults)")
    ex = sub.add_parser(
        "export-mjcf", help="write a mechanism's MuJoCo model (MJCF) and link STLs (mm)"
    )
    ex.add_argument("--id", type=int, required=True, help="mechanism_id in the mechanism table")
    ex.add_argument(
        "--mechanisms",
        default="results/mechanisms/mechanisms.parquet",
        help="mechanism table (default: %(default)s)",
    )
    ex.add_argument("--config", help="config YAML for the link section and payload")
    ex.add_argument("--out", help="output folder (default: results/models/mechanism-ID)")
    return parser


def _export(args: argparse.Namespace, config: dict) -> dict:
    table = read_table(args.mechanisms, MECHANISM_COLUMNS)
    row = table.loc[table["mechanism_id"] == args.id]
    if row.empty:
        raise ValueError(f"mechanism_id {args.id} is not in '{args.mechanisms}'")
    design = row[[f"{n}_m" for n in DESIGN_NAMES]].to_numpy(dtype=float)[0]
    out = Path(args.out or f"results/models/mechanism-{args.id}")
    out.mkdir(parents=True, exist_ok=True)
    cad = settings.cad(config["cad"])
    xml = out / "model.xml"
    xml.write_text(mjcf_xml(design, cad, config["task"]["payload_kg"]))
    stls = export_stl(design, out / "stl", cad)
    return {"mechanism_id": args.id, "mjcf": str(xml), "stl": [str(p) for p in stls]}


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the process exit code."""
    args = _parser().parse_args(argv)
    try:
        config = load_config(args.config)
        if getattr(args, "task_points", None) is not None:
            pts = args.task_points
            if len(pts) % 2:
                raise ConfigError("--task-points takes pairs of numbers: x1 y1 x2 y2 ...")
            config["task"]["points"] = [pts[i : i + 2] for i in range(0, len(pts), 2)]
            try:
                validate_config(config)
            except ConfigError as exc:
                raise ConfigError(f"--task-points: {exc}") from exc
        if args.command == "export-mjcf":
            result = _export(args, config)
        else:
            try:
                ratios = checked_ratios(args.ratios)
            except ValueError as exc:
                raise ValueError(f"--ratios: {exc}") from exc
            result = evaluate_ratios(ratios, config)
    except (ConfigError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(result, indent=2))
    return 0

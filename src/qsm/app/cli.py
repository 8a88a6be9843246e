"""Command line: ``qsm evaluate ...``, ``qsm export ...`` and ``qsm check-config ...`` (``qsm`` is
installed with the package; ``python -m qsm`` runs the same)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from qsm.app.evaluate import checked_ratios, evaluate_lengths, evaluate_ratios
from qsm.config.checks import config_warnings
from qsm.config.reading import ConfigError, load_config, validate_config
from qsm.workflow.json_files import dumps

#: ``--lengths``: one design as its six lengths, evaluated at that scale.
LENGTHS: dict = {
    "nargs": 6,
    "type": float,
    "metavar": ("L1", "L2", "L3", "L4", "EEX", "EEY"),
    "help": "the design's six lengths in metres, evaluated at that scale without refitting",
}


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="qsm",
        description="qsm-design's command line: evaluate a design, export one (MJCF, link STLs, "
        "URDF, JSON, drawing), or check config files. "
        "`qsm COMMAND --help` describes each command; `python -m qsm` runs the same.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    ev = sub.add_parser("evaluate", help="evaluate one design; prints one JSON object")
    given = ev.add_mutually_exclusive_group(required=True)
    given.add_argument(
        "--ratios",
        nargs=5,
        type=float,
        metavar=("L2", "L3", "L4", "EEX", "EEY"),
        help="link ratios to l1 (l1 = 1), scaled to the task as Stage 1 does",
    )
    given.add_argument("--lengths", **LENGTHS)
    ev.add_argument(
        "--task-points",
        nargs="+",
        type=float,
        metavar="X Y",
        help="task points x1 y1 x2 y2 ... in metres (default: the config's task.points)",
    )
    ev.add_argument("--config", nargs="+", help="config YAML(s) (default: built-in defaults)")
    _export_parser(sub)
    check = sub.add_parser(
        "check-config",
        help="validate config files as `snakemake --configfile FILE...` merges them; prints the "
        "warnings, or the error with the key (or the file, line and column of a YAML error)",
    )
    check.add_argument("config", nargs="*", help="config YAML files, later ones over earlier ones")
    return parser


def _export_parser(sub: argparse._SubParsersAction) -> None:
    """``export``: one design's MJCF, STLs, URDF, JSON and drawing (qsm.app.export)."""
    ex = sub.add_parser(
        "export",
        help="write one design's MJCF, link STLs, URDF, JSON (true performance) and drawing",
    )
    which = ex.add_mutually_exclusive_group(required=True)
    which.add_argument("--front", help="a front of the run (paper, ratios); needs --rank")
    which.add_argument("--lengths", **LENGTHS)
    which.add_argument("--id", type=int, help="mechanism_id of a dataset mechanism")
    which.add_argument(
        "--ratios",
        nargs=5,
        type=float,
        metavar=("L2", "L3", "L4", "EEX", "EEY"),
        help="a unit design (l1 = 1), scaled to the task as Stage 1 does",
    )
    ex.add_argument("--rank", type=int, help="rank on the front (1 = knee; see pareto.html)")
    ex.add_argument(
        "--task-points",
        nargs="+",
        type=float,
        metavar="X Y",
        help="with --ratios: task points x1 y1 x2 y2 ... in metres (default: the config's)",
    )
    ex.add_argument("--results", default="results", help="the run's results (default: %(default)s)")
    ex.add_argument(
        "--config", nargs="+", help="the run's config YAML(s), merged in order (default: built-in)"
    )
    ex.add_argument("--out", help="output folder (default: RESULTS/exports/...)")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the process exit code."""
    args = _parser().parse_args(argv)
    try:
        config = load_config(*(args.config or ()))
        if getattr(args, "task_points", None) is not None:
            pts = args.task_points
            if len(pts) % 2:
                raise ConfigError("--task-points takes pairs of numbers: x1 y1 x2 y2 ...")
            config["task"]["points"] = [pts[i : i + 2] for i in range(0, len(pts), 2)]
            try:
                validate_config(config)
            except ConfigError as exc:
                raise ConfigError(f"--task-points: {exc}") from exc
        if args.command == "export":
            from qsm.app.export import export

            result = export(
                front=args.front,
                rank=args.rank,
                mechanism_id=args.id,
                ratios=args.ratios,
                lengths=args.lengths,
                task_points=config["task"]["points"] if args.task_points else None,
                config=config,
                results=args.results,
                out=args.out,
            )
        elif args.command == "check-config":
            result = {"valid": True, "warnings": config_warnings(config)}
        elif args.lengths is not None:
            try:
                result = evaluate_lengths(args.lengths, config)
            except ValueError as exc:
                raise ValueError(f"--lengths: {exc}") from exc
        else:
            try:
                ratios = checked_ratios(args.ratios)
            except ValueError as exc:
                raise ValueError(f"--ratios: {exc}") from exc
            result = evaluate_ratios(ratios, config)
    except (ConfigError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(dumps(result))
    return 0

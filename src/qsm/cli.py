"""Command line: ``python -m qsm evaluate ...`` (see ``python -m qsm --help``)."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

from qsm.config import ConfigError, load_config
from qsm.evaluate import evaluate_ratios


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
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the process exit code."""
    args = _parser().parse_args(argv)
    try:
        config = load_config(args.config)
        if args.task_points is not None:
            pts = args.task_points
            if len(pts) % 2:
                raise ConfigError("--task-points takes pairs of numbers: x1 y1 x2 y2 ...")
            config["task"]["points"] = [pts[i : i + 2] for i in range(0, len(pts), 2)]
        result = evaluate_ratios(args.ratios, config)
    except (ConfigError, ValueError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(result, indent=2))
    return 0

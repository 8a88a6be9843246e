"""Print config/README.md's table of bad inputs: each kind, an example and the message qsm gives.

Each example is written to a file and read as ``snakemake --configfile config/config.yaml FILE``
merges it (``qsm.config.reading.load_config``, which ``qsm check-config`` and the Snakefile run);
the message column is what that prints, the time column how long the check took here. Run from the
checkout: ``python scripts/bad_input_table.py > table.md``.
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from qsm.config.checks import config_warnings
from qsm.config.reading import ConfigError, load_config
from qsm.embodiment.drives.catalogue import default_catalogue_folder
from qsm.workflow.tables import read_table

#: (kind of bad input, the YAML a user might write).
CASES: tuple[tuple[str, str], ...] = (
    ("YAML: a tab", "task:\n\tpayload_kg: 5\n"),
    ("YAML: a bad indent", "task:\n  payload_kg: 5\n   points: [[-0.6, 0.1]]\n"),
    ("unknown key", "dynamics: {shardz: 2}"),
    ("wrong type", "sampling: {n_samples: many}"),
    ("integer written as a fraction", "sampling: {n_samples: 30000.5}"),
    ("out of the schema's range", "dynamics: {shards: 0}"),
    ("not a finite number", "task: {points: [[-0.6, .nan], [-0.5, 0.1]]}"),
    ("a single task point", "task: {points: [[-0.6, 0.1]]}"),
    ("task points in millimetres", "task: {points: [[-530, 170], [-700, 20]]}"),
    ("task out of reach", "task: {points: [[-6.0, 0.0], [-5.8, 0.1]]}"),
    ("task covering the base", "task: {points: [[0.0, 0.0], [-0.3, 0.1]]}"),
    ("task too near the base for its size", "task: {points: [[-0.05, 0.0], [-0.6, 0.0]]}"),
    ("largest scale too small", "scale: {max_m: 0.05}"),
    ("payload in grams", "task: {payload_kg: 5000}"),
    ("payload beyond the motors", "task: {payload_kg: 120}"),
    ("printer in metres", "printing: {build_volume_mm: [0.6, 0.35, 0.35]}"),
    ("printer side below 10 mm", "printing: {build_volume_mm: [600, 350, 5]}"),
    ("printer fits no link", "printing: {build_volume_mm: [100, 100, 15]}"),
    (
        "motor range in radians",
        "operating_range: {theta1_deg: [0.785, 3.1416], theta2_min_deg: -0.654}",
    ),
    ("motor range min above max", "operating_range: {theta1_deg: [180, 45]}"),
    ("motor range over a turn", "operating_range: {theta1_deg: [-200, 200]}"),
    ("motor angle past a full turn", "operating_range: {theta1_deg: [45, 400]}"),
    ("theta2 range empty", "operating_range: {theta2_min_deg: 60}"),
    ("sampling bounds min above max", "sampling: {bounds: {l3: [1.3, 0.8]}}"),
    ("sampling bound not positive", "sampling: {bounds: {l2: [0.0, 0.6]}}"),
    ("no crank-rocker possible", "sampling: {bounds: {l2: [0.5, 0.6], l3: [1.2, 1.3]}}"),
    ("more mechanisms than samples", "sampling: {n_samples: 1000, n_mechanisms: 2000}"),
    ("too few mechanisms for the surrogate", "sampling: {n_mechanisms: 4}"),
    ("optimisation bounds min above max", "optimization: {bounds: {l2_m: [0.3, 0.1]}}"),
    ("optimisation bound not positive", "optimization: {bounds: {l2_m: [0.0, 0.1]}}"),
    ("optimisation bounds in millimetres", "optimization: {bounds: {l1_m: [300, 500]}}"),
    ("front not computed", "optimization: {formulation: paper, formulations: [ratios]}"),
    ("bosses narrower than the bar", "cad: {width_m: 5.0}"),
    ("link section in millimetres", "cad: {width_m: 40, thickness_m: 10, boss_radius_m: 25}"),
    ("density in g/cm^3", "material: {density_kg_m3: 1.04}"),
    ("Young's modulus in GPa", "material: {youngs_modulus_pa: 2.2}"),
    ("yield strength in MPa", "material: {yield_strength_pa: 30}"),
    ("drive catalogue missing", "drives: {catalogue: /no/such/folder}"),
    ("drive catalogue a file", "drives: {catalogue: src/qsm/embodiment/drives/data/motors.csv}"),
    (
        "a stepper without its pull-out curve",
        "drives: {catalogue: steppers}  # motors.csv with a stepper, no torque_speed.csv",
    ),
    ("an empty config file", ""),
    ("a config file that is a list", "- 1\n- 2\n"),
    ("task at x > 0 (designed mirrored)", "task: {points: [[0.53, 0.17], [0.70, 0.02]]}"),
    ("task on both sides of the base", "task: {points: [[-0.1, 0.5], [0.5, 0.5]]}"),
)
#: (kind of bad points file, its CSV text or None for a missing file, the YAML naming it).
POINTS_FILES: tuple[tuple[str, str | None, str], ...] = (
    ("points file missing", None, "task: {points_file: points.csv}"),
    ("points file without its header", "-0.6,0.1\n-0.5,0.1\n", "task: {points_file: points.csv}"),
    (
        "points file: a cell not a number",
        "x_m,y_m\n-0.6,0.1\n-0.5,0.1m\n",
        "task: {points_file: points.csv}",
    ),
    (
        "points file and points both given",
        "x_m,y_m\n-0.6,0.1\n-0.5,0.1\n",
        "task: {points_file: points.csv, points: [[-0.4, 0.1], [-0.3, 0.1]]}",
    ),
)


def _row(kind: str, example: str, outcome: str, message: str, seconds: float) -> str:
    cells = [kind, f"`{example}`".replace("\n", "\\n").replace("\t", "\\t"), outcome, message]
    cells = [c.replace("|", "\\|") for c in cells]
    return f"| {' | '.join(cells)} | {seconds:.2f} |"


def main() -> None:
    """Print the Markdown table."""
    print("| kind of input | example | outcome | message | check (s) |")
    print("| --- | --- | --- | --- | --- |")
    folder = Path(tempfile.mkdtemp())
    path = folder / "mine.yaml"
    steppers = folder / "steppers"
    steppers.mkdir()
    for name in ("motors.csv", "gearboxes.csv", "compatibility.csv"):  # no torque_speed.csv
        (steppers / name).write_text((default_catalogue_folder() / name).read_text())
    cases = [*CASES, ("10,000 task points", None)]
    for kind, text in cases:
        if text is None:
            points = np.random.default_rng(0).normal(size=(10_000, 2)) * 0.05 + [-0.6, 0.1]
            text = f"task: {{points: {np.round(points, 4).tolist()}}}"
            shown = "task: {points: [10,000 points around (-0.6, 0.1)]}"
        else:
            shown = text
        path.write_text(text.replace("catalogue: steppers", f"catalogue: {steppers}"))
        start = time.perf_counter()
        try:
            warnings = config_warnings(load_config("config/config.yaml", path))
        except ConfigError as exc:
            outcome, message = "error", str(exc)
        else:
            outcome = "warning" if warnings else "accepted"
            message = " / ".join(warnings)
        seconds = time.perf_counter() - start
        print(_row(kind, shown, outcome, message.replace(str(folder) + "/", ""), seconds))
    for kind, csv, text in POINTS_FILES:
        points = folder / "points.csv"
        points.unlink(missing_ok=True)
        if csv is not None:
            points.write_text(csv)
        path.write_text(text.replace("points.csv", str(points)))
        start = time.perf_counter()
        try:
            load_config("config/config.yaml", path)
        except ConfigError as exc:
            outcome, message = "error", str(exc)
        else:
            outcome, message = "accepted", ""
        seconds = time.perf_counter() - start
        print(_row(kind, text, outcome, message.replace(str(folder) + "/", ""), seconds))
    table = folder / "dataset.parquet"
    pq.write_table(pa.table({"x": [1.0, 2.0]}), table)
    table.write_bytes(table.read_bytes()[:200])
    start = time.perf_counter()
    try:
        read_table(table)
    except ValueError as exc:
        message = str(exc).replace(str(folder) + "/", "results/")
    print(
        _row("damaged Parquet file", "(truncated)", "error", message, time.perf_counter() - start)
    )


if __name__ == "__main__":
    main()

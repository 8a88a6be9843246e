"""Exploring results: the interactive front, the task-motion GIF, the export, the notebook."""

import base64
import json
import os
import re
import zipfile
from pathlib import Path

import mujoco
import nbformat
import numpy as np
import pandas as pd
import pytest
import trimesh
from nbclient import NotebookClient
from PIL import Image
from workflow_helpers import ROOT, copy_run, snakemake

from qsm.app.cli import main
from qsm.app.export import TRUE_KEYS, export
from qsm.config.reading import load_config
from qsm.config.settings import physics
from qsm.optimization.ranking import front_ranks
from qsm.optimization.verify import verify_design
from qsm.physics.cad import mass_properties
from qsm.physics.duty import duty_cycle, minimum_jerk
from qsm.physics.dynamics import loop_state
from qsm.physics.kinematics import DESIGN_COLUMNS, pose
from qsm.physics.mjcf import add_point_mass
from qsm.physics.task import min_enclosing_circle
from qsm.realization.selection.choice import select_design
from qsm.report.animation import EE_COLOUR, frames_record, write_task_motion
from qsm.workflow.tables import read_table

DESIGN = np.array([0.40, 0.12, 0.40, 0.20, 0.48, 0.16])  # a crank-rocker that closes everywhere


# ---------------------------------------------------------------- helpers


def plotly_figure(path: Path) -> dict:
    """The figure JSON (data and layout) that a page of :mod:`qsm.report.plotly_page` plots, with
    the shared hover texts back in their traces."""
    text = path.read_text()
    start = text.index(">", text.index("id='plotly-figure'")) + 1
    figure = json.loads(text[start : text.index("</script>", start)])
    for trace in figure["data"]:
        if isinstance(trace.get("text"), dict):
            trace["text"] = figure["shared_texts"][trace["text"]["shared"]]
    return figure


def decoded(value) -> np.ndarray:
    """A Plotly array: a list or a typed array ({"dtype", "bdata"}) as numpy."""
    if isinstance(value, dict):
        arr = np.frombuffer(base64.b64decode(value["bdata"]), dtype=np.dtype(value["dtype"]))
        return arr.reshape(value["shape"]) if "shape" in value else arr
    return np.asarray(value)


def drawn_tip(gif: Path, frame: int, geometry: dict) -> np.ndarray:
    """Data coordinates (m) of the centre of the end-effector marker drawn in ``frame``."""
    with Image.open(gif) as im:
        im.seek(frame)
        rgb = np.asarray(im.convert("RGB")).astype(int)
    target = np.array([int(EE_COLOUR[i : i + 2], 16) for i in (1, 3, 5)])
    rows, cols = np.nonzero(np.abs(rgb - target).sum(axis=2) < 60)
    assert len(rows) > 10, f"no end-effector marker in frame {frame}"
    left, top, right, bottom = geometry["box_px"]
    (x0, x1), (y0, y1) = geometry["xlim"], geometry["ylim"]
    cx, cy = cols.mean() + 0.5, rows.mean() + 0.5
    return np.array(
        [
            x0 + (cx - left) / (right - left) * (x1 - x0),
            y1 - (cy - top) / (bottom - top) * (y1 - y0),
        ]
    )


def pixel_m(geometry: dict) -> float:
    """Size of one pixel of the linkage axes in metres (a drawn marker's centre lands within
    1.5 px of its point: pixel snapping and Agg's half-pixel conventions)."""
    left, _, right, _ = geometry["box_px"]
    return (geometry["xlim"][1] - geometry["xlim"][0]) / (right - left)


def gif_frames(path: Path) -> int:
    with Image.open(path) as im:
        return im.n_frames


def run_config(run: Path) -> dict:
    return load_config(run / "config" / "test.yaml")


# ---------------------------------------------------------------- ranks


def test_rank_one_is_the_knee_that_selection_picks_and_unprintable_designs_come_after():
    rng = np.random.default_rng(3)
    n = 12
    table = pd.DataFrame(
        {
            **{c: np.full(n, v) for c, v in zip(DESIGN_COLUMNS, DESIGN, strict=True)},
            "eta_true": rng.uniform(0.05, 0.2, n),
            "tau1_true_Nm": rng.uniform(40, 60, n),
            "tau2_true_Nm": rng.uniform(10, 30, n),
            "feasible": [True] * 10 + [False] * 2,
            "dynamics_status": ["ok"] * n,
            "printable": [True, False] * 6,
        }
    )
    ranks = front_ranks(table)
    assert sorted(ranks) == list(range(1, n + 1))
    printable = table[table["printable"] & table["feasible"]]
    pick = select_design(printable, "knee", volume_mm=(1e4, 1e4, 1e4))
    assert ranks[pick.name] == 1
    assert ranks[table["printable"] & table["feasible"]].max() == len(printable)
    assert set(ranks[~table["feasible"]]) == {n - 1, n}


# ---------------------------------------------------------------- the interactive front


def test_the_html_front_holds_every_pareto_row_with_its_values(run):
    selected = json.loads((run / "results/realization/selected.json").read_text())
    for front in ("paper", "ratios"):
        path = run / f"results/optimization/{front}/pareto.html"
        table = read_table(run / f"results/optimization/{front}/verification.parquet")
        html = path.read_text()
        assert "<script src=" not in html and "http" not in html.split("id='plotly-bundle'")[0]
        assert "Plotly.newPlot" in html  # plotly.js inlined: the page opens offline
        figure = plotly_figure(path)
        traces = figure["data"]
        marked = selected["source"] == front
        # (3D + 3 pairwise) x (predicted, true), and the realised design's star when it is here
        assert len(traces) == 8 + (4 if marked else 0)
        if marked:
            star = traces[8]
            assert star["legendgroup"] == "selected"
            cand = selected["candidate"]
            true = [cand["eta_true"], cand["tau1_true_Nm"], cand["tau2_true_Nm"]]
            shown = [decoded(star[a])[0] for a in ("x", "y", "z")]
            np.testing.assert_allclose(shown, true, rtol=1e-12)
        assert "lower is better" in figure["layout"]["scene"]["xaxis"]["title"]["text"]
        for trace in traces[:8]:
            which = "pred" if trace["legendgroup"] == "predicted" else "true"
            names = [f"eta_{which}", f"tau1_{which}_Nm", f"tau2_{which}_Nm"]
            axes = ["x", "y", "z"] if trace["type"] == "scatter3d" else ["x", "y"]
            shown = {a: decoded(trace[a]) for a in axes}
            for a in axes:
                assert len(shown[a]) == len(table)
            if trace["type"] == "scatter3d":
                for a, name in zip(axes, names, strict=True):
                    np.testing.assert_array_equal(shown[a], table[name].to_numpy(float))
            colour = decoded(trace["marker"]["color"])
            np.testing.assert_array_equal(colour, table["scale_m"].to_numpy(float))
        texts = traces[0]["text"]
        assert len(texts) == len(table)
        for text, (_, row) in zip(texts, table.iterrows(), strict=True):
            lengths = re.search(r"lengths \(mm\): (.*?)<br>", text).group(1)
            mm = [float(v.split()[-1]) for v in lengths.split(", ")]
            np.testing.assert_allclose(
                mm, 1e3 * row[list(DESIGN_COLUMNS)].to_numpy(float), atol=0.051
            )
            for key, digits in (("eta", 4), ("tau1", 2), ("tau2", 2)):
                found = re.search(rf"{key} \(.*?\): predicted ([\d.]+), true ([\d.]+)", text)
                unit = "" if key == "eta" else "_Nm"
                tol = 0.51 * 10.0**-digits
                assert float(found.group(1)) == pytest.approx(row[f"{key}_pred{unit}"], abs=tol)
                assert float(found.group(2)) == pytest.approx(row[f"{key}_true{unit}"], abs=tol)
            held = re.search(r"holds the task: (yes|NO)", text).group(1)
            assert (held == "yes") == bool(row["task_contained"])
            printable = re.search(r"printable: (yes|NO)", text).group(1)
            assert (printable == "yes") == bool(row["printable"])
        ranks = [int(re.search(r"rank (\d+) of", t).group(1)) for t in texts]
        assert sorted(ranks) == list(range(1, len(table) + 1))
        assert f"--front {front} --rank {ranks[0]}" in texts[0]


# ---------------------------------------------------------------- the task motion


def synthetic_series(design: np.ndarray, duration_s: float = 2.0, dt: float = 0.004):
    """A payload-test series moving between two poses, with made-up torques."""
    start, end = np.radians([150.0, 30.0]), np.radians([90.0, -10.0])
    t = np.arange(0.0, duration_s + dt / 2, dt)
    theta, *_ = minimum_jerk(start, end, duration_s, t)
    deg = np.degrees(theta)
    tau = np.column_stack([40 * np.sin(t), -20 * np.cos(t)])
    return pd.DataFrame(
        {
            "t_s": t,
            "theta1_ref_deg": deg[:, 0],
            "theta2_ref_deg": deg[:, 1],
            "theta1_deg": deg[:, 0],
            "theta2_deg": deg[:, 1],
            "tau1_requested_Nm": tau[:, 0],
            "tau2_requested_Nm": tau[:, 1],
            "tau1_applied_Nm": tau[:, 0],
            "tau2_applied_Nm": tau[:, 1],
        }
    )


def test_the_animation_has_one_frame_per_sample_and_draws_the_start_and_end_poses(tmp_path):
    series = synthetic_series(DESIGN)
    ends = series.iloc[[0, -1]][["theta1_deg", "theta2_deg"]].to_numpy(float)
    points = pose(DESIGN, *np.radians(ends).T).E
    gif = tmp_path / "motion.gif"
    op = physics.operating_range({"theta1_deg": [45.0, 180.0], "theta2_min_deg": -37.5})
    result = write_task_motion(
        DESIGN, series, points, min_enclosing_circle(points), op, (150.0, 100.0), gif, fps=10
    )
    record = frames_record(result, DESIGN)
    assert gif_frames(gif) == record["n_frames"] == 21  # 2 s at 10 frames/s, both ends
    assert record["sample"][0] == 0 and record["sample"][-1] == len(series) - 1
    geometry = record["geometry"]
    with Image.open(gif) as im:
        assert list(im.size) == geometry["size_px"]
    tips = {}
    for k in (0, 10, record["n_frames"] - 1):
        row = series.iloc[record["sample"][k]]
        expected = pose(DESIGN, *np.radians([row["theta1_deg"], row["theta2_deg"]])).E
        tips[k] = drawn_tip(gif, k, geometry)
        assert np.linalg.norm(tips[k] - expected) < 2.0 * pixel_m(geometry), k
    assert np.linalg.norm(tips[0] - tips[record["n_frames"] - 1]) > 0.1  # they differ


def test_the_workflow_animates_the_payload_test(run):
    real = run / "results/realization"
    series = read_table(real / "payload_test_series.parquet")
    record = json.loads((real / "task_motion.json").read_text())
    duration = series["t_s"].iloc[-1] - series["t_s"].iloc[0]
    assert gif_frames(real / "task_motion.gif") == record["n_frames"]
    assert record["n_frames"] == round(duration * record["fps"]) + 1
    payload = json.loads((real / "payload_test.json").read_text())
    assert series["t_s"].iloc[-1] == pytest.approx(payload["duration_s"])
    design = np.array(json.loads((real / "selected.json").read_text())["design_m"])
    for k, row in ((0, series.iloc[0]), (record["n_frames"] - 1, series.iloc[-1])):
        expected = pose(design, *np.radians([row["theta1_deg"], row["theta2_deg"]])).E
        tip = drawn_tip(real / "task_motion.gif", k, record["geometry"])
        assert np.linalg.norm(tip - expected) < 2.0 * pixel_m(record["geometry"])
    viewer = (real / "task_motion.html").read_text()
    data = json.loads(re.search(r"id='motion-data'>(.*?)</script>", viewer).group(1))
    assert len(data["frames"]) == record["n_frames"] and f"{record['n_frames']} frames" in viewer


# ---------------------------------------------------------------- the export


def _realised_scale(record, cad):
    """Each link's section scale (4,) on ``cad``'s in an export's record."""
    links = record["strength"]["links"]
    return np.array([links[k]["width_mm"] / (1e3 * cad.width_m) for k in links])


def test_export_round_trip_of_a_pareto_design(run, tmp_path):
    config = run_config(run)
    out = tmp_path / "paper-1"
    args = ["export", "--front", "paper", "--rank", "1", "--results", str(run / "results")]
    assert main([*args, "--config", str(run / "config/test.yaml"), "--out", str(out)]) == 0
    record = json.loads((out / "design.json").read_text())
    design = np.array(list(record["design"]["lengths_m"].values()))
    # the JSON holds a fresh evaluation of the design under the run's config
    fit = physics.fit_of(config)
    duty = duty_cycle(physics.duty(config["dynamics"]["duty"], config["operating_range"]))
    cad = physics.cad(config["cad"], config["material"])
    scale = _realised_scale(record, cad)  # the sections as realised for the tolerance
    fresh = verify_design(design, fit, duty, cad, config["task"]["payload_kg"], scale)
    assert record["true_performance"] == {k: fresh[k] for k in TRUE_KEYS}
    # ... which is the run's own verification of that design (its torques: at the configured
    # section, the export's at the realised one)
    table = read_table(run / "results/optimization/paper/verification.parquet")
    row = table.iloc[int(np.flatnonzero(front_ranks(table) == 1)[0])]
    np.testing.assert_array_equal(design, row[list(DESIGN_COLUMNS)].to_numpy(float))
    same = ("eta_true", "containment_margin_m")
    if np.allclose(scale, 1.0, rtol=0, atol=1e-12):
        same += ("tau1_true_Nm", "tau2_true_Nm")
    for key in same:
        assert record["true_performance"][key] == pytest.approx(row[key], rel=1e-12)
    selected = json.loads((run / "results/realization/selected.json").read_text())
    np.testing.assert_array_equal(design, selected["design_m"])  # rank 1 = the knee selected
    # one realisation (qsm.realization.selection.pipeline.realize): the export's strength and drive
    # records are the workflow's, and its solid bored parts the workflow's, file for file
    assert record["strength"] == selected["strength"]
    assert record["drives"] == selected["drives"]
    topology = json.loads((run / "results/realization/topology.json").read_text())
    links = topology["links"]
    held = {n for n, link in links.items() if link["carries_loads"] and not link["kept_solid"]}
    kit = json.loads((run / "results/realization/kit/kit.json").read_text())
    inserts = {h["link"]: 6 for h in kit["hubs"] if h["link_screws"]["thread"]}  # the kit's holes
    for name, part in record["parts"].items():
        if name not in held:  # an optimised plate has the openings of its own besides
            assert part["holes"] + inserts.get(name, 0) == topology["parts"]["holes"][name], name
        built = run / f"results/realization/stl/before/{name}.stl"
        assert (out / f"stl/{name}.stl").read_bytes() == built.read_bytes(), name
    # the MJCF loads in MuJoCo with the loop closed, the STLs are watertight millimetre solids
    model = mujoco.MjModel.from_xml_path(str(out / "model.xml"))
    assert model.neq == 1 and model.nu == 2 and model.njnt == 4
    masses = mass_properties(design, cad, None if np.allclose(scale, 1.0) else tuple(scale))
    assert model.body("crank").mass[0] == pytest.approx(masses["crank"].mass_kg, rel=1e-5)
    for name, link in record["printability"]["links"].items():
        mesh = trimesh.load(out / link["file"])
        assert mesh.is_watertight and link["watertight"], name
        np.testing.assert_allclose(sorted(mesh.extents), sorted(link["box_mm"]), rtol=1e-6)
    assert record["printability"]["printable"] == bool(row["printable"])
    # the URDF is the spanning tree: with the passive joints set from the loop, D closes and E
    # is where the kinematics put it; its payload-laden upper arm weighs what the MJCF's does
    tree = mujoco.MjModel.from_xml_path(str(out / "model.urdf"))
    assert tree.neq == 0 and tree.njnt == 4
    assert "cannot express closed kinematic loops" in (out / "model.urdf").read_text()
    assert "d_upper == d_coupler" in record["urdf"]["closed_loop"]
    carried = config["task"]["payload_kg"] + record["tool_flange_kg"]  # payload and flange at E
    upper = add_point_mass(masses["upper_arm"], carried, [design[4], -design[5], 0.0])
    assert tree.body("upper_arm").mass[0] == pytest.approx(upper.mass_kg, rel=1e-8)
    data = mujoco.MjData(tree)
    theta = np.radians([[120.0, 20.0], [80.0, -10.0], [160.0, 60.0]])
    state = loop_state(design, theta, np.zeros_like(theta), np.zeros_like(theta))
    for k in range(len(theta)):
        data.qpos[:] = state.q[k]
        mujoco.mj_kinematics(tree, data)
        gap = data.body("d_upper").xpos - data.body("d_coupler").xpos
        assert np.linalg.norm(gap) < 1e-9
        np.testing.assert_allclose(data.body("end_effector").xpos[:2], pose(design, *theta[k]).E)
    assert (out / "design.png").stat().st_size > 20_000


def test_export_of_a_dataset_mechanism_and_of_ratios(run, tmp_path):
    config = run_config(run)
    dataset = read_table(run / "results/dataset.parquet")
    row = dataset.iloc[3]
    record = export(
        mechanism_id=int(row["mechanism_id"]),
        config=config,
        results=run / "results",
        out=tmp_path / "id",
    )
    perf = record["true_performance"]
    assert perf["feasible"]
    scale = _realised_scale(record, physics.cad(config["cad"], config["material"]))
    if np.allclose(scale, 1.0, rtol=0, atol=1e-12):  # not grown for the tolerance
        assert perf["tau1_true_Nm"] == pytest.approx(row["tau1_Nm"], rel=1e-9)
    else:  # heavier links need more torque
        assert perf["tau1_true_Nm"] > row["tau1_Nm"]
    assert perf["eta_true"] == pytest.approx(row["eta"], rel=1e-6)
    ratios = row[["l2", "l3", "l4", "ee_x", "ee_y"]].to_numpy(float)
    again = export(ratios=ratios, config=config, out=tmp_path / "ratios")
    assert again["design"]["scale_m"] == pytest.approx(row["scale_m"], rel=1e-9)
    assert (tmp_path / "ratios" / "model.urdf").is_file()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--front", "pareto", "--rank", "1"], "unknown front 'pareto' (--front)"),
        (["--front", "paper", "--rank", "0"], "--rank 0 is out of range"),
        (["--front", "paper", "--rank", "999"], "--rank 999 is out of range"),
        (["--front", "paper"], "--front and --rank go together"),
        (["--id", "-5"], "--id -5 is not a mechanism_id"),
        (["--front", "paper", "--rank", "1", "--task-points", "0 0"], "--task-points"),
    ],
)
def test_bad_export_arguments_are_named(run, tmp_path, capsys, args, message):
    args = [a for arg in args for a in arg.split()]
    config = ["--config", str(run / "config/test.yaml")]
    code = main(["export", *args, "--results", str(run / "results"), *config])
    err = capsys.readouterr().err
    assert code == 2 and message in err, err
    if "rank" in message and "out of range" in message:
        n = len(read_table(run / "results/optimization/paper/verification.parquet"))
        assert f"ranks 1 to {n}" in err


def test_export_refuses_a_config_other_than_the_runs(run, tmp_path, capsys):
    other = tmp_path / "other.yaml"
    other.write_text("task: {payload_kg: 2.0}\n")
    code = main(["export", "--front", "paper", "--rank", "1", "--results", str(run / "results"),
                 "--config", str(other), "--out", str(tmp_path / "x")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "payload_kg" in err and "--config" in err


# ---------------------------------------------------------------- notebook and report


def test_the_stored_notebook_shows_its_outputs_and_stays_small():
    """docs/quickstart.ipynb is stored executed (it reads on a code host): every code cell has
    output, none an error, no Plotly blob, and the file stays under 300 kB."""
    path = ROOT / "docs" / "quickstart.ipynb"
    nb = nbformat.read(path, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(c["outputs"] for c in code)
    outputs = [o for c in code for o in c["outputs"]]
    assert not [o for o in outputs if o.output_type == "error"]
    assert any("image/png" in o.get("data", {}) for o in outputs)
    assert not any("application/vnd.plotly.v1+json" in o.get("data", {}) for o in outputs)
    assert path.stat().st_size < 300_000


def test_quickstart_notebook_runs_on_a_finished_run(run, tmp_path, monkeypatch):
    work = copy_run(run, tmp_path / "nb")
    monkeypatch.setenv("QSM_CONFIG", "config/test.yaml")
    monkeypatch.setenv("QSM_RESULTS", "results")
    monkeypatch.setenv(
        "PYTHONPATH", os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])
    )
    nb = nbformat.read(ROOT / "docs" / "quickstart.ipynb", as_version=4)
    start = work / "docs"  # where Jupyter starts a kernel for docs/quickstart.ipynb
    start.mkdir(exist_ok=True)
    NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(start)}}
    ).execute()
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors
    record = json.loads((work / "results/exports/paper-rank-1/design.json").read_text())
    assert record["source"] == {**record["source"], "front": "paper", "rank": 1}


def test_the_report_zip_holds_the_interactive_views(run, tmp_path):
    work = copy_run(run, tmp_path / "report")
    snakemake(work, "--report", "results/report.zip")
    with zipfile.ZipFile(work / "results/report.zip") as archive:
        names = archive.namelist()
    for name in ("pareto.html", "task_motion.html"):
        assert any(n.endswith(name) for n in names), name

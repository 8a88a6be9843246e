"""The interactive front drawn by headless Chromium as both report forms show it.

The single-file report shows an HTML result in an iframe whose ``src`` is the file as a base64
``data:`` URL (Snakemake's own ``data_uri_from_file``); Chromium leaves the iframe blank when the
URL is longer than 2 MiB, and a page there is no secure context (no WebCodecs). The zip report
shows the file itself. Plotly paints each subplot's
background in its template's colour (#E5ECF6) and the realised design as a red star, so a page
that drew has many pixels of the one and some of the other; a blank or broken page has none.
"""

import gzip
import hashlib
import html
import json
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from snakemake.report.common import data_uri_from_file
from workflow_helpers import copy_run, snakemake

from qsm.report.plotly_page import BUNDLE, CHROMIUM_MAX_URL_CHARS

PLOT_BACKGROUND = (0xE5, 0xEC, 0xF6)
SIZE = (1400, 1000)
DATA = Path(__file__).resolve().parents[1] / "src/qsm/report/data"


def _find_chromium() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="session")
def chromium() -> str:
    """Headless Chromium: found, or installed with Debian's apt when this is root (as in CI),
    like the SLURM tests' SLURM; otherwise the test is skipped."""
    path = _find_chromium()
    if path is None and os.geteuid() == 0 and shutil.which("apt-get"):
        env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
        apt = ["apt-get", "-o", "DPkg::Lock::Timeout=600", "-q"]
        subprocess.run([*apt, "update"], capture_output=True, check=False, env=env)
        subprocess.run(
            [*apt, "-y", "--no-install-recommends", "install", "chromium"],
            capture_output=True, check=False, env=env,
        )  # fmt: skip
        path = _find_chromium()
    if path is None:
        pytest.skip("needs chromium (apt-get install chromium)")
    return path


def screenshot(chromium: str, url: str, out: Path, profile: Path) -> np.ndarray:
    """RGB pixels of ``url`` drawn by headless Chromium in a SIZE window."""
    subprocess.run(
        [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
         "--no-first-run", "--disable-background-networking", "--disable-component-update",
         "--disable-sync", f"--user-data-dir={profile}", "--hide-scrollbars",
         "--virtual-time-budget=15000", f"--window-size={SIZE[0]},{SIZE[1]}",
         f"--screenshot={out}", url],
        check=True, capture_output=True, timeout=180,
    )  # fmt: skip
    with Image.open(out) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def share_of(rgb: np.ndarray, colour: tuple[int, int, int], tol: int = 6) -> float:
    """Share of the pixels within ``tol`` of ``colour`` in every channel."""
    return float((np.abs(rgb - np.array(colour)).max(axis=2) <= tol).mean())


def red_star_pixels(rgb: np.ndarray) -> int:
    return int(((rgb[..., 0] > 220) & (rgb[..., 1] < 40) & (rgb[..., 2] < 40)).sum())


def test_the_vendored_bundle_is_the_one_its_readme_names():
    readme = (DATA / "README.md").read_text()
    js = gzip.decompress((DATA / BUNDLE).read_bytes())
    assert hashlib.sha256(js).hexdigest() in readme
    version = re.search(r"version (\d+\.\d+\.\d+)", readme).group(1)
    assert js[:200].decode().count(f"plotly.js (gl3d - minified) v{version}") == 1


def in_report_iframe(chromium: str, page: Path, tmp_path: Path) -> np.ndarray:
    """Pixels of ``page`` shown as the single-file report shows it: an iframe whose ``src`` is
    Snakemake's ``data:`` URL of the file."""
    uri = data_uri_from_file(page)
    assert len(uri) < CHROMIUM_MAX_URL_CHARS
    outer = tmp_path / "outer.html"
    outer.write_text(
        "<html><body style='margin: 0'><iframe style='border: 0' width='1400' height='1000' "
        f"src='{html.escape(uri, quote=True)}'></iframe></body></html>"
    )
    return screenshot(chromium, outer.as_uri(), tmp_path / "page.png", tmp_path / "profile")


@pytest.mark.workflow
def test_the_front_draws_in_the_single_file_reports_iframe(run, tmp_path, chromium):
    selected = json.loads((run / "results/realization/selected.json").read_text())
    rgb = in_report_iframe(
        chromium, run / f"results/optimization/{selected['source']}/pareto.html", tmp_path
    )
    assert share_of(rgb, PLOT_BACKGROUND) > 0.15
    assert red_star_pixels(rgb) > 50  # the realised design, marked


@pytest.mark.workflow
def test_the_front_draws_from_the_zip_report(run, tmp_path, chromium):
    work = copy_run(run, tmp_path / "report")
    snakemake(work, "--report", "results/report.zip")
    with zipfile.ZipFile(work / "results/report.zip") as archive:
        archive.extractall(tmp_path / "unzipped")
    pages = sorted((tmp_path / "unzipped").rglob("pareto.html"))
    assert len(pages) == 2
    for k, page in enumerate(pages):
        rgb = screenshot(
            chromium, page.as_uri(), tmp_path / f"front{k}.png", tmp_path / f"profile{k}"
        )
        assert share_of(rgb, PLOT_BACKGROUND) > 0.15, page


@pytest.mark.workflow
def test_the_motion_page_draws_in_the_single_file_reports_iframe(run, tmp_path, chromium):
    """The page's script draws the frames into a canvas (the end effector is the only magenta)."""
    rgb = in_report_iframe(chromium, run / "results/realization/task_motion.html", tmp_path)
    assert share_of(rgb, (0xFF, 0x00, 0xFF), tol=30) * rgb.shape[0] * rgb.shape[1] > 20

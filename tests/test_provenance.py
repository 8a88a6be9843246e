"""Rerun tracking: the library sources a script reaches, through every kind of import."""

import json
from pathlib import Path

from qsm.workflow.provenance import PACKAGE_DIR, _module_file, module_closure, source_hash

ROOT = Path(__file__).resolve().parents[1]


def make_package(tmp_path: Path) -> Path:
    """A package ``qsm`` with a subpackage, absolute and relative imports, and an unused module."""
    pkg = tmp_path / "qsm"
    (pkg / "sub").mkdir(parents=True)
    files = {
        "__init__.py": "",
        "a.py": "from .b import x\n",
        "b.py": "x = 1\n",
        "unused.py": "y = 2\n",
        "sub/__init__.py": "from . import d\n",
        "sub/c.py": "from ..a import x\nimport numpy\n",
        "sub/d.py": "z = 3\n",
    }
    for name, text in files.items():
        (pkg / name).write_text(text)
    return pkg


def test_relative_imports_and_package_inits_are_followed(tmp_path):
    pkg = make_package(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("from qsm.sub.c import x\n")
    found = {str(p.relative_to(pkg)) for p in module_closure(str(script), pkg)}
    assert found == {"__init__.py", "a.py", "b.py", "sub/__init__.py", "sub/c.py", "sub/d.py"}


def test_editing_a_package_init_changes_the_hash(tmp_path):
    pkg = make_package(tmp_path)
    script = tmp_path / "script.py"
    script.write_text("import qsm.sub.c\n")
    before = source_hash(script, pkg)
    (pkg / "unused.py").write_text("y = 3\n")
    module_closure.cache_clear()
    assert source_hash(script, pkg) == before  # not imported: no rerun
    (pkg / "sub" / "__init__.py").write_text("from . import d\n# edited\n")
    module_closure.cache_clear()
    assert source_hash(script, pkg) != before


def test_every_workflow_script_depends_on_the_package_init():
    for script in (ROOT / "workflow" / "scripts").glob("*.py"):
        assert PACKAGE_DIR / "__init__.py" in module_closure(str(script)), script.name


def test_importing_the_figure_modules_leaves_matplotlib_backend_alone():
    """A notebook keeps its backend: no qsm module calls matplotlib.use at import."""
    import subprocess
    import sys

    code = (
        "import matplotlib; matplotlib.use('svg'); "
        "import qsm.report.figures, qsm.design_rules.plots, qsm.report.payload_report; "
        "import qsm.realization.topology.topology; "
        "print(matplotlib.get_backend())"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "svg"


def test_the_public_api_is_importable_from_qsm_without_loading_mujoco():
    import subprocess
    import sys

    code = (
        "import sys, qsm; assert 'mujoco' not in sys.modules; "
        "from qsm import end_effector, joint_torques, evaluate_ratios, load_config, "
        "load_surrogate, choose_design, printing_advice; print(len(qsm.__all__))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "9"


def test_deferred_imports_are_followed_and_type_checking_ones_are_not(tmp_path):
    """An import inside a function runs when the function does, so it is part of the hash; one
    in a ``TYPE_CHECKING`` block never runs."""
    pkg = tmp_path / "qsm"
    pkg.mkdir()
    files = {
        "__init__.py": "",
        "layer.py": (
            "import typing\nfrom typing import TYPE_CHECKING\n"
            "try:\n    from .light import a\nexcept ImportError:\n    pass\n"
            "if TYPE_CHECKING:\n    from .typed import b\n"
            "if typing.TYPE_CHECKING:\n    from .typed2 import b2\n"
            "else:\n    from .other import o\n"
            "def build():\n    from .heavy import c\n    return c\n"
        ),
        "light.py": "a = 1\n",
        "typed.py": "b = 2\n",
        "typed2.py": "b2 = 2\n",
        "other.py": "o = 2\n",
        "heavy.py": "c = 3\n",
    }
    for name, text in files.items():
        (pkg / name).write_text(text)
    script = tmp_path / "script.py"
    script.write_text("from qsm.layer import build\n")
    found = {p.name for p in module_closure(str(script), pkg)}
    assert found == {"__init__.py", "layer.py", "light.py", "other.py", "heavy.py"}


def test_select_designs_hash_follows_the_drive_check(tmp_path):
    """select_design runs the drive check only through the settings layer: an edit of
    embodiment/drives/drive_checks.py changes its rule's hash (edaf7cc's hash left it out)."""
    import shutil

    pkg = tmp_path / "qsm"
    shutil.copytree(PACKAGE_DIR, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    script = ROOT / "workflow" / "scripts" / "select_design.py"
    before = source_hash(script, pkg)
    module = pkg / "embodiment" / "drives" / "drive_checks.py"
    module.write_text(module.read_text() + "\n# an edit\n")
    module_closure.cache_clear()
    assert source_hash(script, pkg) != before


def test_every_module_a_job_ran_is_in_its_rules_hash(run):
    """Each job of the test run recorded the qsm modules it had loaded at its end
    (``QSM_RECORD_MODULES``, :func:`qsm.workflow.logs.record_modules`): every one of them is in
    the closure that its script's rerun hash covers."""
    records = sorted((run / "modules").glob("*.json"))
    scripts = {p.name for p in (ROOT / "workflow" / "scripts").glob("*.py")}
    seen = set()
    for path in records:
        record = json.loads(path.read_text())
        script = record["script"].split(".", 1)[1]  # Snakemake runs a copy named tmpXXXX.<name>
        seen.add(script)
        closure = set(module_closure(str(ROOT / "workflow" / "scripts" / script)))
        ran = {_module_file(name, PACKAGE_DIR) for name in record["modules"]}
        missing = sorted(str(p.relative_to(PACKAGE_DIR)) for p in ran - closure if p is not None)
        assert not missing, f"{script} ran modules outside its rerun hash: {missing}"
    assert seen == scripts  # every rule script ran and recorded


def test_scripts_build_settings_only_through_the_settings_layer():
    for script in (ROOT / "workflow" / "scripts").glob("*.py"):
        text = script.read_text()
        for idiom in (
            "Settings(",
            "from_degrees(",
            "from_section",
            "cad_settings",
            "duty_settings",
        ):
            assert idiom not in text, f"{script.name} builds settings with {idiom}"


def test_the_quick_import_scan_finds_what_parsing_whole_files_finds(tmp_path, monkeypatch):
    """Files whose qsm imports all start a line have only their import lines parsed: on every
    module of qsm and every workflow script, a docstring that reads like an import and imports
    in a module-level block and in a function, the qsm modules found are those of the
    whole-file parse."""
    import ast

    from qsm.workflow import provenance

    prose = tmp_path / "prose.py"
    prose.write_text('"""Notes.\n\nimport time matters here.\n"""\nfrom qsm.physics import cad\n')
    blocks = tmp_path / "blocks.py"
    blocks.write_text(
        "try:\n    from qsm.physics import duty\nexcept ImportError:\n    pass\n\n\n"
        "def f():\n    from qsm.physics import mjcf\n"
    )
    scripts = (ROOT / "workflow" / "scripts").glob("*.py")
    files = [*PACKAGE_DIR.rglob("*.py"), *scripts, prose, blocks]

    def found() -> dict[Path, frozenset[str]]:
        provenance._qsm_imports.cache_clear()
        return {f: provenance._qsm_imports(f, PACKAGE_DIR) for f in files}

    quick = found()
    whole = provenance._imports  # the statements of a whole-file parse
    monkeypatch.setattr(provenance, "_import_statements", lambda p: whole(ast.parse(p.read_text())))
    assert quick == found()
    assert quick[prose] == {"qsm", "qsm.physics", "qsm.physics.cad"}
    assert quick[blocks] == {"qsm", "qsm.physics", "qsm.physics.duty", "qsm.physics.mjcf"}
    provenance._qsm_imports.cache_clear()

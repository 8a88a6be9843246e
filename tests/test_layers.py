"""The packages of ``qsm`` import only downward: no package imports one listed above it."""

import ast
import graphlib
from pathlib import Path

import pytest

import qsm

SRC = Path(qsm.__file__).parent


def _rank() -> dict[str, int]:
    return {name: k for k, layer in enumerate(qsm.LAYERS) for name in layer}


def _unit(module: str) -> str:
    """The entry of ``qsm.LAYERS`` that holds dotted ``module`` (without ``qsm.``): the longest
    listed prefix, or the module's first part when none is listed."""
    parts = module.split(".")
    for k in range(len(parts), 0, -1):
        if ".".join(parts[:k]) in _rank():
            return ".".join(parts[:k])
    return parts[0]


def _package(path: Path) -> str:
    rel = path.relative_to(SRC).with_suffix("").parts
    return "__init__" if rel == ("__init__",) else _unit(".".join(rel))


def _imports(path: Path) -> set[str]:
    """The layer entries of ``qsm`` that ``path`` imports (at any depth of the file)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        found |= {_unit(n.removeprefix("qsm.")) for n in names if n.startswith("qsm.")}
    return found


#: Units that are only a package's docstring, split into layered subpackages.
DOCSTRING_PACKAGES = {"__init__", "realization"}


def test_every_package_and_module_has_a_layer():
    names = {_package(p) for p in SRC.rglob("*.py")} - DOCSTRING_PACKAGES
    assert names == set(_rank()), "list every package or module of qsm in qsm.LAYERS"


@pytest.mark.parametrize("path", sorted(SRC.rglob("*.py")), ids=lambda p: str(p.relative_to(SRC)))
def test_imports_point_down(path):
    rank = _rank()
    own = _package(path)
    if own in DOCSTRING_PACKAGES:  # the package docstrings import nothing
        return
    up = sorted(p for p in _imports(path) if p != own and rank[p] >= rank[own])
    assert not up, f"{path.relative_to(SRC)} ({own}, layer {rank[own]}) imports {up}"


def test_the_test_can_fail(tmp_path):
    """A module of physics that imports the optimization is reported."""
    module = tmp_path / "bad.py"
    module.write_text("from qsm.optimization.constraints import link_boxes_mm\n")
    assert _imports(module) == {"optimization"}
    assert _rank()["optimization"] > _rank()["physics"]


#: The longest a function of qsm may be (lines, its signature and docstring included).
MAX_FUNCTION_LINES = 60


def _long_functions(root: Path, limit: int) -> set[str]:
    """``path:name`` of every function under ``root`` longer than ``limit`` lines."""
    found = set()
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                if node.end_lineno - node.lineno + 1 > limit:
                    found.add(f"{path.relative_to(root).as_posix()}:{node.name}")
    return found


def test_no_function_is_longer_than_the_limit():
    assert _long_functions(SRC, MAX_FUNCTION_LINES) == set()


def test_the_function_length_check_can_fail(tmp_path):
    body = "".join(f"    x{k} = {k}\n" for k in range(MAX_FUNCTION_LINES))
    (tmp_path / "long.py").write_text(f"def long():\n{body}")
    (tmp_path / "short.py").write_text("def short():\n    return 1\n")
    assert _long_functions(tmp_path, MAX_FUNCTION_LINES) == {"long.py:long"}


def test_no_two_modules_share_a_name():
    names = [p.name for p in SRC.rglob("*.py") if p.name != "__init__.py"]
    assert sorted({n for n in names if names.count(n) > 1}) == []


def _package_graph() -> dict[str, set[str]]:
    """Each top-level package (or module) of qsm and the top-level ones it imports."""
    graph: dict[str, set[str]] = {}
    for path in SRC.rglob("*.py"):
        own = path.relative_to(SRC).parts[0].removesuffix(".py")
        found = {unit.split(".")[0] for unit in _imports(path)} - {own}
        graph.setdefault(own, set()).update(found)
    return graph


def test_the_packages_import_each_other_without_a_cycle():
    """Checked at package level, not only by layer entry: no package is above itself."""
    tuple(graphlib.TopologicalSorter(_package_graph()).static_order())  # raises CycleError


def test_the_cycle_check_can_fail():
    with pytest.raises(graphlib.CycleError):
        tuple(
            graphlib.TopologicalSorter(
                {"config": {"physics"}, "physics": {"config"}}
            ).static_order()
        )

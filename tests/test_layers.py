"""The packages of ``qsm`` import only downward: no package imports one listed above it."""

import ast
from pathlib import Path

import pytest

import qsm

SRC = Path(qsm.__file__).parent


def _package(path: Path) -> str:
    rel = path.relative_to(SRC).parts
    return rel[0] if len(rel) > 1 else rel[0].removesuffix(".py")


def _imports(path: Path) -> set[str]:
    """The ``qsm`` packages and top-level modules ``path`` imports (at any depth of the file)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        names = []
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        found |= {n.split(".")[1] for n in names if n.startswith("qsm.")}
    return found


def _rank() -> dict[str, int]:
    return {name: k for k, layer in enumerate(qsm.LAYERS) for name in layer}


def test_every_package_and_module_has_a_layer():
    names = {_package(p) for p in SRC.rglob("*.py")} - {"__init__"}
    assert names == set(_rank()), "list every package or module of qsm in qsm.LAYERS"


@pytest.mark.parametrize("path", sorted(SRC.rglob("*.py")), ids=lambda p: str(p.relative_to(SRC)))
def test_imports_point_down(path):
    rank = _rank()
    own = _package(path)
    if own == "__init__":
        return
    up = sorted(p for p in _imports(path) if p != own and rank[p] >= rank[own])
    assert not up, f"{path.relative_to(SRC)} ({own}, layer {rank[own]}) imports {up}"


def test_the_test_can_fail(tmp_path):
    """A module of physics that imports the optimization is reported."""
    module = tmp_path / "bad.py"
    module.write_text("from qsm.optimization.constraints import link_boxes_mm\n")
    assert _imports(module) == {"optimization"}
    assert _rank()["optimization"] > _rank()["physics"]

"""Which library sources a workflow script runs, and a hash of them for Snakemake's params.

Snakemake reruns a rule when its script changes, not when a module the script imports does. A
rule that passes ``source_hash(script)`` as a param is rerun when any ``qsm`` module it reaches
through its imports changes, and only then.
"""

from __future__ import annotations

import ast
import hashlib
from functools import cache
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent


def _qsm_imports(path: Path) -> set[str]:
    """Names of the ``qsm`` modules that the Python file ``path`` imports."""
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "qsm":
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            names.update(a.name for a in node.names if a.name.split(".")[0] == "qsm")
    return names


def _module_file(name: str) -> Path | None:
    parts = name.split(".")[1:]
    candidate = PACKAGE_DIR.joinpath(*parts).with_suffix(".py") if parts else None
    return candidate if candidate is not None and candidate.exists() else None


@cache
def module_closure(script: str) -> tuple[Path, ...]:
    """The ``qsm`` source files that ``script`` reaches through its imports, sorted."""
    seen: set[Path] = set()
    todo = [Path(script)]
    while todo:
        path = todo.pop()
        for name in _qsm_imports(path):
            found = _module_file(name)
            if found is not None and found not in seen:
                seen.add(found)
                todo.append(found)
    return tuple(sorted(seen))


def source_hash(script: str | Path) -> str:
    """Short SHA-256 of the ``qsm`` sources that ``script`` depends on (config values reach the
    rules as params of their own, so the schema is not part of it)."""
    digest = hashlib.sha256()
    for path in module_closure(str(script)):
        digest.update(path.name.encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]

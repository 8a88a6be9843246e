"""Which library sources a workflow script runs, and a hash of them for Snakemake's params.

Snakemake reruns a rule when its script changes, not when a module the script imports does. A
rule that passes ``source_hash(script)`` as a param is rerun when any ``qsm`` module it reaches
through its imports changes, and only then. Absolute and relative imports count, and so does the
``__init__.py`` of every package on the way (Python runs it on import). Imports inside functions
are deferred and not followed (:mod:`qsm.settings` relies on that), nor are ``TYPE_CHECKING``
blocks.
"""

from __future__ import annotations

import ast
import hashlib
from functools import cache
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[1]  # src/qsm


def _package_of(path: Path, package_dir: Path) -> list[str] | None:
    """Dotted package (as parts) that the file ``path`` belongs to, None outside the package."""
    try:
        rel = path.resolve().relative_to(package_dir.parent)
    except ValueError:
        return None
    return list(rel.parts[:-1])


def _module_level(tree: ast.Module) -> list[ast.stmt]:
    """Statements run on import: the module body and its ``try``/``if`` blocks, not function
    bodies (deferred imports) nor ``if TYPE_CHECKING:`` blocks (never run)."""
    out: list[ast.stmt] = []
    todo = list(tree.body)
    while todo:
        node = todo.pop()
        out.append(node)
        if isinstance(node, ast.If):
            if not (isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"):
                todo += node.body + node.orelse
        elif isinstance(node, ast.Try):
            todo += node.body + node.orelse + node.finalbody
            for handler in node.handlers:
                todo += handler.body
    return out


@cache
def _qsm_imports(path: Path, package_dir: Path) -> frozenset[str]:
    """Dotted names of the ``qsm`` modules (and their parent packages) that ``path`` imports;
    each file is parsed once per process (the rules share most of their modules)."""
    root = package_dir.name
    package = _package_of(path, package_dir)
    names = set()
    for node in _module_level(ast.parse(path.read_text(), filename=str(path))):
        modules: list[str] = []
        if isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the file's package
                if package is None or node.level > len(package):
                    continue
                base = package[: len(package) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            modules = [module, *(f"{module}.{alias.name}" for alias in node.names)]
        elif isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
        for module in modules:
            parts = module.split(".")
            if parts[0] == root:
                names.update(".".join(parts[: k + 1]) for k in range(len(parts)))
    return frozenset(names)


def _module_file(name: str, package_dir: Path) -> Path | None:
    """The source file of a dotted ``qsm`` name: a module, a package's ``__init__.py``, or None
    (a function or class imported from a module)."""
    path = package_dir.joinpath(*name.split(".")[1:])
    for candidate in (path.with_suffix(".py"), path / "__init__.py"):
        if candidate.exists():
            return candidate
    return None


@cache
def module_closure(script: str, package_dir: Path = PACKAGE_DIR) -> tuple[Path, ...]:
    """The ``qsm`` source files that ``script`` reaches through its imports, sorted."""
    seen: set[Path] = set()
    todo = [Path(script)]
    while todo:
        path = todo.pop()
        for name in _qsm_imports(path, package_dir):
            found = _module_file(name, package_dir)
            if found is not None and found not in seen:
                seen.add(found)
                todo.append(found)
    return tuple(sorted(seen))


def source_hash(script: str | Path, package_dir: Path = PACKAGE_DIR) -> str:
    """Short SHA-256 of the ``qsm`` sources that ``script`` depends on (config values reach the
    rules as params of their own, so the schema is not part of it)."""
    digest = hashlib.sha256()
    for path in module_closure(str(script), package_dir):
        digest.update(str(path.relative_to(package_dir)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]

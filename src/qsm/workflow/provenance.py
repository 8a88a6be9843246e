"""Which library sources a workflow script runs, and a hash of them for Snakemake's params.

Snakemake reruns a rule when its script changes, not when a module the script imports does. A
rule that passes ``source_hash(script)`` as a param is rerun when any ``qsm`` module it reaches
through its imports changes, and only then. Absolute and relative imports count, and so does the
``__init__.py`` of every package on the way (Python runs it on import). Imports inside functions
(deferred: they run when the function does) count too, so a module reached only through a
function's import is followed; ``TYPE_CHECKING`` blocks, which never run, are not. An import by a
computed name (``importlib.import_module``) is not seen: the workflow's scripts do not use one,
and ``tests/test_provenance.py`` holds every module a script loads while it runs to its hash.
"""

from __future__ import annotations

import ast
import hashlib
import re
from functools import cache
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parents[1]  # src/qsm
#: An indented import that may reach ``qsm``: inside a block (a function's, or a ``TYPE_CHECKING``
#: block's, which never runs), so the file is parsed whole.
_INDENTED = re.compile(r"^[ \t]+(?:from[ \t]+(?:qsm\b|\.)|import[ \t]+qsm\b)", re.M)
#: A whole import statement at the start of a line: one line, or a parenthesised list.
_TOP_LEVEL = re.compile(
    r"^(?:from[ \t]+\S+[ \t]+import[ \t]+(?:\([^)]*\)|.*)|import[ \t]+.*)", re.M
)


def _package_of(path: Path, package_dir: Path) -> list[str] | None:
    """Dotted package (as parts) that the file ``path`` belongs to, None outside the package."""
    try:
        rel = path.resolve().relative_to(package_dir.parent)
    except ValueError:
        return None
    return list(rel.parts[:-1])


def _imports(tree: ast.Module) -> list[ast.stmt]:
    """Every import statement of the module, those inside functions (deferred, run when the
    function is) included; not those of ``if TYPE_CHECKING:`` blocks (never run)."""
    out: list[ast.stmt] = []
    todo: list[ast.AST] = [tree]
    while todo:
        node = todo.pop()
        if isinstance(node, ast.Import | ast.ImportFrom):
            out.append(node)
        elif isinstance(node, ast.If) and _is_type_checking(node.test):
            todo += node.orelse
        else:
            todo += ast.iter_child_nodes(node)
    return out


def _is_type_checking(test: ast.expr) -> bool:
    """``TYPE_CHECKING`` or ``typing.TYPE_CHECKING``."""
    name = test.attr if isinstance(test, ast.Attribute) else getattr(test, "id", None)
    return name == "TYPE_CHECKING"


def _import_statements(path: Path) -> list[ast.stmt]:
    """The import statements of ``path`` that :func:`_imports` gives: a file whose every ``qsm``
    import starts a line has only those lines parsed (parsing whole files was a tenth of
    Snakemake's start on this workflow)."""
    text = path.read_text()
    if not _INDENTED.search(text):
        try:
            return [node for m in _TOP_LEVEL.finditer(text) for node in ast.parse(m.group()).body]
        except SyntaxError:  # a line of prose that starts like an import
            pass
    return _imports(ast.parse(text, filename=str(path)))


@cache
def _qsm_imports(path: Path, package_dir: Path) -> frozenset[str]:
    """Dotted names of the ``qsm`` modules (and their parent packages) that ``path`` imports;
    each file is parsed once per process (the rules share most of their modules)."""
    root = package_dir.name
    package = _package_of(path, package_dir)
    names = set()
    for node in _import_statements(path):
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

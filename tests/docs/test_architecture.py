"""docs/architecture.md stays true to the code, and imports stay at module tops.

The layers themselves are checked by import-linter (``make lint``, contracts in pyproject.toml).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "linkwork"

#: What a function may import lazily: heavy or optional dependencies that `import linkwork`
#: and `linkwork --help` should not pay for (matplotlib through linkwork.plot, scipy's optimisers
#: and samplers, dask, pandas, pint, rich's progress bars, numba and the engine's compiled
#: kernels, which import it).
LAZY = ("linkwork.plot", "matplotlib", "pandas", "dask", "scipy", "pint", "rich", "numba",
        "linkwork.planar.compiled.")
#: Deprecated names that import their new home when used (also ignored by import-linter):
#: plot.sine.plot_force_ratio evaluates its model; errors.require_* are now in linkwork.checks.
#: And the command modules, which linkwork.cli imports only to run a command: `linkwork --help`
#: would otherwise import the studies, pydantic and the engine (issue 19 item 7: start-up
#: under 0.3 s; 0.51 s with them, measured in docs/performance.md). And ctypes.util in
#: linkwork.heap, which the command line imports at start: it imports shutil, subprocess and
#: tempfile (9 ms) and is needed only where glibc is not among the loaded symbols.
LAZY_EXCEPTIONS = {("linkwork/plot/sine.py", "linkwork.models.sine"),
                   ("linkwork/heap.py", "ctypes.util"),
                   ("linkwork/errors.py", "linkwork.checks"),
                   ("linkwork/errors.py", "linkwork.deprecation"),
                   ("linkwork/cli/__init__.py", "linkwork.cli")}


def _modules() -> list[Path]:
    return sorted(p for p in PACKAGE.rglob("*.py") if "__pycache__" not in p.parts)


def test_every_module_is_described_in_the_architecture_page() -> None:
    """Each module file (other than package faces) is named in docs/architecture.md, so that a
    new module cannot land without its line there."""
    text = (ROOT / "docs" / "architecture.md").read_text()
    missing = [str(p.relative_to(ROOT)) for p in _modules()
               if p.name != "__init__.py" and p.name not in text]
    assert not missing, f"modules missing from docs/architecture.md: {missing}"


def test_imports_inside_functions_are_only_lazy_heavy_dependencies() -> None:
    """Imports live at module tops; inside a function only the LAZY dependencies (not under
    ``if TYPE_CHECKING:``, which is module level)."""
    found = []
    for path in _modules():
        rel = str(path.relative_to(ROOT))

        def walk(node: ast.AST, in_function: bool, rel: str = rel) -> None:
            for child in ast.iter_child_nodes(node):
                inner = in_function or isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef)
                if in_function and isinstance(child, ast.Import | ast.ImportFrom):
                    mod = (child.module or "") if isinstance(child, ast.ImportFrom) \
                        else child.names[0].name
                    if not mod.startswith(LAZY) and (rel, mod) not in LAZY_EXCEPTIONS:
                        found.append(f"{rel}:{child.lineno} imports {mod}")
                walk(child, inner)

        walk(ast.parse(path.read_text()), False)
    assert not found, found

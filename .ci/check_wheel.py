"""Check that a built wheel holds the package and nothing of the book; print its size and contents.

Usage: ``python .ci/check_wheel.py dist/flapping-X.Y.Z-py3-none-any.whl``.

Fails (exit status 1, naming each problem) if a module of ``flapping/`` is missing from the wheel,
if the licence is missing, if the book's helpers (``flapping_book``, or a ``flapping/book``
folder) are in it, or if a module in it imports the book's build stack (Sphinx, docutils,
MyST, Jupyter Book) or the book's helpers: the wheel users install is the package alone.
"""

from __future__ import annotations

import ast
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).parents[1]

REQUIRED = [
    "flapping/__init__.py",
    "flapping/__main__.py",
    "flapping/cli.py",
    "flapping/hover/__init__.py",
    "flapping/studies/__init__.py",
    "flapping/py.typed",
    "flapping/model/__init__.py",
    "flapping/model/_derivatives_generated.py",
    "flapping/periodic/__init__.py",
]

#: Folders of the book's helpers: nothing under them belongs in the wheel.
BOOK_FOLDERS = ("flapping_book/", "flapping/book/")

#: Top-level modules only the book's build uses: no module of the wheel may import them.
BOOK_IMPORTS = frozenset({"flapping_book", "sphinx", "docutils", "myst_nb", "myst_parser",
                          "jupyter_book", "sphinx_exercise", "sphinx_mathjax_offline",
                          "sphinxcontrib", "nbformat", "jupytext"})


def _imported_roots(source: str) -> set[str]:
    """The top-level names of every module ``source`` imports (``flapping.book`` counts as
    ``flapping_book``)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            modules = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            modules = [node.module] + [f"{node.module}.{alias.name}" for alias in node.names]
        else:
            continue
        for module in modules:
            names.add("flapping_book" if module.startswith("flapping.book") else
                      module.split(".")[0])
    return names


def problems(wheel: zipfile.ZipFile, source_root: Path = ROOT) -> list[str]:
    """Everything wrong with ``wheel``: missing modules, book helpers, book-build imports."""
    names = wheel.namelist()
    found = [f"missing from the wheel: {name}" for name in REQUIRED if name not in names]
    if not any(n.endswith(".dist-info/licenses/LICENSE") or n.endswith("/LICENSE")
               for n in names):
        found.append("missing from the wheel: LICENSE")
    source = sorted(p.relative_to(source_root).as_posix()
                    for p in (source_root / "flapping").rglob("*.py"))
    found += [f"missing from the wheel: {name}" for name in source if name not in names]
    found += [f"a book helper in the wheel: {name}" for name in names
              if name.startswith(BOOK_FOLDERS)]
    for name in names:
        if name.endswith(".py"):
            bad = _imported_roots(wheel.read(name).decode("utf-8")) & BOOK_IMPORTS
            found += [f"{name} imports {module} (the book's, not the package's)"
                      for module in sorted(bad)]
    return found


if __name__ == "__main__":
    path = Path(sys.argv[1])
    with zipfile.ZipFile(path) as wheel:
        names = wheel.namelist()
        print(f"{path.name}: {path.stat().st_size / 1024:.0f} KiB, {len(names)} files")
        for name in names:
            print("   ", name)
        found = problems(wheel)
    if found:
        sys.exit("the wheel is not the package alone:\n  " + "\n  ".join(found))

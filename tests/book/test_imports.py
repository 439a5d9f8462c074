"""The chapters import only the public paths the API reference documents.

A reader copies a chapter's imports: each ``from flapping... import ...`` and ``import flapping...``
in a chapter must name a module that book/api.md documents (an ``automodule``), never a
deprecated path of ``flapping._moved.MOVED_MODULES`` (they warn), and only names that module
makes public (its ``__all__``).
"""

from __future__ import annotations

import importlib
import importlib.util
import re
from pathlib import Path

import pytest

from flapping._moved import MOVED_MODULES

BOOK = Path(__file__).resolve().parents[2] / "book"
API = (BOOK / "api.md").read_text(encoding="utf-8")
DOCUMENTED = set(re.findall(r"^\.\. automodule:: ([\w.]+)", API, re.MULTILINE)) | {"flapping"}
FROM_IMPORT = re.compile(r"^[ \t]*from (flapping(?:\.\w+)*) import (\([^)]*\)|[^\n]*)", re.MULTILINE)
IMPORT = re.compile(r"^\s*import (flapping(?:\.\w+)*)", re.MULTILINE)
CHAPTERS = sorted(p.stem for p in BOOK.glob("*.md"))


def imports(text: str) -> list[tuple[str, list[str]]]:
    """(module, names) of every import of the package in a chapter's text."""
    found = []
    for match in FROM_IMPORT.finditer(text):
        names = re.sub(r"#[^\n]*", "", match[2]).strip("()")
        found.append((match[1], [n.split()[0] for n in names.split(",") if n.strip()]))
    return found + [(m[1], []) for m in IMPORT.finditer(text)]


def _documented_elsewhere(module: str, name: str) -> bool:
    """``from module import name``, with ``module`` undocumented: ``name`` is a documented
    submodule, or an object a documented submodule of ``module`` holds."""
    if f"{module}.{name}" in DOCUMENTED:
        return True
    obj = getattr(importlib.import_module(module), name)
    return any(getattr(importlib.import_module(doc), name, None) is obj
               for doc in DOCUMENTED if doc.startswith(module + "."))


def _is_submodule(module: str, name: str) -> bool:
    package = importlib.import_module(module)
    return hasattr(package, "__path__") and importlib.util.find_spec(f"{module}.{name}") is not None


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_chapter_imports_documented_public_paths(chapter):
    problems = []
    for module, names in imports((BOOK / f"{chapter}.md").read_text(encoding="utf-8")):
        if module in MOVED_MODULES:
            problems.append(f"{module} is deprecated: import from {MOVED_MODULES[module]}")
            continue
        if module not in DOCUMENTED:
            # a package itself undocumented, re-exporting names its documented modules define
            problems += [f"{module}.{name}: not documented in book/api.md" for name in names
                         if not _documented_elsewhere(module, name)]
            if not names:
                problems.append(f"{module} is not documented in book/api.md")
            continue
        public = getattr(importlib.import_module(module), "__all__", None)
        problems += [f"{module}.{name} is not public (not in its __all__)" for name in names
                     if public is not None and name not in public
                     and not _is_submodule(module, name)]
    assert not problems, f"{chapter}:\n  " + "\n  ".join(problems)


def test_imports_parses_both_forms():
    text = "from flapping.hover import (find_hover_orbit,\n    HoverProblem)\nimport flapping.atlas\n"
    assert imports(text) == [("flapping.hover", ["find_hover_orbit", "HoverProblem"]),
                             ("flapping.atlas", [])]

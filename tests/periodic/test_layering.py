"""flapping.periodic is the reusable layer: it imports nothing from the insect model, and its
modules use each other's public (or package-internal underscore-module) API only.

(tests/test_package.py checks the layering of every subpackage and the length of functions.)"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import flapping.periodic

PACKAGE = Path(flapping.periodic.__file__).parent
MODULES = sorted(PACKAGE.glob("*.py"))


def imports(path: Path) -> list[tuple[str, list[str]]]:
    """(module, imported names) of every import statement of a file."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found.extend((alias.name, []) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            found.append((node.module or "", [alias.name for alias in node.names]))
    return found


# the shared top-level modules below every layer (flapping.backends lies above this one: it
# takes this layer's default tolerances)
ALLOWED = ("flapping.periodic", "flapping.errors", "flapping._validation", "flapping._numdiff",
           "flapping.results")


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.name)
def test_periodic_imports_nothing_from_the_model(path):
    # `import flapping.model...` or `from flapping import model`: both name the insect layer
    for module, names in imports(path):
        targets = [f"{module}.{n}" for n in names] if names else [module]
        for target in targets:
            if target.startswith("flapping"):
                assert target.startswith(ALLOWED), f"{path.name} imports {target}"


@pytest.mark.parametrize("path", MODULES, ids=lambda p: p.name)
def test_no_private_names_imported_from_public_modules(path):
    # shooting and floquet once imported nine private names of integrate; private *modules*
    # (flapping.periodic._segments, flapping._validation) are the package-internal API
    root = PACKAGE.parent.parent
    for module, names in imports(path):
        if module.startswith("flapping") and not module.rsplit(".", 1)[-1].startswith("_"):
            folder = root.joinpath(*module.split("."))
            private = [n for n in names if n.startswith("_") and not (folder / f"{n}.py").exists()]
            assert not private, f"{path.name} imports {private} from {module}"


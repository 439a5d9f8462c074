"""The layout of flapping.model: each module imports only the modules before it (package docstring)."""

import ast
from pathlib import Path

import pytest

import flapping.model

#: The order of the package docstring: a module may import only the ones before it.
ORDER = ["kinematics", "morphology", "presets", "insect_file", "aerodynamics", "derivation",
         "_derivatives_generated", "derivatives", "sixdof_derivation", "inertia_derivation",
         "_inertia_generated", "inertia", "dynamics", "_sixdof_generated",
         "_sixdof_jacobian_generated", "sixdof_linear_derivation", "_sixdof_linear_generated",
         "sixdof"]
PACKAGE = Path(flapping.model.__file__).parent


def model_imports(module: str) -> set[str]:
    """Names X of every ``flapping.model.X`` the module imports (at any depth, lazily or not)."""
    tree = ast.parse((PACKAGE / f"{module}.py").read_text())
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module == "flapping.model":
                found.update(alias.name for alias in node.names)
            elif node.module.startswith("flapping.model."):
                found.add(node.module.split(".")[2])
        elif isinstance(node, ast.Import):
            found.update(a.name.split(".")[2] for a in node.names
                         if a.name.startswith("flapping.model."))
    return found


def test_every_module_is_in_the_documented_order():
    assert sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__") == sorted(ORDER)


@pytest.mark.parametrize("module", ORDER)
def test_modules_import_only_earlier_layers(module):
    # derivation.evaluate used to import flapping.model.derivatives (a later module) lazily.
    earlier = set(ORDER[:ORDER.index(module)])
    assert model_imports(module) <= earlier

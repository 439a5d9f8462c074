"""The package's shape: layers import only the layers below them; functions fit on a screen.

These are the redesign's promises to the next maintainer (issue 7), checked on the source text so
that a violation fails here rather than in review.
"""

from __future__ import annotations

import ast
import fnmatch
import importlib
import importlib.util
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

import flapping

PACKAGE = Path(flapping.__file__).parent
GENERATED = {"_derivatives_generated.py", "_generated.py", "_sixdof_linear_generated.py",
             "_sixdof_jacobian_generated.py"}  # written by SymPy, not by hand
MAX_CODE_LINES = 80  # per function, docstring, comments and blank lines aside


def _modules(subpackage: str = "") -> list[Path]:
    root = PACKAGE / subpackage if subpackage else PACKAGE
    return sorted(p for p in root.rglob("*.py") if p.name not in GENERATED)


def _runtime_nodes(tree: ast.AST):
    """Every node of ``tree`` but those under ``if TYPE_CHECKING:`` (annotations only: no import
    happens at run time)."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            yield from (n for child in node.orelse for n in [child, *_runtime_nodes(child)])
            continue
        yield node
        yield from _runtime_nodes(node)


def _imported_modules(path: Path) -> set[str]:
    names: set[str] = set()
    for node in _runtime_nodes(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module != "flapping":  # `from flapping import x` imports flapping.x only
                names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


# The shared top-level modules every layer may import: errors, validation, numerical helpers and
# what a solve returns (results). How a solve runs (backends) takes the periodic layer's defaults
# and ranges: it lies above that layer, below the ones that run solves.
SHARED = ("flapping.errors", "flapping._validation", "flapping._numdiff", "flapping.results")
BACKENDS = ("flapping.backends",)

# Which flapping modules each layer may import (besides its own subpackage).
ALLOWED = {
    "periodic": ("flapping.periodic", "flapping.errors", "flapping._validation", "flapping._numdiff"),
    "model": ("flapping.model", "flapping.errors", "flapping._validation", "flapping._numdiff"),
    "fast": ("flapping.fast", "flapping.model", "flapping.periodic", "flapping.errors",
             "flapping._validation", "flapping._numdiff", *BACKENDS),
    "hover": ("flapping.hover", "flapping.fast", "flapping.model", "flapping.periodic",
              "flapping.errors", "flapping._validation", "flapping._numdiff", *BACKENDS),
    # flapping.peers: a study that joins two models (ours and FWUAV's, flapping.studies.fwuav)
    # sits above both.
    "studies": ("flapping.studies", "flapping.hover", "flapping.fast", "flapping.model",
                "flapping.peers", "flapping.periodic", "flapping.errors", "flapping._validation",
                "flapping._numdiff", *BACKENDS),
    "peers": ("flapping.peers", "flapping.periodic", "flapping.errors", "flapping._validation",
              "flapping._numdiff", *BACKENDS),
}

#: What each shared top-level module may import: the layering holds for them too (issue 35: the
#: exemption hid a results -> periodic.floquet -> errors -> results circle). The namespace, the
#: command line, ``__main__`` and the forwarding modules sit on top and may import anything.
TOP_ALLOWED = {
    "errors": (),
    "_numdiff": (),
    "_validation": ("flapping.errors",),
    "results": ("flapping.errors",),
    "backends": ("flapping._validation", "flapping.errors", "flapping.periodic",
                 "flapping.results"),
}

#: The modules at the top of the package: the namespace, the command line and the shared
#: helpers every layer may use; everything else lives in a layer's subpackage.
TOP_LEVEL = {"__init__", "__main__", "cli", "errors", "_validation", "_numdiff", "backends",
             "results"}
#: The old module paths, each a forwarding module (flapping/_moved.py holds what they share).
FORWARDING = {"_moved"} | {old.rpartition(".")[2] for old in flapping.MOVED_MODULES}


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_a_layer_imports_only_what_lies_below_it(layer):
    allowed = ALLOWED[layer] + SHARED
    offending = []
    for path in _modules(layer):
        for name in _imported_modules(path):
            if name.startswith("flapping") and not name.startswith(allowed):
                offending.append(f"{path.relative_to(PACKAGE)} imports {name}")
    assert not offending, "\n".join(offending)


@pytest.mark.parametrize("module", sorted(TOP_ALLOWED))
def test_a_shared_module_imports_only_what_lies_below_it(module):
    path = PACKAGE / f"{module}.py"
    offending = [name for name in _imported_modules(path)
                 if name.startswith("flapping") and name != f"flapping.{module}"
                 and not name.startswith(TOP_ALLOWED[module])]
    assert not offending, offending


#: A circle another change removes (issue 35, item 5: the compile policy of flapping.fast).
KNOWN_CIRCLES: list[set[str]] = [{"flapping.fast._background", "flapping.fast.kernel"}]


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _import_graph() -> dict[str, set[str]]:
    """Module -> the package's modules it imports at run time (functions' imports too)."""
    modules = {_module_name(path): path for path in _modules()}
    graph = {}
    for name, path in modules.items():
        targets = set()
        for imported in _imported_modules(path):
            while imported and imported not in modules:  # `from a.b import c`: c or a.b
                imported = imported.rpartition(".")[0]
            if imported and imported != name:
                targets.add(imported)
        graph[name] = targets
    return graph


def _circles(graph: dict[str, set[str]]) -> list[set[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[set[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = set()
            while True:
                w = stack.pop()
                component.add(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(component)

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def test_no_module_imports_itself_through_others():
    # Reproducers (issue 35): results -> periodic.floquet -> errors -> results, and
    # hover.orbit <-> hover.sixdof. A package's __init__ importing its own modules is no circle
    # (the modules are below it): edges into a package's __init__ from inside it are left out.
    graph = _import_graph()
    for name, targets in graph.items():
        graph[name] = {t for t in targets if not name.startswith(f"{t}.")}
    circles = [c for c in _circles(graph) if c not in KNOWN_CIRCLES]
    assert not circles, circles


def test_the_circle_finder_finds_a_circle():
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [{"a", "b", "c"}]


def test_the_book_helpers_are_not_in_the_package_nor_imported_by_it():
    # They are a package of their own beside the book (book/_ext/flapping_book).
    assert not (PACKAGE / "book").exists()
    offending = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in _modules()
        for name in _imported_modules(path)
        if name.startswith(("flapping_book", "flapping.book"))
    ]
    assert not offending, "\n".join(offending)


def _wheel_check():
    path = PACKAGE.parent / ".ci" / "check_wheel.py"
    spec = importlib.util.spec_from_file_location("check_wheel", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_wheel_check_refuses_the_book(tmp_path):
    check = _wheel_check()
    wheel = tmp_path / "flapping-0-py3-none-any.whl"
    with zipfile.ZipFile(wheel, "w") as zf:
        for path in PACKAGE.rglob("*.py"):
            zf.write(path, path.relative_to(PACKAGE.parent).as_posix())
        zf.write(PACKAGE / "py.typed", "flapping/py.typed")
        zf.writestr("flapping-0.dist-info/licenses/LICENSE", "MIT License")
    with zipfile.ZipFile(wheel) as zf:
        assert check.problems(zf, PACKAGE.parent) == []  # the package alone passes
    with zipfile.ZipFile(wheel, "a") as zf:
        zf.writestr("flapping_book/plotting.py", "import numpy\n")
        zf.writestr("flapping/_ext.py", "from sphinx.util import logging\nimport flapping.book\n")
    with zipfile.ZipFile(wheel) as zf:
        found = check.problems(zf, PACKAGE.parent)
    assert any("flapping_book/plotting.py" in p for p in found)
    assert any("imports sphinx" in p for p in found)
    assert any("imports flapping_book" in p for p in found)


def test_the_wheel_finds_only_the_package():
    pyproject = tomllib.loads((PACKAGE.parent / "pyproject.toml").read_text(encoding="utf-8"))
    include = pyproject["tool"]["setuptools"]["packages"]["find"]["include"]
    assert include == ["flapping", "flapping.*"]
    assert not any(fnmatch.fnmatchcase("flapping_book", pattern) for pattern in include)


def _code_lines(lines: list[str], node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    skip: set[int] = set()
    first = node.body[0]
    if ast.get_docstring(node, clean=False) is not None and isinstance(first, ast.Expr):
        skip.update(range(first.lineno, (first.end_lineno or first.lineno) + 1))
    end = node.end_lineno or node.lineno
    return sum(
        1 for i in range(node.lineno, end + 1)
        if i not in skip and lines[i - 1].strip() and not lines[i - 1].strip().startswith("#")
    )


def test_no_function_is_longer_than_a_screen():
    long = []
    for path in _modules():
        source = path.read_text(encoding="utf-8")
        lines = source.splitlines()
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = _code_lines(lines, node)
                if n > MAX_CODE_LINES:
                    long.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name}: {n} lines")
    assert not long, "\n".join(long)


def test_the_top_level_namespace_offers_the_main_entry_points():
    for name in ("Insect", "hawkmoth", "find_hover_orbit", "hover_stability",
                 "find_periodic_orbit", "monodromy", "ConvergenceError"):
        assert name in flapping.__all__ and hasattr(flapping, name)
    assert not hasattr(flapping, "plotting")  # book helpers stay out of the namespace
    assert not hasattr(flapping, "book")


def test_the_top_of_the_package_holds_only_a_handful_of_modules():
    assert {p.stem for p in PACKAGE.glob("*.py")} == TOP_LEVEL | FORWARDING


def test_a_study_imports_no_other_study():
    # Private modules (flapping/studies/_path.py, the warm-start helper) are the layer's shared
    # tools, not studies: every study may use them; so is the batch tool, the sweep.
    studies = {p.stem for p in (PACKAGE / "studies").glob("*.py")
               if not p.stem.startswith("_") and p.stem != "sweep"}
    for path in (PACKAGE / "studies").glob("*.py"):
        others = {f"flapping.studies.{s}" for s in studies - {path.stem}}
        assert not {n for n in _imported_modules(path) if n.startswith(tuple(others))}, path


@pytest.mark.parametrize("old", sorted(flapping.MOVED_MODULES))
def test_an_old_module_path_imports_and_warns(old, monkeypatch):
    new = importlib.import_module(flapping.MOVED_MODULES[old])
    monkeypatch.delitem(sys.modules, old, raising=False)  # so the import runs the module again
    with pytest.warns(DeprecationWarning, match=re.escape(new.__name__)) as caught:
        __import__(old)  # as the statement `import flapping.stability` does
    module = sys.modules[old]
    assert module is not new and caught[0].filename == __file__  # the warning names our line
    name = new.__all__[0]
    with pytest.warns(DeprecationWarning, match=rf"import {name} from {re.escape(new.__name__)}"):
        assert getattr(module, name) is getattr(new, name)  # the object itself
    assert set(new.__all__) <= set(dir(module))


@pytest.mark.parametrize("old", sorted(flapping.MOVED_MODULES))
def test_an_old_module_is_only_a_forwarder(old):
    # Nothing is defined twice: the old path holds no code of its own.
    tree = ast.parse((PACKAGE / f"{old.rpartition('.')[2]}.py").read_text(encoding="utf-8"))
    defined = {node.name for node in tree.body if isinstance(node, ast.FunctionDef | ast.ClassDef)}
    assigned = [node for node in tree.body if isinstance(node, ast.Assign | ast.AnnAssign)]
    assert defined == {"__getattr__", "__dir__"} and not assigned


def test_the_old_import_forms_keep_working_and_warn(monkeypatch):
    from flapping.hover.stability import hover_stability as new

    with pytest.warns(DeprecationWarning, match="flapping.hover.stability"):
        from flapping.stability import hover_stability
    monkeypatch.delitem(sys.modules, "flapping.control", raising=False)  # not imported yet
    monkeypatch.delattr(flapping, "control", raising=False)
    with pytest.warns(DeprecationWarning, match="flapping.studies.control"):
        from flapping import control
    with pytest.warns(DeprecationWarning, match="flapping.studies.control"):
        passive_sweep = control.passive_sweep
    from flapping.studies.control import passive_sweep as new_sweep

    assert hover_stability is new and passive_sweep is new_sweep
    with pytest.raises(AttributeError), pytest.warns(DeprecationWarning):
        control.no_such_name  # noqa: B018


def test_importing_an_old_path_warns_in_a_fresh_interpreter():
    # Fresh, so the warning at import cannot have been given (and swallowed) earlier; as an error
    # it fails the import, which is what a user running with -W error sees.
    code = "import flapping.hover_branch"
    run = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code],
                         capture_output=True, text=True)
    assert run.returncode != 0 and "flapping.hover.branch" in run.stderr


def test_the_names_users_import_today_stay_importable():
    from flapping.hover import find_hover_orbit
    from flapping.hover.stability import hover_stability
    from flapping.model.morphology import hawkmoth
    from flapping.model.presets import preset
    from flapping.periodic.continuation import continue_orbit
    from flapping.periodic.floquet import monodromy
    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.studies.sweep import sweep_hover

    assert callable(preset) and callable(continue_orbit)
    assert flapping.find_periodic_orbit is find_periodic_orbit and flapping.monodromy is monodromy
    assert flapping.find_hover_orbit is find_hover_orbit and flapping.hawkmoth is hawkmoth
    assert flapping.hover_stability is hover_stability and flapping.sweep_hover is sweep_hover
    for name in flapping.__all__:
        assert getattr(flapping, name) is not None and name in dir(flapping)
    namespace: dict = {}
    exec("from flapping import *", namespace)
    assert set(flapping.__all__) <= set(namespace)


def _modules_after(code: str) -> set[str]:
    """The names in ``sys.modules`` after running ``code`` in a fresh interpreter."""
    code += "\nimport sys; print(' '.join(sys.modules))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(run.stdout.split())


#: What ``import flapping`` alone must not load: the solvers, the compiler, the optional extras
#: and the peers' models (they load when a name needs them).
NOT_AT_IMPORT = ("numba", "matplotlib", "pandas", "scipy.integrate", "scipy.optimize",
                 "flapping.peers", "flapping.hover", "flapping_book")


def test_importing_the_package_loads_no_solver():
    loaded = _modules_after("import flapping")
    assert "flapping" in loaded
    assert not [name for name in NOT_AT_IMPORT if name in loaded]


def test_an_entry_point_loads_its_layer_when_first_used():
    # The check above can fail: the same probe sees the solvers once a name needs them.
    loaded = _modules_after("import flapping; flapping.find_periodic_orbit")
    assert {"flapping.periodic.shooting", "scipy.integrate"} <= loaded
    assert "flapping.hover" not in loaded

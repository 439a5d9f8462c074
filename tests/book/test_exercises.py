"""Every exercise can be copied and run: its solution needs nothing that only a hidden cell makes.

A reader who works an exercise copies the code the page shows: the code cells that are not
hidden (tagged ``remove-cell`` or ``remove-input``: the build runs them, the reader never sees
their code) and the exercise's solution. A solution that uses a variable only a hidden cell
defines fails for the reader with a NameError, although the book builds.

The check is static, so no chapter runs a third time (nbval and the book build run every cell,
the solutions included): the page's code cells are read in order with :mod:`ast` and
:mod:`symtable`, and every module-level name a visible cell reads (directly, or from inside a
function, lambda, class or comprehension it defines) must be bound by an earlier visible cell
or by itself, or be a builtin. A name that is not, and that a hidden cell binds, fails the test.
(A name bound nowhere is a NameError in the chapter itself, which nbval reports.)

It also checks the labels a reader follows: no two exercises share one, each chapter has its own
prefix (``ex-primer-``), a label that names a species belongs to a question about that species,
and every solution names an exercise of its page.
"""

from __future__ import annotations

import ast
import builtins
import re
import symtable
import warnings
from dataclasses import dataclass
from pathlib import Path

import jupytext
import nbformat
import pytest
from IPython.core.inputtransformer2 import TransformerManager

ROOT = Path(__file__).resolve().parents[2]
BOOK = ROOT / "book"
#: Tags whose code a reader never sees.
HIDDEN = {"remove-cell", "remove-input"}
EXERCISE = re.compile(r"^```\{exercise\}[^\n]*\n:label: (?P<label>[\w-]+)", re.MULTILINE)
SOLUTION = re.compile(r"^```\{solution(?:-start)?\} (?P<label>[\w-]+)", re.MULTILINE)
#: Names a Jupyter kernel provides besides Python's builtins.
KERNEL_NAMES = {"display", "get_ipython", "In", "Out", "exit", "quit", "_", "__", "___"}
BUILTINS = set(dir(builtins)) | KERNEL_NAMES


def _chapters_with_exercises() -> list[str]:
    return sorted(p.stem for p in BOOK.glob("*.md") if EXERCISE.search(p.read_text("utf-8")))


CHAPTERS = _chapters_with_exercises()


@dataclass(frozen=True)
class Cell:
    """A code cell of a chapter: its source, whether a reader sees it, whether it solves."""

    source: str
    visible: bool
    solution: bool


def chapter_cells(path: Path) -> list[Cell]:
    """The chapter's code cells in page order, each marked visible or hidden and solution or
    not (between ``{solution-start}`` and ``{solution-end}``)."""
    cells, in_solution = [], False
    for cell in jupytext.read(path).cells:
        if cell.cell_type == "markdown":
            if "{solution-start}" in cell.source:
                in_solution = True
            if "{solution-end}" in cell.source:
                in_solution = False
        elif cell.cell_type == "code":
            visible = not HIDDEN & set(cell.metadata.get("tags", []))
            cells.append(Cell(cell.source, visible, in_solution))
    return cells


def visible_notebook(path: Path) -> tuple[nbformat.NotebookNode, int]:
    """The chapter's code cells a reader sees, in page order, as a notebook; and how many of them
    are solution cells."""
    cells = [c for c in chapter_cells(path) if c.visible]
    notebook = nbformat.v4.new_notebook(
        cells=[nbformat.v4.new_code_cell(c.source) for c in cells],
        metadata=jupytext.read(path).metadata)
    return notebook, sum(c.solution for c in cells)


#: Magics whose argument is Python code run in the reader's namespace.
CODE_MAGICS = {"time", "timeit", "prun", "capture"}


def _statements(source: str) -> list[ast.stmt]:
    """The cell's statements as the kernel runs them: IPython syntax (%magic, !shell) translated,
    and the code a ``%time``-like magic runs parsed in its place."""
    # The chapters' own syntax warnings (a LaTeX "\\P" in a plain string) are nbval's to show.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", (DeprecationWarning, SyntaxWarning))
        body = ast.parse(TransformerManager().transform_cell(source)).body
    statements: list[ast.stmt] = []
    for statement in body:
        code = _magic_code(statement)
        statements += _statements(code) if code is not None else [statement]
    return statements


def _magic_code(statement: ast.stmt) -> str | None:
    # get_ipython().run_line_magic('time', 'code') or .run_cell_magic('time', '', 'code')
    call = statement.value if isinstance(statement, (ast.Expr, ast.Assign)) else None
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
            and call.func.attr in ("run_line_magic", "run_cell_magic")
            and all(isinstance(a, ast.Constant) for a in call.args)
            and call.args and call.args[0].value in CODE_MAGICS):
        return None
    return call.args[-1].value


def _scope_names(table: symtable.SymbolTable) -> tuple[set[str], set[str]]:
    """(read, bound): the module-level names a piece of code reads and binds, nested scopes
    included (a function body reads a global when it runs)."""
    read, bound = set(), set()
    for symbol in table.get_symbols():
        name = symbol.get_name()
        top = table.get_type() == "module"
        if symbol.is_referenced() and (top or symbol.is_global()):
            read.add(name)
        if (top and (symbol.is_assigned() or symbol.is_imported() or symbol.is_namespace())
                or symbol.is_declared_global() and symbol.is_assigned()):
            bound.add(name)
    for child in table.get_children():
        child_read, child_bound = _scope_names(child)
        read |= child_read
        bound |= child_bound
    return read, bound


def statement_names(statement: ast.stmt) -> tuple[set[str], set[str]]:
    """(needed, bound): the module-level names a statement needs bound before it runs, and those
    it binds. A simple statement (``x = f(x)``, ``x += 1``) reads before it binds, so everything
    it reads is needed; a compound one (``for i in ...:``, ``def``, ``with ... as``) may bind a
    name before reading it, so only what it reads and never binds is."""
    source = ast.unparse(ast.Module(body=[statement], type_ignores=[]))
    read, bound = _scope_names(symtable.symtable(source, "<cell>", "exec"))
    # symtable counts `x += 1` as a binding only; it reads x first.
    if isinstance(statement, ast.AugAssign) and isinstance(statement.target, ast.Name):
        read.add(statement.target.id)
    compound = isinstance(statement, (ast.For, ast.AsyncFor, ast.While, ast.If, ast.With,
                                      ast.AsyncWith, ast.Try, ast.FunctionDef,
                                      ast.AsyncFunctionDef, ast.ClassDef, ast.Match))
    return (read - bound if compound else read), bound


def names_from_hidden_cells(cells: list[Cell]) -> list[tuple[int, str]]:
    """Each (visible cell's index among the visible cells, name) where a visible cell needs a
    name that no earlier visible cell binds, that is no builtin, and that a hidden cell binds."""
    hidden = set()
    for cell in cells:
        if not cell.visible:
            for statement in _statements(cell.source):
                hidden |= statement_names(statement)[1]
    defined, found = set(BUILTINS), []
    for index, cell in enumerate(c for c in cells if c.visible):
        for statement in _statements(cell.source):
            needed, bound = statement_names(statement)
            found += [(index, name) for name in sorted(needed - defined)
                      if name in hidden and (index, name) not in found]
            defined |= bound
    return found


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_exercises_need_nothing_from_hidden_cells(chapter):
    cells = chapter_cells(BOOK / f"{chapter}.md")
    assert any(c.visible and c.solution for c in cells), (
        f"{chapter}: no visible solution code (every exercise here has some)")
    found = names_from_hidden_cells(cells)
    assert not found, (
        f"{chapter}: the visible cells and solutions read names only a hidden cell defines "
        f"(visible cell index, name): {found}")


def test_exercise_labels_are_unique_match_their_question_and_are_solved_on_their_page():
    species = ("hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly", "monarch")
    seen: dict[str, str] = {}
    prefixes: dict[str, str] = {}
    problems = []
    for chapter in CHAPTERS:
        text = (BOOK / f"{chapter}.md").read_text("utf-8")
        labels = [m["label"] for m in EXERCISE.finditer(text)]
        for match in EXERCISE.finditer(text):
            label = match["label"]
            if label in seen:
                problems.append(f"{label} ({chapter}) repeats the label of {seen[label]}")
            seen[label] = chapter
            # One prefix per chapter (ex-sm- was both stability_map's and second_model's).
            prefix = label.split("-")[1]
            if prefixes.setdefault(prefix, chapter) != chapter:
                problems.append(f"{label} ({chapter}) uses {prefixes[prefix]}'s prefix ex-{prefix}-")
            # A label naming a species asks about that species (ex-sm-monarch was the bumblebee).
            question = text[match.end():text.index("```", match.end())].lower()
            for name in species:
                if name.replace("_", "-") in label and name.replace("_", " ") not in question:
                    problems.append(f"{label} ({chapter}) names the {name}; its question does not")
        for match in SOLUTION.finditer(text):
            if match["label"] not in labels:
                problems.append(f"{chapter}: a solution to {match['label']}, no such exercise here")
    assert not problems, "\n".join(problems)


PAGE_HEAD = ("---\njupytext:\n  text_representation:\n    extension: .md\n    format_name: myst\n"
             "kernelspec:\n  display_name: Python 3\n  language: python\n  name: python3\n---\n\n")


def _page(tmp_path, *blocks: str) -> Path:
    page = tmp_path / "page.md"
    page.write_text(PAGE_HEAD + "\n\n".join(blocks) + "\n", encoding="utf-8")
    return page


def _code(source: str, hidden: bool = False) -> str:
    tags = ":tags: [remove-cell]\n\n" if hidden else ""
    return f"```{{code-cell}} ipython3\n{tags}{source}\n```"


SOLVED = ("```{exercise}\n:label: ex-a\n\nAsk.\n```", "```{solution-start} ex-a\n```")
END = "```{solution-end}\n```"


def test_visible_notebook_drops_hidden_cells_and_counts_solutions(tmp_path):
    page = _page(tmp_path, _code("x = 1"), _code("hidden = 2", hidden=True), *SOLVED,
                 _code("print(x)"), END)
    notebook, n_solution = visible_notebook(page)
    assert [c.source for c in notebook.cells] == ["x = 1", "print(x)"]
    assert n_solution == 1


@pytest.mark.parametrize("solution", [
    "print(hidden)",                                  # read directly
    "hidden += 1",                                    # read by an augmented assignment
    "hidden = hidden + 1",                            # read before it is bound
    "def f(t):\n    return t * hidden\n\nf(2)",       # read from a function body
    "values = [hidden * i for i in range(3)]",        # from a comprehension
    "for i in range(2):\n    print(i, hidden)",       # from a loop body
    "%time y = hidden",                               # through an IPython magic
    "%%time\nz = 1\nprint(z + hidden)",                # through a cell magic
])
def test_a_solution_that_reads_a_hidden_variable_fails(tmp_path, solution):
    page = _page(tmp_path, _code("import math\nx = 1"), _code("hidden = 2", hidden=True),
                 *SOLVED, _code(solution), END)
    assert [name for _, name in names_from_hidden_cells(chapter_cells(page))] == ["hidden"]


@pytest.mark.parametrize("solution", [
    "hidden = 3\nprint(hidden, x, math.pi, len([x]))",   # bound by the visible cells first
    "for hidden in range(2):\n    print(hidden)",        # bound by the loop it is read in
    "def f(hidden):\n    return hidden\n\nf(x)",          # a parameter, not the global
    "values = [hidden for hidden in range(3)]",          # the comprehension's own variable
    "import numpy as hidden\nhidden.pi",                 # bound by an import
    "%time y = x",
])
def test_a_solution_that_binds_its_own_names_passes(tmp_path, solution):
    page = _page(tmp_path, _code("import math\nx = 1"), _code("hidden = 2", hidden=True),
                 *SOLVED, _code(solution), END)
    assert names_from_hidden_cells(chapter_cells(page)) == []


def test_a_name_a_hidden_cell_binds_before_the_visible_one_does_fails(tmp_path):
    # The chapter runs (the hidden cell came first); a reader's copy does not.
    page = _page(tmp_path, _code("orbit = 1", hidden=True), _code("print(orbit)"),
                 _code("orbit = 2"), *SOLVED, _code("print(orbit)"), END)
    assert names_from_hidden_cells(chapter_cells(page)) == [(0, "orbit")]

"""Every exercise can be copied and run: its solution runs in a fresh kernel from what the page shows.

A reader who works an exercise copies the code the page shows: the code cells that are not
hidden (tagged ``remove-cell`` or ``remove-input``: the build runs them, the reader never sees
their code) and the exercise's solution. For each chapter with exercises this test builds a
notebook of exactly those cells, in page order, and runs it in a fresh Jupyter kernel started in
book/ (as the build does). A solution that uses a variable only a hidden cell defines fails here
with its NameError, although the book builds.

It also checks the labels a reader follows: no two exercises share one, each chapter has its own
prefix (``ex-primer-``), a label that names a species belongs to a question about that species,
and every solution names an exercise of its page.

Each chapter is one test; chapters whose visible cells take more than ~20 s are marked ``slow``.
"""

from __future__ import annotations

import re
from pathlib import Path

import jupytext
import nbformat
import pytest

ROOT = Path(__file__).resolve().parents[2]
BOOK = ROOT / "book"
#: Tags whose code a reader never sees.
HIDDEN = {"remove-cell", "remove-input"}
#: Chapters whose visible cells run for more than ~20 s on two busy cores (measured 2026-12-03:
#: control 137 s, continuation 82 s, stability_map 39 s, atlas 24 s; the others 3 to 17 s).
SLOW = {"control", "continuation", "stability_map", "atlas"}
EXERCISE = re.compile(r"^```\{exercise\}[^\n]*\n:label: (?P<label>[\w-]+)", re.MULTILINE)
SOLUTION = re.compile(r"^```\{solution(?:-start)?\} (?P<label>[\w-]+)", re.MULTILINE)


def _chapters_with_exercises() -> list[str]:
    return sorted(p.stem for p in BOOK.glob("*.md") if EXERCISE.search(p.read_text("utf-8")))


CHAPTERS = _chapters_with_exercises()


def visible_notebook(path: Path) -> tuple[nbformat.NotebookNode, int]:
    """The chapter's code cells a reader sees, in page order, as a notebook; and how many of them
    are solution cells (between ``{solution-start}`` and ``{solution-end}``)."""
    notebook = jupytext.read(path)
    cells, in_solution, n_solution = [], False, 0
    for cell in notebook.cells:
        if cell.cell_type == "markdown":
            if "{solution-start}" in cell.source:
                in_solution = True
            if "{solution-end}" in cell.source:
                in_solution = False
            continue
        if cell.cell_type != "code" or HIDDEN & set(cell.metadata.get("tags", [])):
            continue
        cells.append(nbformat.v4.new_code_cell(cell.source))
        n_solution += in_solution
    visible = nbformat.v4.new_notebook(cells=cells, metadata=notebook.metadata)
    return visible, n_solution


def _params():
    return [pytest.param(c, marks=[pytest.mark.slow] if c in SLOW else []) for c in CHAPTERS]


@pytest.mark.parametrize("chapter", _params())
def test_exercises_run_from_the_visible_cells(chapter):
    nbclient = pytest.importorskip("nbclient")
    notebook, n_solution = visible_notebook(BOOK / f"{chapter}.md")
    assert n_solution > 0, f"{chapter}: no visible solution code (every exercise here has some)"
    client = nbclient.NotebookClient(notebook, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(BOOK)}})
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as exc:
        pytest.fail(f"{chapter}: the visible cells and solutions do not run on their own "
                    f"(a hidden cell defines something they use?):\n{exc}"[:4000])


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


def test_visible_notebook_drops_hidden_cells_and_counts_solutions(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "---\njupytext:\n  text_representation:\n    extension: .md\n    format_name: myst\n"
        "kernelspec:\n  display_name: Python 3\n  language: python\n  name: python3\n---\n\n"
        "```{code-cell} ipython3\nx = 1\n```\n\n"
        "```{code-cell} ipython3\n:tags: [remove-cell]\n\nhidden = 2\n```\n\n"
        "```{exercise}\n:label: ex-a\n\nAsk.\n```\n\n```{solution-start} ex-a\n```\n\n"
        "```{code-cell} ipython3\nprint(x)\n```\n\n```{solution-end}\n```\n", encoding="utf-8")
    notebook, n_solution = visible_notebook(page)
    assert [c.source for c in notebook.cells] == ["x = 1", "print(x)"]
    assert n_solution == 1

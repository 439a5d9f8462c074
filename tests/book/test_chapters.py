"""The book's reader's path, read from the chapter sources (issue 13).

Every chapter a student reads in order (the main line and "Beyond the paper") opens with prose
saying what it establishes, ends with a summary, further reading and exercises that each have a
solution; every Greek symbol used in the book's mathematics has its entry on the notation page;
and the chapters that follow the paper stay about half of their length before the forensic
detail moved to the appendices.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from flapping_book.provenance import chapter_statistics

BOOK = Path(__file__).resolve().parents[2] / "book"
TOC = yaml.safe_load((BOOK / "_toc.yml").read_text(encoding="utf-8"))
# Parts whose chapters are read in order and teach: each follows the reader's path.
TAUGHT_PARTS = ("The model", "Hover and its stability", "Beyond the paper")

# The seven chapters that follow the paper, and their prose before issue 13 moved the forensics
# to the appendices (commit 463de7a, counted with chapter_statistics): 14,415 words.
PAPER_CHAPTERS = ("intro", "aerodynamic_model", "stability_derivatives", "shooting_validation",
                  "hover_orbit", "floquet_multipliers", "hover_stability")
PAPER_CHAPTERS_WORDS_BEFORE = 14_415
MAIN_LINE_SHARE = 0.55  # "about half" of the words before, exercises and summaries included

GREEK = frozenset({
    "alpha", "beta", "gamma", "delta", "epsilon", "varepsilon", "zeta", "eta", "theta",
    "vartheta", "iota", "kappa", "lambda", "mu", "nu", "xi", "pi", "rho", "sigma", "tau",
    "upsilon", "phi", "varphi", "chi", "psi", "omega", "Gamma", "Delta", "Theta", "Lambda", "Xi",
    "Pi", "Sigma", "Upsilon", "Phi", "Psi", "Omega",
})
_MATH = re.compile(r"\$\$.*?\$\$|\$[^$\n]+\$", re.DOTALL)
_MACRO = re.compile(r"\\\\?([A-Za-z]+)")  # \\alpha inside Python strings of code cells too


def _taught_chapters() -> list[str]:
    return [chapter["file"] for part in TOC["parts"] if part["caption"] in TAUGHT_PARTS
            for chapter in part["chapters"]]


def _text(name: str) -> str:
    return (BOOK / f"{name}.md").read_text(encoding="utf-8")


def _greek(text: str) -> set[str]:
    return {name for math in _MATH.findall(text) for name in _MACRO.findall(math)
            if name in GREEK}


def test_the_taught_parts_are_in_the_table_of_contents():
    captions = [part["caption"] for part in TOC["parts"]]
    assert all(part in captions for part in TAUGHT_PARTS), captions
    assert len(_taught_chapters()) >= 10


@pytest.mark.parametrize("name", _taught_chapters())
def test_chapter_opens_with_prose_before_any_code(name):
    body = _text(name).split("\n# ", 1)[1]  # after the title
    first_block = next(block for block in body.split("\n\n")[1:] if block.strip())
    assert not first_block.lstrip().startswith(("```", ":::", "#")), \
        f"{name}: the chapter must open with a paragraph saying what it establishes"
    assert len(first_block.split()) >= 30, f"{name}: the opening paragraph is too short"


@pytest.mark.parametrize("name", _taught_chapters())
def test_chapter_ends_with_summary_further_reading_and_exercises(name):
    text = _text(name)
    headings = re.findall(r"^## (.+)$", text, flags=re.MULTILINE)
    assert len(headings) >= 2 and headings[-2].startswith("Summary") \
        and headings[-1] == "Exercises", f"{name}: last sections are {headings[-2:]}"
    summary = text.split("\n## Summary", 1)[1].split("\n## Exercises\n", 1)[0]
    assert "**Further reading.**" in summary and "{cite" in summary, \
        f"{name}: the summary has no further reading with citations"


@pytest.mark.parametrize("name", _taught_chapters())
def test_every_exercise_has_a_solution(name):
    text = _text(name)
    exercises = re.findall(r"```\{exercise(?:-start)?\}[^\n]*\n:label: ([\w-]+)", text)
    solved = set(re.findall(r"```\{solution(?:-start)?\} ([\w-]+)", text))
    assert len(exercises) >= 2, f"{name}: {len(exercises)} exercise(s), at least 2 wanted"
    assert not set(exercises) - solved, f"{name}: no solution for {set(exercises) - solved}"
    hidden = re.findall(r"```\{solution(?:-start)?\} [\w-]+\n:class: dropdown", text)
    assert len(hidden) == len(solved), f"{name}: every solution is hidden in a dropdown"


def test_every_greek_symbol_of_the_book_is_on_the_notation_page():
    notation = _greek(_text("notation"))
    missing = {}
    for path in sorted(BOOK.glob("*.md")):
        unknown = _greek(path.read_text(encoding="utf-8")) - notation
        if unknown:
            missing[path.stem] = sorted(unknown)
    assert not missing, f"symbols without an entry on book/notation.md: {missing}"


def test_the_paper_chapters_are_about_half_their_length_before_the_appendices():
    words = sum(chapter_statistics(BOOK / f"{name}.md").words for name in PAPER_CHAPTERS)
    assert words <= MAIN_LINE_SHARE * PAPER_CHAPTERS_WORDS_BEFORE, (
        f"the chapters that follow the paper have {words} words of prose, more than "
        f"{MAIN_LINE_SHARE:.0%} of the {PAPER_CHAPTERS_WORDS_BEFORE} before issue 13: move "
        "forensic detail to an appendix")


def _toc_order() -> list[str]:
    return [TOC["root"]] + [chapter["file"] for part in TOC["parts"] for chapter in part["chapters"]]


def test_the_floquet_primer_comes_before_the_first_chapter_that_uses_its_words():
    order = _toc_order()
    # the words shooting_validation used before the reader had met them (a passing "analogue of
    # a Floquet multiplier" in stability_derivatives' table caption needs no theory)
    words = re.compile(r"monodromy|trivial multiplier|Liouville|Poincar", re.IGNORECASE)
    taught = _taught_chapters()
    first = next(name for name in taught if name != "primer_floquet"
                 and words.search(_text(name).split("\n# ", 1)[1]))
    assert order.index("primer_floquet") < order.index(first), (
        f"{first} uses the primer's words before book/primer_floquet.md")
    primer = _text("primer_floquet")
    for topic in (r"P\(t\)\\?,?\s*e\^\{Bt\}", r"linearis", r"negative", r"complex"):
        assert re.search(topic, primer), f"the primer does not treat {topic!r}"


@pytest.mark.parametrize("name", [n for n in _toc_order() if n != "references"])
def test_every_figure_a_page_shows_is_numbered_and_captioned(name):
    text = _text(name)
    assert "plt.show()" not in text, f"{name}: a figure shown without a number or caption"
    glued = set(re.findall(r"""glue\(\s*["'](fig-[\w-]+)["']""", text))
    shown = set(re.findall(r"```\{glue:figure\} (fig-[\w-]+)\n:name: \1", text))
    assert glued <= shown, f"{name}: glued figures never shown as numbered figures: {glued - shown}"


@pytest.mark.parametrize("name", [n for n in _toc_order() if n != "references"])
def test_every_exercise_solution_executes(name):
    assert "skip-execution" not in _text(name), f"{name}: a code cell the build does not run"


@pytest.mark.parametrize("name", _taught_chapters())
def test_every_exercise_solution_prints_its_answer(name):
    # a solution is a gated block (solution-start/-end) with a code cell that prints, shows or
    # displays its answer, so the reader sees the computation and the number it gives
    text = _text(name)
    assert not re.search(r"```\{solution\} ", text), f"{name}: a solution without code"
    for label, body in re.findall(r"```\{solution-start\} ([\w-]+)\n(.*?)```\{solution-end\}",
                                  text, flags=re.DOTALL):
        cells = re.findall(r"```\{code-cell\}[^\n]*\n(.*?)```", body, flags=re.DOTALL)
        assert any(re.search(r"\b(print|show|display)\(", cell) for cell in cells), \
            f"{name}: the solution of {label} prints no answer"


@pytest.mark.parametrize("name", [n for n in _toc_order() if n != "references"])
def test_no_orange_unit_circle(name):
    # the unit circle and other reference lines are grey; orange (SOURCE_COLORS["paper"]) is the
    # paper's printed numbers only
    for line in _text(name).splitlines():
        if "axhline(1.0" in line or "axhline(1," in line:
            assert "paper" not in line and "C_REF" not in line and "E69F00" not in line, \
                f"{name}: {line.strip()}"


def _code_lines(text: str) -> list[str]:
    lines, inside = [], False
    for line in text.splitlines():
        if line.startswith("```{code-cell}"):
            inside = True
        elif inside and line.startswith("```"):
            inside = False
        elif inside:
            lines.append(line)
    return lines


@pytest.mark.parametrize("name", [n for n in _toc_order() if n != "references"])
def test_figure_text_uses_only_what_matplotlib_typesets(name):
    # matplotlib's mathtext has no \lvert, \rvert: the figure then fails to render and myst-nb
    # silently shows its text repr ("<Figure size 640x380 with 1 Axes>") in place of the image
    figure_text = re.compile(r"label|title|\.text\(|annotate|suptitle")
    bad = [line.strip() for line in _code_lines(_text(name))
           if figure_text.search(line) and re.search(r"\\\\?[lr]vert", line)]
    assert not bad, f"{name}: {bad}"


@pytest.mark.parametrize("name", [n for n in _toc_order() if n not in ("references", "api")])
def test_every_code_cell_fence_is_a_code_cell(name):
    # A backtick inside a 4-backtick ````{table} caption made jupytext swallow the next six code
    # cells of control.md into one Markdown cell (they never ran, the next cell failed).
    import jupytext

    text = _text(name)
    fences = len(re.findall(r"^```\{code-cell\}", text, re.M))
    cells = sum(c.cell_type == "code" for c in jupytext.reads(text, fmt="myst").cells)
    assert cells == fences, f"{name}: {fences} code-cell fences, {cells} code cells"


# The setup-cell convention: the first code cell of every page (imports, the insect, the page's
# small helpers) is tagged hide-input, collapsed behind "Show code cell source" so that a student
# can open and copy it, never removed.
def _first_code_cell(name: str):
    import jupytext

    cells = [c for c in jupytext.reads(_text(name), fmt="myst").cells if c.cell_type == "code"]
    return cells[0] if cells else None


@pytest.mark.parametrize("name", [n for n in _toc_order() if n not in ("references", "api")])
def test_every_setup_cell_is_collapsed_not_removed(name):
    cell = _first_code_cell(name)
    if cell is None:
        pytest.skip(f"{name} has no code")
    tags = set(cell.metadata.get("tags", []))
    assert not tags & {"remove-cell", "remove-input"}, \
        f"{name}: the setup cell is removed ({sorted(tags)}); a reader cannot see how to start"
    assert "hide-input" in tags, f"{name}: tag the setup cell hide-input (got {sorted(tags)})"

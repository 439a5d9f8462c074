"""The notation page's rule for line styles, read from the code that draws the figures (issue 19).

"Line style = aerodynamic model" (book/notation.md, :mod:`flapping_book.style`): a curve in a
quantity's or a source's colour is solid unless it is one of the models of
:data:`~flapping_book.style.MODEL_LINESTYLES`; guide lines (zero, the unit circle, cycle means,
envelopes, reference slopes) are grey in any line style. So every line drawn with a constant
dashed or dotted style, in a book chapter's code cells or in the book's plotting modules, must
be grey. Styles taken from a table (``MODEL_LINESTYLES[model]``, the loads' styles in
:func:`flapping_book.plotting.plot_derivative_differences`) are the rule itself and not checked
here. The bifurcation diagrams' convention (solid stable, dashed unstable) draws its branches in
the grey of "ours".

The check is static: each call's ``ls``/``linestyle``/``linestyles`` keyword or its format
string (``"--"``, ``"o:"``), and its ``color``/``colors``/``c`` keyword, resolved through the
simple assignments of the same chapter (``C_GREY = "0.55"``) and the book's style tables.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from flapping_book import style

ROOT = Path(__file__).resolve().parents[2]
BOOK = ROOT / "book"
HELPERS = Path(style.__file__).resolve().parent  # book/_ext/flapping_book
MODULES = sorted(HELPERS.glob("*.py"))
SOLID = {"-", "solid", "none", "None", ""}
STYLE_KEYWORDS = {"ls", "linestyle", "linestyles"}
COLOR_KEYWORDS = {"color", "colors", "c"}
TABLES = {"SOURCE_COLORS": style.SOURCE_COLORS, "STATE_COLORS": style.STATE_COLORS,
          "LOAD_COLORS": style.LOAD_COLORS}
PLOTS = {"plot", "loglog", "semilogx", "semilogy", "errorbar", "step"}  # take a format string
_FORMAT = re.compile(r"^[.,ov^<>1-4sp*hH+xXDd|_]?(--|-\.|:)[.,ov^<>1-4sp*hH+xXDd|_]?"
                     r"[bgrcmykw]?$")


def _code_cells(text: str) -> list[str]:
    cells, lines, inside = [], [], False
    for line in text.splitlines():
        if line.startswith("```{code-cell}"):
            inside, lines = True, []
        elif inside and line.startswith("```"):
            inside = False
            cells.append("\n".join(line for line in lines if not line.startswith(":tags:")))
        elif inside:
            lines.append(line)
    return cells


def _sources() -> list[tuple[str, list[str]]]:
    pages = [(f"book/{p.name}", _code_cells(p.read_text(encoding="utf-8")))
             for p in sorted(BOOK.glob("*.md"))]
    modules = [(p.relative_to(ROOT).as_posix(), [p.read_text(encoding="utf-8")]) for p in MODULES]
    return pages + modules


def _resolve(node: ast.AST, names: dict[str, ast.AST]):
    """A colour or style expression as a constant string, or None if it is not one."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.Constant):
        return None
    if isinstance(node, ast.Tuple):  # a dash pattern (offset, (on, off)): not solid
        return "dash-pattern"
    if isinstance(node, ast.Name) and node.id in names:
        return _resolve(names[node.id], names)
    if isinstance(node, ast.Name) and isinstance(getattr(style, node.id, None), str):
        return getattr(style, node.id)  # GUIDE_COLOR, imported from flapping_book.style
    if (isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name)
            and node.value.id in TABLES and isinstance(node.slice, ast.Constant)):
        return TABLES[node.value.id].get(node.slice.value)
    return None


def _assignments(trees: list[ast.AST]) -> dict[str, ast.AST]:
    names: dict[str, ast.AST] = {}
    for tree in trees:
        for node in ast.walk(tree):
            if isinstance(node, ast.Assign) and len(node.targets) == 1:
                target, value = node.targets[0], node.value
                if isinstance(target, ast.Name):
                    names[target.id] = value
                elif (isinstance(target, ast.Tuple) and isinstance(value, ast.Tuple)
                      and len(target.elts) == len(value.elts)):
                    for t, v in zip(target.elts, value.elts, strict=True):
                        if isinstance(t, ast.Name):
                            names[t.id] = v
    return names


def _non_solid_lines(cells: list[str]) -> list[tuple[str, object]]:
    """(source line, resolved colour) of every call drawn in a constant non-solid style."""
    trees = [ast.parse(cell) for cell in cells]
    names = _assignments(trees)
    found = []
    for cell, tree in zip(cells, trees, strict=True):
        for call in (n for n in ast.walk(tree) if isinstance(n, ast.Call)):
            keywords = {k.arg: k.value for k in call.keywords if k.arg}
            styles = [_resolve(keywords[k], names) for k in STYLE_KEYWORDS & set(keywords)]
            if isinstance(call.func, ast.Attribute) and call.func.attr in PLOTS:
                styles += [a.value for a in call.args
                           if isinstance(a, ast.Constant) and isinstance(a.value, str)
                           and _FORMAT.match(a.value)]
            if not any(s is not None and s not in SOLID for s in styles):
                continue
            colours = [_resolve(keywords[k], names) for k in COLOR_KEYWORDS & set(keywords)]
            line = ast.get_source_segment(cell, call) or ast.dump(call)
            found.append((" ".join(line.split()), colours[0] if colours else None))
    return found


def test_the_scanner_finds_dashed_and_dotted_lines():
    cells = ['C_G = "0.6"\nax.plot(x, y, "--", color=C_G)\nax.axhline(0, ls=":", color="C1")\n'
             'ax.plot(x, y, color=STATE_COLORS["u"])\nax.plot(x, y, "o", color="C2")\n'
             'ax.plot(x, y, ls=MODEL_LINESTYLES[m], color="C3")\n'
             'ax.plot(x, y, "o--", color=SOURCE_COLORS["averaged"])\ntext.split(":")']
    found = _non_solid_lines(cells)
    assert [colour for _, colour in found] == ["0.6", "C1", style.SOURCE_COLORS["averaged"]]


def test_the_helpers_that_draw_are_checked():
    # A helpers' path that matched no file would check nothing and pass.
    assert {"plotting.py", "schematic.py", "animation.py"} <= {p.name for p in MODULES}


@pytest.mark.parametrize("name, cells", _sources(), ids=[name for name, _ in _sources()])
def test_dashed_and_dotted_lines_are_models_or_grey_guides(name, cells):
    bad = [line for line, colour in _non_solid_lines(cells)
           if not (isinstance(colour, str) and style.is_grey(colour))]
    assert not bad, (
        f"{name}: dashed or dotted lines in a colour, which the notation page reserves for the "
        f"aerodynamic models (draw them solid, or grey if they are guides): {bad}")

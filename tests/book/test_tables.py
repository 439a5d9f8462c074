"""Markdown tables and LaTeX aligned blocks for glue."""

import pytest

from flapping_book import tables


def test_markdown_table_has_one_line_per_row_and_escapes_pipes():
    text = tables.markdown_table(["a", "b"], [[1, "x|y"], [2, 3]], align="lr")
    lines = text.splitlines()
    assert len(lines) == 4 and lines[1] == "|:--|--:|"
    assert r"x\|y" in lines[2]
    with pytest.raises(ValueError, match="cells"):
        tables.markdown_table(["a", "b"], [[1]])


def test_latex_aligned_breaks_long_sums():
    sympy = pytest.importorskip("sympy")
    x = sympy.symbols("x0:7")
    text = tables.latex_aligned({"y": sympy.Add(*x), "z": r"\alpha"}, terms_per_line=3)
    assert text.startswith(r"\begin{aligned}") and text.endswith(r"\end{aligned}")
    assert text.count(r"&\qquad") == 2        # 7 terms, 3 per line: two continuation lines
    assert r"z &= \alpha" in text


def test_book_symbols_renames_the_damping_coefficients_not_the_multipliers():
    assert tables.book_symbols(r"\mu_{1} f + \mu_{2} \Omega") == r"\nu_{1} f + \nu_{2} \Omega"
    assert tables.book_symbols(r"\mu_1 + \mu_2") == r"\nu_1 + \nu_2"
    assert tables.book_symbols(r"\mu_{k} \mu_3") == r"\mu_{k} \mu_3"


def test_markdown_table_sets_true_minus_signs_in_cells_outside_math():
    table = tables.markdown_table(["a", "b"], [["-0.2627 m/s", "$-1$"], ["-21%", "1.2e-04"]])
    assert "\u22120.2627 m/s" in table and "\u221221%" in table
    assert "$-1$" in table and "1.2e-04" in table

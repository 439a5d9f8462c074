"""Numbers in e notation become 1.2 × 10⁻¹³ in the text."""

import pytest

from flapping_book.formatting import (
    bmatrix,
    complex_text,
    latex_array,
    latex_complex,
    latex_scientific,
    scientific,
    split_scientific,
    text_minus,
    text_number,
)


@pytest.mark.parametrize("text, expected", [
    ("1.2e-13", "1.2 × 10⁻¹³"), ("1e-06", "10⁻⁶"), ("-3.0e+05", "−3.0 × 10⁵"),
    ("4E2", "4 × 10²"), ("0.25", "0.25"), ("abc", "abc"), ("1.2e-13 m", "1.2e-13 m"),
])
def test_scientific(text, expected):
    assert scientific(text) == expected


def test_split_keeps_a_true_minus_sign_for_the_superscript():
    assert split_scientific(" 2.5e-07 ") == ("2.5 × 10", "−7")


def test_latex_scientific():
    assert latex_scientific(1.234e-13) == r"1.2 \times 10^{-13}"
    assert latex_scientific(1e-6, 1) == "10^{-6}"
    assert latex_scientific(0.5) == "0.5"


def test_zero_in_e_notation_is_zero_not_zero_times_ten_to_the_zero():
    from flapping_book.formatting import scientific, split_scientific

    assert split_scientific("0e+00") == ("0", "")
    assert scientific("0e+00") == "0"
    assert scientific("-0.0e+00") == "0"
    assert scientific("2e-14") == "2 × 10⁻¹⁴"


def test_roundoff_bound_never_zero():
    import numpy as np

    from flapping_book.formatting import roundoff_bound

    assert roundoff_bound(0.0, 100.0) == np.finfo(float).eps * 100.0
    assert roundoff_bound(-3e-12, 100.0) == 3e-12
    assert f"{roundoff_bound(0.0, 107.5):.0e}" != "0e+00"


def test_every_force_budget_term_is_typeset_without_code_names():
    from flapping.hover.orbit import force_budget  # noqa: F401  (the keys below are its keys)
    from flapping_book.formatting import term_latex
    keys = ["-q w", "-g sin(theta)", "X0/m", "Xu u", "Xw w", "Xq q", "q u", "g cos(theta)",
            "Z0/m", "Zu u", "Zw w", "Zq q", "M0/Iy", "Mu u", "Mw w", "Mq q"]
    out = {k: term_latex(k) for k in keys}
    assert out["Z0/m"] == "$Z_0/m$" and out["g cos(theta)"] == r"$g \cos\theta$"
    assert out["M0/Iy"] == "$M_0/I_y$" and out["Xq q"] == "$X_q q$"
    for tex in out.values():
        assert tex.startswith("$") and tex.endswith("$")
        assert "theta" not in tex.replace(r"\theta", "") and "Iy" not in tex


def test_a_lone_negative_number_gets_a_true_minus_sign():
    from flapping_book.formatting import minus_sign

    assert minus_sign("-0.10") == "\u22120.10"
    assert minus_sign(" -3 ") == " \u22123 "
    # anything but a lone plain number is left alone: ranges, words, positives, e-notation
    for text in ("0.10", "+2", "-0.1 to 0.2", "-", "x-1", "-1e-3", "n/a"):
        assert minus_sign(text) == text


def test_the_transform_typesets_a_glued_negative_number():
    from docutils import nodes

    from flapping_book.formatting import _typeset

    node = nodes.inline("", "-0.25", classes=["pasted-text"])
    assert _typeset(node, nodes) and node.astext() == "\u22120.25"
    node = nodes.inline("", "0.25", classes=["pasted-text"])
    assert not _typeset(node, nodes) and node.astext() == "0.25"


@pytest.mark.parametrize("text, expected", [
    ("-0.2627 m/s", "\u22120.2627 m/s"),
    ("-21%", "\u221221%"),
    ("(-3.5 %)", "(\u22123.5 %)"),
    ("0.9871 - 0.0108i", "0.9871 \u2212 0.0108i"),
    ("0.1-0.2", "0.1-0.2"),          # a range
    ("1.2e-04", "1.2e-04"),          # an exponent (typeset at build time)
    ("$-1$", "$-1$"),                # math
    ("`x = -1`", "`x = -1`"),        # code
    ("k-1, well-posed, -", "k-1, well-posed, -"),
])
def test_text_minus_sets_true_minus_signs_only_where_a_hyphen_is_a_minus(text, expected):
    assert text_minus(text) == expected


def test_complex_text_uses_true_minus_signs():
    assert complex_text(0.9871 - 0.0108j) == "0.9871 \u2212 0.0108i"
    assert complex_text(-0.25 + 8.6729j, 2) == "\u22120.25 + 8.67i"
    assert complex_text(-0.5) == "\u22120.5000"


def test_bmatrix_formats_each_entry():
    assert bmatrix([[1, -2], [3, 4]], ".1f") == (
        r"\begin{bmatrix}1.0 & -2.0 \\ 3.0 & 4.0\end{bmatrix}")


def test_latex_complex_writes_pairs_with_plus_minus():
    assert latex_complex(-0.25 - 8.6729j, 2, pair=True) == r"-0.25 \pm 8.67i"
    assert latex_complex(-0.25 - 8.6729j, 2) == "-0.25 - 8.67i"
    assert latex_complex(-2.403954 + 0j, 3) == "-2.404"


def test_latex_array_has_a_rule_below_the_header_and_checks_its_rows():
    assert latex_array(["a", "b"], [[1, 2], [3, 4]], "lr") == (
        r"\begin{array}{lr}a & b \\ \hline 1 & 2 \\ 3 & 4 \end{array}")
    with pytest.raises(ValueError, match="entries"):
        latex_array(["a", "b"], [[1]])


@pytest.mark.parametrize("value, fmt, expected", [
    (-1.28211e-14, ".6g", "\u22121.28211 × 10⁻¹⁴"),
    (1.19e-10, ".3g", "1.19 × 10⁻¹⁰"),
    (-2.40395, ".6g", "\u22122.40395"),
    (1.0, ".6g", "1"),
    (0.0367, ".2e", "3.67 × 10⁻²"),
])
def test_text_number_typesets_powers_and_minus_signs(value, fmt, expected):
    assert text_number(value, fmt) == expected


def test_source_markdown_sets_formulas_as_math_and_files_as_code():
    from flapping_book.formatting import source_markdown

    assert (source_markdown("estimate: Ellington's fit r2 = 0.929 r1^0.732, inverted")
            == r"estimate: Ellington's fit $\hat r_2 = 0.929\,\hat r_1^{0.732}$, inverted")
    assert (source_markdown("Berman & Wang (2007) in FWUAV morp_params.mat: S = R c_bar, "
                            "c_bar = 4.02 mm")
            == r"Berman & Wang (2007) in FWUAV `morp_params.mat`: $S = R\,\bar c$, "
               r"$\bar c$ = 4.02 mm")
    assert (source_markdown("hover stroke plane WK.beta in sim_QS_x_hover_*.mat, ~60 deg")
            == "hover stroke plane `WK.beta` in `sim_QS_x_hover_*.mat`, ≈60°")
    assert source_markdown("+-0.02: the scatter") == "±0.02: the scatter"
    assert source_markdown("no formula here (1990)") == "no formula here (1990)"


@pytest.mark.parametrize("text, expected", [
    ("1.558652210716", True), ("-3e-05", True), ("−0.2500 ± 8.6700i", True), ("+0.123", True),
    ("1648", True), ("0.98 − 0.01i", True), ("1.2 × 10⁻¹³", True),
    ("hawkmoth", False), ("1.2 to 3.4", False), ("", False), ("16.3 (V)", False),
])
def test_is_number_text(text, expected):
    from flapping_book.formatting import is_number_text

    assert is_number_text(text) is expected

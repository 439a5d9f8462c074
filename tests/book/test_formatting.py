"""Numbers in e notation become 1.2 × 10⁻¹³ in the text."""

import pytest

from flapping.book.formatting import latex_scientific, scientific, split_scientific


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

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


def test_zero_in_e_notation_is_zero_not_zero_times_ten_to_the_zero():
    from flapping.book.formatting import scientific, split_scientific

    assert split_scientific("0e+00") == ("0", "")
    assert scientific("0e+00") == "0"
    assert scientific("-0.0e+00") == "0"
    assert scientific("2e-14") == "2 × 10⁻¹⁴"


def test_roundoff_bound_never_zero():
    import numpy as np

    from flapping.book.formatting import roundoff_bound

    assert roundoff_bound(0.0, 100.0) == np.finfo(float).eps * 100.0
    assert roundoff_bound(-3e-12, 100.0) == 3e-12
    assert f"{roundoff_bound(0.0, 107.5):.0e}" != "0e+00"

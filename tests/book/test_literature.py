"""Literature values: printed digits, agreement in significant digits, ChaosBook's two sources."""

import math
from decimal import InvalidOperation

import pytest

from flapping.book.literature import (
    MAX_DIGITS,
    ROSSLER_MU_WEB,
    ROSSLER_T_CODE,
    ROSSLER_T_WEB,
    PrintedValue,
    agreement_digits,
)


def test_printed_value_counts_its_digits():
    assert ROSSLER_T_CODE.significant_digits == 19
    assert ROSSLER_T_WEB.significant_digits == 12
    assert ROSSLER_MU_WEB.significant_digits == 10
    assert PrintedValue("1.500", "x").significant_digits == 4      # trailing zeros were printed
    assert PrintedValue("0.0012", "x").significant_digits == 2
    assert PrintedValue("5.88108845586", "x").decimals == 11
    with pytest.raises(InvalidOperation):
        PrintedValue("about 5.9", "x")


def test_agreement_digits():
    assert math.isclose(agreement_digits(1.0 + 1e-6, 1.0), 6.0, rel_tol=1e-6)
    assert agreement_digits(2.0, 2.0) == MAX_DIGITS
    assert math.isclose(agreement_digits(-2.4, PrintedValue("-2.4", "x") ), MAX_DIGITS)
    with pytest.raises(ValueError):
        agreement_digits(1.0, 0.0)


def test_chaosbook_sources_disagree_in_the_eleventh_digit():
    # the web page's period is the course code's to about 10.3 digits, not to its 12 printed
    between = agreement_digits(ROSSLER_T_WEB.value, ROSSLER_T_CODE)
    assert 10.0 < between < 10.6
    assert ROSSLER_T_CODE.source != ROSSLER_T_WEB.source == ROSSLER_MU_WEB.source

"""Literature values: printed digits, agreement in significant digits, ChaosBook's two sources."""

import math
from decimal import InvalidOperation

import pytest

from flapping_book.literature import (
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


def test_dednam_and_botha_printed_their_orbit_to_the_digits_our_shooting_finds():
    # their Table 1 case, from their own initial guess: the period to all 13 printed digits, the
    # largest non-trivial multiplier to its printed rounding (half a unit in the 6th decimal)
    import numpy as np

    from flapping.periodic.floquet import monodromy, nontrivial_multipliers
    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.periodic.testproblems import rossler, rossler_jac
    from flapping_book.literature import DEDNAM_BOTHA_MU, DEDNAM_BOTHA_T

    args = (0.15, 0.2, 3.5)
    orbit = find_periodic_orbit(rossler, [2.7002161609, 3.4723025491, 3.0], 5.92030065,
                                fixed=[2], jac=rossler_jac, args=args)
    mon = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, args=args)
    assert DEDNAM_BOTHA_T.significant_digits == 13 and DEDNAM_BOTHA_MU.decimals == 6
    assert agreement_digits(orbit.period, DEDNAM_BOTHA_T) > 12.0
    mu = float(np.max(np.abs(nontrivial_multipliers(mon))))
    assert abs(mu - DEDNAM_BOTHA_MU.value) <= 0.5e-6


def test_viswanaths_orbit_ab_is_found_to_his_printed_digits():
    # from his (x, y) on the section z = r - 1, rounded to one decimal, and his period rounded
    import numpy as np

    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.periodic.testproblems import lorenz, lorenz_jac
    from flapping_book.literature import VISWANATH_AB_T, VISWANATH_AB_XY, VISWANATH_AB_Z

    x_ab = np.array([*(v.value for v in VISWANATH_AB_XY), VISWANATH_AB_Z])
    orbit = find_periodic_orbit(lorenz, np.round(x_ab, 1), round(VISWANATH_AB_T.value, 2),
                                fixed=[2], jac=lorenz_jac)
    assert agreement_digits(orbit.period, VISWANATH_AB_T) > 13.0
    for ours, printed in zip(orbit.x0[:2], VISWANATH_AB_XY, strict=True):
        assert abs(ours - printed.value) < 1e-10


def test_no_page_types_a_literature_value():
    # every page reads them from flapping_book.literature, so a source's digits live once
    from pathlib import Path

    from flapping_book import literature

    printed = [getattr(literature, name) for name in literature.__all__
               if isinstance(getattr(literature, name), PrintedValue)]
    printed += list(literature.VISWANATH_AB_XY)
    book = Path(__file__).resolve().parents[2] / "book"
    for page in book.glob("*.md"):
        text = page.read_text()
        for value in printed:
            assert value.text not in text, f"{page.name} types {value.text} ({value.source})"

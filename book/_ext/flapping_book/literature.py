"""Literature values the book compares with, each once, as printed, with where it was printed.

Several chapters quote the same published number (ChaosBook's Rössler period appears in
``shooting_validation``, ``continuation`` and ``appendix_methods``); they all read it from here, so
that a page cannot quote one source's digits under another's name. A value is kept as the *text*
its source prints (trailing digits count: they were printed), and :func:`agreement_digits` says
in how many significant digits a computed number agrees with it.

ChaosBook {Cvitanović et al., *Chaos: Classical and Quantum*} gives the period-1 orbit of the
Rössler system (a = b = 0.2, c = 5.7) in two places, to different precision:

* its course code carries the period to 19 significant digits (:data:`ROSSLER_T_CODE`), more than a
  double holds;
* its web page ``extras/simon/Roessler.html`` prints the period to 12 digits and the expanding
  multiplier to 10 (:data:`ROSSLER_T_WEB`, :data:`ROSSLER_MU_WEB`). That page's period differs
  from the course code's in its 11th digit.

Viswanath (2003) computes the Lorenz system's periodic orbits (sigma = 10, r = 28, b = 8/3) to 14
digits; the orbit AB's period and its point on the section z = r - 1 = 27 are
:data:`VISWANATH_AB_T` and :data:`VISWANATH_AB_XY`.

Dednam and Botha (2015), who introduced the optimized shooting method, report their own Rössler
case (a = 0.15, b = 0.2, c = 3.5) in their Table 1: its period and the modulus of its largest
non-trivial multiplier (:data:`DEDNAM_BOTHA_T`, :data:`DEDNAM_BOTHA_MU`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from decimal import Decimal

__all__ = [
    "PrintedValue",
    "agreement_digits",
    "MAX_DIGITS",
    "ROSSLER_T_CODE",
    "ROSSLER_T_WEB",
    "ROSSLER_MU_WEB",
    "DEDNAM_BOTHA_T",
    "DEDNAM_BOTHA_MU",
    "VISWANATH_AB_T",
    "VISWANATH_AB_XY",
    "VISWANATH_AB_Z",
]

#: The most digits a comparison of doubles can show: beyond about 16 significant digits the
#: relative difference of two doubles is round-off.
MAX_DIGITS = 16.0


@dataclass(frozen=True)
class PrintedValue:
    """A number as its source prints it.

    Attributes
    ----------
    text : str
        The digits as printed, e.g. ``"5.88108845586"``.
    source : str
        Where, in words a caption can use.
    """

    text: str
    source: str

    def __post_init__(self) -> None:
        Decimal(self.text)   # raises decimal.InvalidOperation for anything but a number

    @property
    def value(self) -> float:
        """The printed number as a float (rounded to double precision)."""
        return float(self.text)

    @property
    def significant_digits(self) -> int:
        """Significant digits printed, e.g. ``"5.88108845586"`` -> 12 (trailing zeros count)."""
        return len(Decimal(self.text).as_tuple().digits)

    @property
    def decimals(self) -> int:
        """Digits printed after the decimal point."""
        return max(0, -int(Decimal(self.text).as_tuple().exponent))


def agreement_digits(ours: float, reference: float | PrintedValue) -> float:
    """Significant digits in which ``ours`` agrees with ``reference``: ``-log10 |ours/ref - 1|``.

    Capped at :data:`MAX_DIGITS` (identical doubles).

    Raises
    ------
    ValueError
        For a zero reference (no relative difference).
    """
    ref = reference.value if isinstance(reference, PrintedValue) else float(reference)
    if ref == 0:
        raise ValueError("the reference is zero: agreement in significant digits is undefined")
    rel = abs(ours / ref - 1.0)
    return MAX_DIGITS if rel == 0 else min(MAX_DIGITS, -math.log10(rel))


_CODE = "ChaosBook's course code"
_WEB = "ChaosBook's web page extras/simon/Roessler.html"

#: Period of the Rössler period-1 orbit (a = b = 0.2, c = 5.7), ChaosBook's course code.
ROSSLER_T_CODE = PrintedValue("5.881088455554846384", _CODE)
#: The same period as ChaosBook's web page prints it.
ROSSLER_T_WEB = PrintedValue("5.88108845586", _WEB)
#: The expanding Floquet multiplier of that orbit, as ChaosBook's web page prints it.
ROSSLER_MU_WEB = PrintedValue("-2.403953527", _WEB)

_VISWANATH = "Viswanath (2003), Nonlinearity 16, 1035-1056, orbit AB"

#: Period of the Lorenz orbit AB, as printed.
VISWANATH_AB_T = PrintedValue("1.5586522107162", _VISWANATH)
#: (x, y) of the orbit AB on the section z = r - 1, as printed.
VISWANATH_AB_XY = (PrintedValue("-13.763610682134", _VISWANATH),
                   PrintedValue("-19.578751942452", _VISWANATH))
#: The section's z = r - 1 (r = 28).
VISWANATH_AB_Z = 27.0

_DB = "Dednam and Botha (2015), Table 1"

#: Period of Dednam and Botha's Rössler orbit (a = 0.15, b = 0.2, c = 3.5), as printed.
DEDNAM_BOTHA_T = PrintedValue("5.920340248194", _DB)
#: Modulus of the largest non-trivial Floquet multiplier of that orbit, as printed.
DEDNAM_BOTHA_MU = PrintedValue("0.812252", _DB)

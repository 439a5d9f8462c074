"""Argument validation at the public boundary, in one place.

Every public function of :mod:`flapping` checks its arguments once, through these helpers, so that
a bad input gets the same kind of message everywhere: the argument's name, the accepted range,
and the value received. Internal functions trust their inputs.

Conventions
-----------
- Numbers are converted to Python ``float`` (float64) on entry, whatever their type (``int``,
  ``np.float32``, ``np.int64``, 0-d arrays); ``bool``, strings, complex numbers and ``None`` are
  refused, because ``True`` silently meaning 1 kg is a bug, not a convenience.
- Arrays are converted to float64 copies; non-finite entries are refused.
- Errors are :class:`ValueError` (a wrong type is also a ValueError: the value is what is wrong).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Sequence
from typing import Any, TypeVar

import numpy as np

from flapping.errors import NonFiniteError

__all__ = [
    "real", "positive", "nonnegative", "integer", "choice", "vector", "matrix",
    "finite_output", "array", "instance", "tolerances", "boolean", "call_args",
]

T = TypeVar("T")


def _show(value: Any, width: int = 60) -> str:
    """``repr(value)`` cut to ``width`` characters (a 10**400 has 401 digits, 10**5000 no repr)."""
    try:
        text = repr(value)
    except ValueError:  # int too large to convert to a string (sys.set_int_max_str_digits)
        return f"an int of {value.bit_length()} bits"
    return text if len(text) <= width else f"{text[:width - 20]}...{text[-15:]} " \
        f"({len(text)} characters)"


def _fmt(bound: float) -> str:
    return {math.pi / 2: "pi/2", math.pi: "pi", -math.pi / 2: "-pi/2"}.get(bound, f"{bound:g}")


def _range_text(low: float | None, high: float | None, low_open: bool, high_open: bool) -> str:
    if low is None and high is None:
        return "a finite real number"
    left = "(-inf" if low is None else ("(" if low_open else "[") + _fmt(low)
    right = "inf)" if high is None else _fmt(high) + (")" if high_open else "]")
    return f"a real number in {left}, {right}"


def real(
    name: str,
    value: Any,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    high_open: bool = False,
    unit: str = "",
) -> float:
    """``value`` as a finite float64 in the given interval, or a ValueError naming ``name``.

    Parameters
    ----------
    name : str
        The argument's name, as the user wrote it.
    value : object
        A real number (Python or NumPy scalar, or a 0-d array).
    low, high : float, optional
        Bounds of the accepted interval (``None``: unbounded).
    low_open, high_open : bool
        Whether the bound itself is excluded.
    unit : str
        Unit for the message (e.g. ``"rad"``).
    """
    # The message is built only on failure: this runs on every Insect field of every sweep point.
    if type(value) is float:  # the common case, without the abstract-class checks below
        x = value
    else:
        if isinstance(value, np.ndarray) and value.ndim == 0:
            value = value[()]
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
            raise ValueError(f"`{name}` must be {_expected(low, high, low_open, high_open, unit)}"
                             f"; got {_show(value)} ({type(value).__name__})")
        try:
            x = float(value)
        except OverflowError:  # an int or Fraction beyond float64 (e.g. 10**400)
            raise ValueError(f"`{name}` must be {_expected(low, high, low_open, high_open, unit)}"
                             f"; got {_show(value)}, which is beyond float64's range "
                             "(about 1.8e308)") from None
    ok = math.isfinite(x)
    if ok and low is not None:
        ok = x > low if low_open else x >= low
    if ok and high is not None:
        ok = x < high if high_open else x <= high
    if not ok:
        raise ValueError(f"`{name}` must be {_expected(low, high, low_open, high_open, unit)}; "
                         f"got {_show(value)}")
    return x


def _expected(low: float | None, high: float | None, low_open: bool, high_open: bool,
              unit: str) -> str:
    """What :func:`real` accepts, in words (for its messages)."""
    return _range_text(low, high, low_open, high_open) + (f" {unit}" if unit else "")


def positive(name: str, value: Any, *, unit: str = "") -> float:
    """``value`` as a float > 0 (see :func:`real`)."""
    return real(name, value, low=0.0, low_open=True, unit=unit)


def nonnegative(name: str, value: Any, *, unit: str = "") -> float:
    """``value`` as a float >= 0 (see :func:`real`)."""
    return real(name, value, low=0.0, unit=unit)


def integer(name: str, value: Any, *, low: int | None = None, high: int | None = None) -> int:
    """``value`` as a Python int in [low, high]; integral floats such as ``4.0`` are refused."""
    if type(value) is int and (low is None or value >= low) and (high is None or value <= high):
        return value  # the common case, without the abstract-class checks below
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    lo = "-inf" if low is None else str(low)
    hi = "inf" if high is None else str(high)
    expected = f"an integer in [{lo}, {hi}]"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise ValueError(f"`{name}` must be {expected}; got {_show(value)} "
                         f"({type(value).__name__})")
    n = int(value)
    if (low is not None and n < low) or (high is not None and n > high):
        raise ValueError(f"`{name}` must be {expected}; got {_show(value)}")
    return n


def choice(name: str, value: T, options: Iterable[T]) -> T:
    """``value`` if it is one of ``options``, else a ValueError listing them."""
    options = tuple(options)
    try:
        ok = value in options
    except TypeError:  # unhashable or incomparable
        ok = False
    if not ok:
        raise ValueError(f"`{name}` must be one of {options}; got {value!r}")
    return value


def vector(name: str, value: Any, *, size: int | None = None) -> np.ndarray:
    """A non-empty, finite, 1-D float64 copy of ``value`` (of length ``size`` if given).

    Bools and strings are refused, as in :func:`array` (``[True, False]`` or ``["1", "2"]`` would
    otherwise pass as numbers through ``float()``).
    """
    x = array(name, value)
    if x.ndim != 1 or x.size == 0 or (size is not None and x.size != size):
        shape = "a non-empty 1-D array" if size is None else f"an array of shape ({size},)"
        raise ValueError(f"`{name}` must be {shape}; got shape {x.shape}")
    return x


def matrix(name: str, value: Any, *, square: bool = False) -> np.ndarray:
    """A finite 2-D float64 (or complex128, if complex) copy of ``value``."""
    x = np.array(value)
    x = x.astype(complex if np.iscomplexobj(x) else float)
    if x.ndim != 2 or (square and x.shape[0] != x.shape[1]):
        what = "a square 2-D array" if square else "a 2-D array"
        raise ValueError(f"`{name}` must be {what}; got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"`{name}` must be finite")
    return x


def finite_output(name: str, value: np.ndarray, t: float, x: Sequence[float] | np.ndarray) -> None:
    """Raise :class:`~flapping.errors.NonFiniteError` if a user callable returned NaN or infinity.

    Solvers fed NaN never converge (``solve_ivp`` shrinks its step forever), so every integration
    checks what ``fun`` and ``jac`` return and names which one failed, where: the error (a
    ValueError) carries ``source`` (``name``), ``t``, ``state`` (``x``) and ``value``. A state
    beyond 1e100 is said to be blowing up (the callable overflowed with the solution).
    """
    if not np.all(np.isfinite(value)):
        state = np.asarray(x, dtype=float)
        size = float(np.max(np.abs(state))) if state.size else 0.0
        why = (f" (the solution is blowing up: max |x| = {size:.3g}, and `{name}` overflowed "
               f"with it)" if size > 1e100 else "")
        raise NonFiniteError(
            f"`{name}` returned a non-finite value at t = {t!r}, x = {state!r}: "
            f"{np.asarray(value)!r}{why}", source=name, t=t, state=state, value=value)


def array(name: str, value: Any) -> np.ndarray:
    """A finite float64 array of any shape (0-d included) from ``value``, or a ValueError.

    For arguments that broadcast (times, states, radii); bools and strings are refused as in
    :func:`real`.
    """
    if type(value) is np.ndarray and value.dtype == np.float64:
        x = value.copy()  # the common case (a previous answer): nothing to convert or refuse
    else:
        try:
            x = np.asarray(value)
        except (TypeError, ValueError):  # ragged nested sequences
            raise ValueError(f"`{name}` must be an array of real numbers; got {value!r}"
                             ) from None
        if x.dtype.kind not in "iuf":
            raise ValueError(
                f"`{name}` must be an array of real numbers; got {value!r} (dtype {x.dtype})")
        x = x.astype(float)
    if not np.isfinite(x).all():
        raise ValueError(f"`{name}` must be finite; got {value!r}")
    return x


def instance(name: str, value: T, cls: type) -> T:
    """``value`` if it is an instance of ``cls``, else a ValueError naming ``name`` and the type."""
    if not isinstance(value, cls):
        article = "an" if cls.__name__[:1].lower() in "aeiou" else "a"
        raise ValueError(f"`{name}` must be {article} {cls.__name__}; got {_show(value)} "
                         f"({type(value).__name__})")
    return value


def tolerances(rtol: Any, atol: Any) -> tuple[float, float]:
    """``(rtol, atol)`` of an integration as positive floats, or a ValueError naming the bad one."""
    return positive("rtol", rtol), positive("atol", atol)


def call_args(value: Any) -> tuple[Any, ...]:
    """``args`` (extra arguments of a user callable) as a tuple, or a ValueError.

    Like :func:`scipy.integrate.solve_ivp`, any finite iterable is accepted; a single number
    (``args=5`` instead of ``args=(5,)``) or None is refused, naming ``args``.
    """
    if type(value) is tuple:
        return value
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise ValueError(f"`args` must be a tuple of extra arguments of the callables (e.g. "
                         f"args=(c,) for one); got {_show(value)} ({type(value).__name__})")
    return tuple(value)


def boolean(name: str, value: Any) -> bool:
    """``value`` if it is a bool (Python or NumPy), else a ValueError naming ``name``.

    A flag is not a number: ``check=0`` or ``check="no"`` (truthy!) is refused.
    """
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"`{name}` must be True or False; got {_show(value)} "
                         f"({type(value).__name__})")
    return bool(value)


def components(name: str, value: Any, limits: Sequence[tuple[str, float, str]]) -> np.ndarray:
    """A finite float64 vector whose entry ``i`` lies in ``[-limit_i, limit_i]``, or a ValueError.

    For states given by a user (an initial condition): an entry far outside what the system
    can reach is a unit slip or a typo, and integrating from it may never end (a stiff, fast
    blow-up shrinks the step forever). ``limits`` holds ``(label, limit, unit)`` per entry; the
    message names ``name``, the entry's label and its range.
    """
    x = vector(name, value, size=len(limits))
    for i, (label, limit, unit) in enumerate(limits):
        if not abs(x[i]) <= limit:
            raise ValueError(f"`{name}[{i}]` ({label}) must be a real number in "
                             f"[{-limit:g}, {limit:g}] {unit}; got {x[i]!r}".rstrip())
    return x


def triangle_inequality(names: str, moments: Sequence[float], *, max_ratio: float = 1.0,
                        check: Sequence[int] | None = None, rtol: float = 1e-9) -> None:
    """Refuse a body's principal moments that no rigid body has, or pass.

    A rigid body's principal moments obey the triangle inequality ``I_a <= I_b + I_c`` (each is
    an integral of a sum of two squared coordinates; a lamina reaches equality). A set that
    breaks it is most often one moment in the wrong unit (g cm^2 typed as kg m^2 is 1e7 times
    too large). Refused when a moment of ``check`` (indices; default all) exceeds
    ``max_ratio`` times the sum of the other two (1: the inequality itself); ``rtol`` absorbs
    the rounding of a lamina's equality. ``names`` names the fields they are made of.
    """
    m = np.asarray(moments, dtype=float)
    total = float(m.sum())
    for i in range(m.size) if check is None else check:
        others = total - float(m[i])
        if m[i] > max_ratio * others * (1.0 + rtol):
            bound = "the sum of the other two" if max_ratio == 1.0 else \
                f"{max_ratio:g} times the sum of the other two"
            raise ValueError(
                f"{names}: the principal moments {sorted(m.tolist())} kg m^2 break the triangle "
                f"inequality ({m[i]:.6g} must not exceed {bound}, {max_ratio * others:.6g}): no "
                "rigid body has them (a moment in the wrong unit? g cm^2 is 1e-7 kg m^2)")


def grid_size(name: str, size: int, *, high: int, why: str = "") -> int:
    """``size`` (points of a grid or a sample, already counted) if it is at most ``high``.

    Checked before any work starts, so that a grid of 10^8 points is refused in microseconds
    instead of running for days (or exhausting memory).
    """
    if size > high:
        raise ValueError(f"`{name}` must have at most {high} points{why}; got {size}")
    return size

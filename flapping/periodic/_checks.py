"""The user's ODE checked at the public boundary of :mod:`flapping.periodic`: one call each.

A mistake in the user's callables (``args`` that do not fit the signature, a field that returns
None, a string, a complex or wrongly shaped array, an ``x0`` of the wrong length) would otherwise
surface as whatever Python or NumPy says deep inside an integration, or not at all (NumPy casts a
complex array to float with a warning, dropping the imaginary part). Every public function that
takes ``fun`` (and ``jac``, ``param_jac``) calls :func:`first_call` once per callable before it
integrates anything; the integrations themselves keep only their cheap shape and finiteness checks
(:class:`flapping.periodic._segments.Checked`): nothing here runs per step.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from typing import Any

import numpy as np

import flapping._validation as check

__all__ = ["first_call", "numeric", "probe_fields"]

#: Exceptions that a field raises when handed a state of the wrong length (unpacking, indexing,
#: matrix products): at the first call they are answered as a ValueError naming ``x0``.
_SHAPE_ERRORS = (ValueError, IndexError)


def first_call(fun: Callable[..., Any], name: str, t: float, x: np.ndarray,
               extra: tuple[Any, ...], shape: tuple[int, ...], *, call: str,
               given: str, reshape: bool = False, first: bool = True) -> np.ndarray:
    """``fun(t, x, *extra)`` as a float64 array of ``shape``, or an error naming the culprit.

    Parameters
    ----------
    fun : callable
        The user's callable.
    name : str
        Its argument name (``"fun"``, ``"jac"``, ``"param_jac"``).
    t : float
        The time of the call (the start of the integration, or of the callable's segment).
    x : ndarray, shape (n,)
        The initial state ``x0`` (a copy is passed).
    extra : tuple
        The trailing arguments (``args``, then the parameters, if any).
    shape : tuple of int
        The shape the value must have.
    call : str
        How the callable is called, for messages (e.g. ``"fun(t, x, *args)"``).
    given : str
        What supplies ``extra``, for messages (e.g. ``"`args` = (1.0,)"``).
    reshape : bool
        Accept any shape of the right size (``param_jac`` of one parameter may return (n,)).
    first : bool
        Whether this is the first callable probed: only then can a wrong length be ``x0``'s
        (a later segment's ``fun`` of another length is that callable's own mistake).

    Returns
    -------
    ndarray
        The value, float64, of ``shape``.

    Raises
    ------
    TypeError
        ``extra`` does not fit the callable's signature (naming ``args``, the signature and the
        call), or the value is None, a string, complex, boolean or not numeric.
    ValueError
        The callable raised a ValueError or IndexError at this first call (usually an ``x0`` of
        the wrong length: the message names ``x0`` and its length), the value has the wrong
        shape (naming the callable, and ``x0`` when the lengths disagree), or is not finite
        (:class:`~flapping.errors.NonFiniteError`).
    """
    n = x.size
    where = f"at its first call, {call} with t = {t!r} and `x0` of length {n}"
    try:
        raw = fun(t, x.copy(), *extra)
    except TypeError as exc:
        mismatch = _signature_mismatch(fun, t, x, extra)
        if mismatch is not None:
            raise TypeError(
                f"`{name}` cannot be called as {call} with {given} ({len(extra)} argument(s) "
                f"after t and x): {mismatch}; its signature is {_signature(fun)}") from exc
        exc.add_note(f"(raised by `{name}` {where})")
        raise
    except _SHAPE_ERRORS as exc:
        raise ValueError(
            f"`{name}` raised {type(exc).__name__} ({exc}) {where}: does it expect a state of "
            f"another length (check the length of `x0`) or other arguments (check {given})?"
        ) from exc
    except Exception as exc:  # the user's own error: kept as it is, with where it happened
        exc.add_note(f"(raised by `{name}` {where})")
        raise
    return _as_array(raw, name, shape, t, x, where, reshape, first)


def _as_array(raw: Any, name: str, shape: tuple[int, ...], t: float, x: np.ndarray,
              where: str, reshape: bool, first: bool) -> np.ndarray:
    """The value checked for type, shape and finiteness (see :func:`first_call`)."""
    value = numeric(raw, name, where, f"an array of real numbers of shape {shape}")
    if value.shape != shape:
        if reshape and value.size == math.prod(shape):
            value = value.reshape(shape)
        else:
            raise ValueError(f"`{name}` must return an array of shape {shape}, got shape "
                             f"{value.shape} {where}"
                             f"{_length_hint(name, value.shape, x.size) if first else ''}")
    check.finite_output(name, value, t, x)
    return value


def numeric(raw: Any, name: str, where: str, expected: str) -> np.ndarray:
    """``raw`` (a callable's value) as a float64 array, or a TypeError naming the callable.

    None, strings, ragged sequences, complex, boolean and other non-numeric values are refused
    (NumPy would turn None into NaN and drop an imaginary part with a mere warning).
    """
    if raw is None:
        raise TypeError(f"`{name}` returned None {where}; it must return {expected} (a missing "
                        f"`return`?)")
    if isinstance(raw, (str, bytes)):
        raise TypeError(f"`{name}` returned {check._show(raw)} ({type(raw).__name__}) {where}; "
                        f"it must return {expected}")
    try:
        value = np.asarray(raw)
    except ValueError:  # ragged nested sequences
        raise TypeError(f"`{name}` returned {check._show(raw)} {where}, which is not an array of "
                        f"numbers; it must return {expected}") from None
    if value.dtype.kind == "c":
        raise TypeError(f"`{name}` returned complex values ({value.dtype}) {where}; it must "
                        f"return {expected} (the integrators are real: write a complex state "
                        f"as its real and imaginary parts)")
    if value.dtype.kind not in "iuf":
        raise TypeError(f"`{name}` returned {check._show(raw)} (dtype {value.dtype}) {where}; it "
                        f"must return {expected}")
    return value.astype(float)


def _length_hint(name: str, got: tuple[int, ...], n: int) -> str:
    """A hint that ``x0``, not ``fun``, may be wrong: when ``fun`` returns another length.

    Only for ``fun``: the probes call ``fun`` first, so a ``jac`` of the wrong size is the
    Jacobian's own mistake (``fun`` accepted ``x0``)."""
    m = got[0] if len(got) == 1 else None
    if name == "fun" and m is not None and m != n:
        return (f"; if the system has {m} states, `x0` has the wrong length ({n}, expected "
                f"{m})")
    return ""


def _signature(fun: Callable[..., Any]) -> str:
    try:
        return f"{getattr(fun, '__name__', type(fun).__name__)}{inspect.signature(fun)}"
    except (TypeError, ValueError):
        return "not readable"


def _signature_mismatch(fun: Callable[..., Any], t: float, x: np.ndarray,
                        extra: tuple[Any, ...]) -> str | None:
    """Why ``fun(t, x, *extra)`` does not bind to ``fun``'s signature, or None if it does (or
    the signature cannot be read: a compiled function)."""
    try:
        signature = inspect.signature(fun)
    except (TypeError, ValueError):
        return None
    try:
        signature.bind(t, x, *extra)
    except TypeError as exc:
        return str(exc)
    return None


def probe_fields(funs: tuple[Any, ...], jacs: tuple[Any, ...], pjacs: tuple[Any, ...],
                 args: Any, x0: np.ndarray, params: np.ndarray | None, period: float,
                 breakpoints: tuple[float, ...]) -> tuple[Any, ...]:
    """Every segment's ``fun``, ``jac`` and ``param_jac`` once, at the segment's start time and
    ``x0``, checked by :func:`first_call`; returns ``args`` as a tuple.

    For the solvers that take ``fun(t, x, *args[, params])`` with one callable per segment of
    the period (``jacs``/``pjacs`` entries may be None).

    Raises
    ------
    ValueError, TypeError
        As :func:`first_call`, and for ``args`` that is not a sequence.
    """
    args = check.call_args(args)
    n = x0.size
    extra = args if params is None else args + (params,)
    tail = "" if params is None else ", params"
    given = f"`args` = {check._show(args)}" + ("" if params is None else " and `free_params`")
    n_p = 0 if params is None else params.size
    for k, (f, J, P) in enumerate(zip(funs, jacs, pjacs, strict=True)):
        t = period * (breakpoints[k - 1] if k else 0.0)
        first_call(f, "fun", t, x0, extra, (n,), call=f"fun(t, x, *args{tail})", given=given,
                   first=k == 0)
        if J is not None:
            first_call(J, "jac", t, x0, extra, (n, n), call=f"jac(t, x, *args{tail})",
                       given=given)
        if P is not None:
            first_call(P, "param_jac", t, x0, extra, (n, n_p), reshape=True,
                       call=f"param_jac(t, x, *args{tail})", given=given)
    return args

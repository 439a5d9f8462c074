"""Exceptions and warnings shared by the solvers of :mod:`flapping`.

- :class:`ConvergenceError`: a solver or an integration did not reach its answer;
  :func:`require_success` raises it for an integration result that failed. When an integration
  stopped at a time, it carries where: ``t``, ``state`` and ``source`` (what failed there).
- :class:`NonFiniteError`: a user callable returned NaN or infinity during an integration (a
  ValueError), with the time, the state, the callable's name and the value as attributes.
- :class:`DomainError`: an iterate left the domain of the model (a solver may step back);
- :class:`HoverDriftWarning`: a "hover" orbit that flies away horizontally (an offset hinge).
- :class:`PlausibilityWarning`: an insect whose magnitudes no insect or flapping vehicle has.
- :class:`ClosureWarning`: a monodromy matrix of a point that is not on a periodic orbit.
- :class:`AliasedPeriodWarning`: a period that is a multiple of the orbit's minimal period, or
  shooting residual points that sample the same phase twice.
- :class:`ToleranceWarning`: a tolerance below what float64 delivers, raised to the floor.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # an annotation only: results imports this module, not the reverse
    from flapping.results import Status

__all__ = ["ConvergenceError", "NonFiniteError", "DomainError", "HoverDriftWarning",
           "ClosureWarning", "AliasedPeriodWarning", "ToleranceWarning", "PlausibilityWarning",
           "caused_by_interrupt", "require_success"]


class ConvergenceError(RuntimeError):
    """A solver did not converge.

    Carries what a user needs to diagnose the failure instead of a silently wrong answer.

    Parameters
    ----------
    message : str
        What failed and why.
    x : array_like, optional
        The last iterate of the unknowns.
    residual : float, optional
        Norm of the residual at the last iterate.
    iterations : int, optional
        Number of iterations (or function evaluations, if the solver counts those) taken.
    result : object, optional
        The solver's full result object, when one exists.
    t : float, optional
        The time at which the failing integration stopped (the state blew up, the step budget
        ran out, the step size fell below rounding), when one did.
    state : array_like, optional
        The state of that integration at ``t``.
    source : str, optional
        What failed at ``t``: ``"state"`` (the solution overflowed), ``"fun"``, ``"jac"`` or
        ``"param_jac"`` (the callable returned NaN or infinity), ``"step budget"`` or
        ``"integrator"`` (the integrator gave up).
    status : Status, optional
        The outcome from the one status table (:class:`flapping.results.Status`), when the
        solver reports one.

    Attributes
    ----------
    x, residual, iterations, result, t, state, source, status
        As given (``None`` when not known); ``x`` and ``state`` are float64 copies.
    """

    def __init__(
        self,
        message: str,
        *,
        x: Any = None,
        residual: float | None = None,
        iterations: int | None = None,
        result: Any = None,
        t: float | None = None,
        state: Any = None,
        source: str | None = None,
        status: Status | None = None,
    ) -> None:
        details = []
        if residual is not None:
            details.append(f"residual norm {residual:.3e}")
        if iterations is not None:
            details.append(f"{iterations} iterations")
        full = message + (f" ({', '.join(details)})" if details else "")
        super().__init__(full)
        self.x = None if x is None else np.asarray(x, dtype=float).copy()
        self.residual = residual
        self.iterations = iterations
        self.result = result
        self.t = None if t is None else float(t)
        self.state = None if state is None else np.array(state, dtype=float)
        self.source = source
        self.status = status


def caused_by_interrupt(error: BaseException) -> bool:
    """True if ``error`` is, or was caused by, a Ctrl-C: a KeyboardInterrupt in its chain of
    causes and contexts (numba turns one raised inside compiled code into a SystemError that
    carries it)."""
    seen: set[int] = set()
    chain: BaseException | None = error
    while chain is not None and id(chain) not in seen:
        if isinstance(chain, KeyboardInterrupt):
            return True
        seen.add(id(chain))
        chain = chain.__cause__ or chain.__context__
    return False


class NonFiniteError(ValueError):
    """A user callable returned NaN or infinity at a finite state during an integration.

    A ValueError (the callable's value is what is wrong), raised at the first such evaluation,
    with where it happened as attributes, so that a caller (e.g. the hover layer) can attribute
    it: a field that overflows because the solution blows up has a huge ``state``; a field with
    a singularity (``1 / x`` at ``x = 0``) a moderate one.

    Parameters
    ----------
    message : str
        What failed, where (the message names the callable, ``t`` and the state).
    source : str
        The callable: ``"fun"``, ``"jac"`` or ``"param_jac"``.
    t : float
        The time of the evaluation.
    state : array_like
        The state at which it was evaluated.
    value : array_like
        What it returned.

    Attributes
    ----------
    source, t, state, value
        As given (``state`` and ``value`` as arrays).
    """

    def __init__(self, message: str, *, source: str, t: float, state: Any, value: Any) -> None:
        super().__init__(message)
        self.source = source
        self.t = float(t)
        self.state = np.array(state, dtype=float)
        self.value = np.array(value)


class DomainError(ConvergenceError):
    """An iterate of a solver left the domain on which the model is defined.

    For example a stroke amplitude beyond 90 deg, where the wings would cross. A
    :class:`ConvergenceError` (a solver that cannot step back ends with it); Newton on the
    fixed-step period map (:func:`flapping.periodic.fixedstep.find_periodic_orbit_fixed_step`)
    meets it by halving its step towards the last iterate it could evaluate.
    """


class HoverDriftWarning(UserWarning):
    """An orbit found as hover has a non-zero mean horizontal speed: it is not hover.

    The hover condition fixes the mean *vertical* speed only; with the half-period symmetry
    broken (a non-zero ``hinge_offset``) the orbit may fly forwards or backwards on average.
    Emitted by :func:`flapping.hover.find_hover_orbit`; see
    :attr:`flapping.hover.HoverOrbit.is_hover` for the tolerance.
    """


class ClosureWarning(RuntimeWarning):
    """The state after one period is not the initial state: the point is on no periodic orbit.

    Emitted by :func:`flapping.periodic.floquet.monodromy` when the relative closure error
    ``|x(T) - x(0)| / max(1, |x(0)|)`` exceeds
    :data:`flapping.periodic.floquet.CLOSURE_TOL`; the multipliers it returns are then those
    of a transition matrix, not of an orbit.
    """


class AliasedPeriodWarning(RuntimeWarning):
    """A period or a sampling that aliases.

    Emitted by :func:`flapping.periodic.shooting.find_periodic_orbit` and
    :func:`flapping.periodic.floquet.monodromy` when the orbit closes already at ``T / k`` (the
    period given or found is ``k`` times the minimal period: multipliers are then the ``k``-th
    powers of the orbit's), and by ``find_periodic_orbit`` when two of its residual points
    ``k delta`` fall on the same phase of the period (their residual rows repeat each other).
    """


class ToleranceWarning(RuntimeWarning):
    """A tolerance below what float64 can deliver was raised to the floor (as scipy does).

    See :mod:`flapping.periodic.settings` for the floors.
    """


class PlausibilityWarning(UserWarning):
    """A value is valid for the model but outside what any insect or flapping vehicle has.

    E.g. a 1e12 Hz wing beat: the equations still have a "hover" orbit, at a nonsense speed.
    Emitted by :class:`flapping.model.morphology.Insect`, whose ``PLAUSIBLE_RANGES`` lists the
    ranges; the message names the field, its value and the range.
    """


def require_success(result: Any, what: str) -> Any:
    """``result`` if the integration it reports reached its end, else a ConvergenceError.

    Parameters
    ----------
    result : object
        An integration result with ``success`` and ``message`` attributes (e.g. of
        :func:`flapping.periodic.integrate.flow`).
    what : str
        What was being integrated, for the message (e.g. ``"the averaged Jacobian"``).

    Returns
    -------
    object
        ``result`` itself.

    Raises
    ------
    ConvergenceError
        If ``result.success`` is false; the message names ``what`` and the solver's message, and
        ``t``, ``state``, ``source`` say where the integration stopped (from ``result.failure``,
        when the result has one).
    """
    if not result.success:
        where = getattr(result, "failure", None)
        raise ConvergenceError(f"{what}: the integration failed ({result.message})", result=result,
                               t=None if where is None else where.t,
                               state=None if where is None else where.state,
                               source=None if where is None else where.source)
    return result

"""Exceptions and warnings shared by the solvers of :mod:`flapping`.

- :class:`ConvergenceError`: a solver or an integration did not reach its answer;
  :func:`require_success` raises it for an integration result that failed.
- :class:`HoverDriftWarning`: a "hover" orbit that flies away horizontally (an offset hinge).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["ConvergenceError", "HoverDriftWarning", "require_success"]


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
    """

    def __init__(
        self,
        message: str,
        *,
        x: Any = None,
        residual: float | None = None,
        iterations: int | None = None,
        result: Any = None,
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


class HoverDriftWarning(UserWarning):
    """An orbit found as hover has a non-zero mean horizontal speed: it is not hover.

    The hover condition fixes the mean *vertical* speed only; with the half-period symmetry
    broken (a non-zero ``hinge_offset``) the orbit may fly forwards or backwards on average.
    Emitted by :func:`flapping.hover.find_hover_orbit`; see
    :attr:`flapping.hover.HoverOrbit.is_hover` for the tolerance.
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
        If ``result.success`` is false; the message names ``what`` and the solver's message.
    """
    if not result.success:
        raise ConvergenceError(f"{what}: the integration failed ({result.message})", result=result)
    return result

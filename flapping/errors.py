"""Exceptions shared by the solvers of :mod:`flapping`."""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["ConvergenceError"]


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

"""Dynamical systems with known periodic orbits, for validating :mod:`flapping.periodic.shooting`
and :mod:`flapping.periodic.floquet` (and for users who want to check their own tools the same way).

* :func:`lorenz` (Lorenz 1963): orbit AB, period 1.5586522107162 (Viswanath 2003).
* :func:`rossler` (Roessler 1976): period-1 orbit at a = b = 0.2, c = 5.7, T = 5.881088455554846
  (ChaosBook); Dednam & Botha's case a = 0.15, b = 0.2, c = 3.5.
* :func:`forced_oscillator`: a damped, harmonically forced linear oscillator whose periodic
  solution and Floquet multipliers are known in closed form (:func:`forced_oscillator_orbit`).

Each vector field follows the ``fun(t, x, *args)`` convention of :func:`scipy.integrate.solve_ivp`
and has its analytic Jacobian beside it.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = [
    "lorenz",
    "lorenz_jac",
    "rossler",
    "rossler_jac",
    "forced_oscillator",
    "forced_oscillator_jac",
    "forced_oscillator_orbit",
]


def _floats(x: Any) -> Any:
    # A float64 state of three: Python floats, the same IEEE arithmetic as NumPy scalars at a
    # fraction of the cost (these fields run at every stage of every integration of a
    # continuation). Anything else (a batch of states, other dtypes) is indexed as it comes.
    if type(x) is np.ndarray and x.dtype is _FLOAT64 and x.ndim == 1 and x.size == 3:
        return x.tolist()
    return x[0], x[1], x[2]


_FLOAT64 = np.dtype(np.float64)  # NumPy's built-in dtypes are singletons: `is` compares them


def lorenz(t: float, x: Any, sigma: float = 10.0, rho: float = 28.0,
           beta: float = 8.0 / 3.0) -> np.ndarray:
    """Lorenz (1963) vector field; trace of its Jacobian is ``-(sigma + 1 + beta)``.

    Parameters
    ----------
    t : float
        Time (unused: autonomous).
    x : array_like, shape (3,)
        State.
    sigma, rho, beta : float, optional
        The classical parameters 10, 28, 8/3.

    Returns
    -------
    ndarray, shape (3,)
    """
    x0, x1, x2 = _floats(x)
    return np.array([sigma * (x1 - x0), x0 * (rho - x2) - x1, x0 * x1 - beta * x2])


def lorenz_jac(t: float, x: Any, sigma: float = 10.0, rho: float = 28.0,
               beta: float = 8.0 / 3.0) -> np.ndarray:
    """Jacobian of :func:`lorenz`.

    Parameters
    ----------
    t : float
        Time (unused: autonomous).
    x : array_like, shape (3,)
        State.
    sigma, rho, beta : float, optional
        As in :func:`lorenz`.

    Returns
    -------
    ndarray, shape (3, 3)
    """
    x0, x1, x2 = _floats(x)
    return np.array([[-sigma, sigma, 0.0], [rho - x2, -1.0, -x0], [x1, x0, -beta]])


def rossler(t: float, x: Any, a: float = 0.2, b: float = 0.2, c: float = 5.7) -> np.ndarray:
    """Roessler (1976) vector field.

    Parameters
    ----------
    t : float
        Time (unused: autonomous).
    x : array_like, shape (3,)
        State.
    a, b, c : float, optional
        Parameters (ChaosBook's 0.2, 0.2, 5.7).

    Returns
    -------
    ndarray, shape (3,)
    """
    x0, x1, x2 = _floats(x)
    return np.array([-x1 - x2, x0 + a * x1, b + x2 * (x0 - c)])


def rossler_jac(t: float, x: Any, a: float = 0.2, b: float = 0.2, c: float = 5.7) -> np.ndarray:
    """Jacobian of :func:`rossler`.

    Parameters
    ----------
    t : float
        Time (unused: autonomous).
    x : array_like, shape (3,)
        State.
    a, b, c : float, optional
        As in :func:`rossler`.

    Returns
    -------
    ndarray, shape (3, 3)
    """
    x0, _, x2 = _floats(x)
    return np.array([[0.0, -1.0, -1.0], [1.0, a, 0.0], [x2, 0.0, x0 - c]])


def _scalar(value: Any) -> float:
    # Free parameters arrive as 1-element arrays; fixed ones as numbers.
    return float(np.asarray(value, dtype=float).reshape(-1)[0])


def forced_oscillator(t: float, x: Any, zeta: float, omega0: float, omega: float,
                      amplitude: Any) -> np.ndarray:
    """Damped, harmonically forced linear oscillator ``y'' + 2 zeta w0 y' + w0^2 y = A cos(W t)``.

    Parameters
    ----------
    t : float
        Time.
    x : array_like, shape (2,)
        State ``(y, y')``.
    zeta, omega0, omega : float
        Damping ratio, natural and forcing angular frequencies.
    amplitude : float or array_like of one element
        Forcing amplitude ``A`` (a 1-element array when it is a free parameter of shooting).

    Returns
    -------
    ndarray, shape (2,)
    """
    a = _scalar(amplitude)
    return np.array([x[1], a * math.cos(omega * t) - 2.0 * zeta * omega0 * x[1] - omega0**2 * x[0]])


def forced_oscillator_jac(t: float, x: Any, zeta: float, omega0: float, omega: float,
                          amplitude: Any) -> np.ndarray:
    """Jacobian of :func:`forced_oscillator` (constant).

    Parameters
    ----------
    t, x, zeta, omega0, omega, amplitude
        As in :func:`forced_oscillator`.

    Returns
    -------
    ndarray, shape (2, 2)
    """
    return np.array([[0.0, 1.0], [-omega0**2, -2.0 * zeta * omega0]])


def forced_oscillator_orbit(zeta: float, omega0: float, omega: float,
                            amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    """Closed forms for :func:`forced_oscillator`: periodic state at t = 0 and Floquet multipliers.

    The periodic solution is ``y(t) = Re(A H e^{i W t})``, ``H = 1 / (w0^2 - W^2 + 2 i zeta w0 W)``;
    the multipliers are ``exp(lambda T)`` for the roots ``lambda`` of ``s^2 + 2 zeta w0 s + w0^2``
    and ``T = 2 pi / W``.

    Parameters
    ----------
    zeta, omega0, omega, amplitude : float
        As in :func:`forced_oscillator`.

    Returns
    -------
    x0 : ndarray, shape (2,)
        ``(y(0), y'(0))`` on the periodic solution.
    multipliers : ndarray, shape (2,), complex
        Sorted by modulus, then argument (descending).
    """
    H = 1.0 / (omega0**2 - omega**2 + 2j * zeta * omega0 * omega)
    x0 = np.array([(amplitude * H).real, (1j * omega * amplitude * H).real])
    lam = np.roots([1.0, 2.0 * zeta * omega0, omega0**2]).astype(complex)
    mu = np.exp(lam * 2.0 * math.pi / omega)
    order = np.lexsort((-np.angle(mu), -np.abs(mu)))
    return x0, mu[order]

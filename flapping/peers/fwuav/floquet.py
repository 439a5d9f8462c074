"""FWUAV's hover orbits and their Floquet exponents, computed with :mod:`flapping.periodic`.

The right-hand side of :class:`~flapping.peers.fwuav.model.FwuavHover` does not depend on the
position, so the velocity ``v`` is a forced system of its own, periodic with the wing beat
``T = 1 / f``. We find its periodic orbit by shooting (:func:`flapping.periodic.shooting.
find_periodic_orbit`, started at FWUAV's stored velocity ``x_dot0``), then integrate the
variational equations of the full state ``(x, v)`` over one period (:func:`flapping.periodic.
floquet.monodromy`, analytic Jacobian). Three multipliers are exactly 1 (position enters
nothing): the three zero exponents. Mirror symmetry decouples the lateral velocity ``v_2``
(one exponent) from the longitudinal ``v_1, v_3`` (two).

FWUAV's kinematics make the position drift by a small amount per period (their optimiser held
the mean velocity to zero only within its tolerance). The position is then periodic in a frame
moving with the mean velocity ``v_mean``; we integrate ``(x - v_mean t, v)``, whose Jacobian is
the same, so that the state returns to itself and the monodromy matrix is that of an orbit.
``HoverFloquet.mean_velocity`` reports the drift.

FWUAV's own exponents (``floquet_stability.m``) come from the linearised equations integrated by
MATLAB's ``ode45`` (``RelTol = AbsTol = 1e-6``) along its stored trajectory, over two periods
from its optimiser's initial state, with the period map read between the 251st and the 751st of
1001 output points; ``log|mu| f``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

import flapping._validation as check
from flapping.backends import AUTO, Adaptive, as_backend
from flapping.errors import ConvergenceError, require_success
from flapping.peers.fwuav.data import SPECIES, Species, species
from flapping.peers.fwuav.model import FwuavHover
from flapping.periodic.floquet import monodromy
from flapping.periodic.integrate import flow
from flapping.periodic.shooting import find_periodic_orbit

__all__ = ["HoverFloquet", "hover_floquet", "fwuav_procedure", "NAMES"]

#: The insects FWUAV stores hover exponents for.
NAMES: tuple[str, ...] = tuple(SPECIES)


@dataclass(frozen=True)
class HoverFloquet:
    """The periodic hover orbit of one FWUAV insect and its Floquet exponents.

    Attributes
    ----------
    name : str
        The insect.
    x0 : ndarray, shape (6,)
        Initial state ``(x, v)`` of the orbit at ``t = 0`` (m, m/s; inertial, ``e3`` down).
    period : float
        ``1 / f`` (s).
    exponents : ndarray, shape (6,), complex
        Floquet exponents (1/s), sorted by real part, descending.
    multipliers : ndarray, shape (6,), complex
        ``exp(exponents * period)``, same order.
    longitudinal : ndarray, shape (2,), complex
        The two exponents of the ``(v_1, v_3)`` block, real part descending (1/s).
    lateral : complex
        The exponent of ``v_2`` (1/s).
    stored_longitudinal : ndarray, shape (2,)
        FWUAV's longitudinal exponents (1/s), same order.
    stored_lateral : float
        FWUAV's lateral exponent (1/s).
    relative_difference : ndarray, shape (3,)
        ``|ours - FWUAV's| / |FWUAV's|`` for the two longitudinal exponents, then the lateral.
    residual_norm : float
        Shooting residual ``|v(T) - v(0)|`` (m/s).
    closure_error : float
        ``|state(T) - state(0)|`` of the monodromy integration in the co-moving frame.
    mean_velocity : ndarray, shape (3,)
        Mean velocity over a period (m/s): the drift of FWUAV's kinematics.
    liouville_error : float
        Relative mismatch of ``det M`` and ``exp(int trace J)``.
    nfev : int
        Right-hand-side evaluations (shooting and monodromy).
    monodromy : ndarray, shape (6, 6)
        The monodromy matrix.
    """

    name: str
    x0: np.ndarray
    period: float
    exponents: np.ndarray
    multipliers: np.ndarray
    longitudinal: np.ndarray
    lateral: complex
    stored_longitudinal: np.ndarray
    stored_lateral: float
    relative_difference: np.ndarray
    residual_norm: float
    closure_error: float
    mean_velocity: np.ndarray
    liouville_error: float
    nfev: int
    monodromy: np.ndarray = field(repr=False)

    def __post_init__(self) -> None:
        for value in vars(self).values():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)


def _velocity_orbit(model: FwuavHover, rtol: float) -> tuple[np.ndarray, float, int]:
    """The periodic velocity (FWUAV's ``x_dot0`` as the guess): ``v(0)``, residual, nfev."""
    guess = np.array(model.species.velocity_guess)
    orbit = find_periodic_orbit(model.velocity_rhs, guess, model.period, autonomous=False,
                                jac=model.velocity_jacobian, rtol=rtol, atol=rtol * 1e-1)
    return orbit.x0, orbit.residual_norm, orbit.nfev


def _split(exponents: np.ndarray, M: np.ndarray, T: float
           ) -> tuple[np.ndarray, complex]:
    """Longitudinal pair and lateral exponent from the velocity block of the monodromy."""
    block = M[3:6, 3:6]
    coupling = np.abs(block[[0, 2]][:, 1]).max() + np.abs(block[1, [0, 2]]).max()
    if coupling > 1e-8 * np.abs(block).max():
        raise ConvergenceError(f"the lateral velocity is coupled to the longitudinal ones "
                               f"(|M_lat,long| = {coupling:.2e}): the orbit is not symmetric")
    pair = np.log(np.linalg.eigvals(block[np.ix_([0, 2], [0, 2])]).astype(complex)) / T
    return pair[np.argsort(-pair.real)], complex(np.log(complex(block[1, 1])) / T)


def _relative(ours: np.ndarray, theirs: np.ndarray) -> np.ndarray:
    return np.abs(ours - theirs) / np.abs(theirs)


def _build(sp: Species, rtol: float, quadrature: str, n_strips: int, body_rate_term: str
           ) -> HoverFloquet:
    if sp.morphology.coefficients != "sane-dickinson":
        raise ConvergenceError(
            f"the {sp.name}'s fitted lift does not vanish at a strip's stroke reversal, so the "
            "force jumps hundreds of times a wingbeat and adaptive integration at these "
            "tolerances stalls there (tried: the step budget runs out); its orbit needs event "
            "location or a fixed-step integrator, not written yet", iterations=0)
    model = FwuavHover(sp, n_strips=n_strips, quadrature=quadrature,
                       body_rate_term=body_rate_term)
    T = model.period
    v0, residual, nfev = _velocity_orbit(model, rtol)
    x0 = np.concatenate([np.zeros(3), v0])
    path = require_success(flow(model.rhs, (0.0, T), x0, rtol=rtol, atol=rtol * 1e-1),
                           "the position over one period")
    drift = (path.x[0:3, -1] - x0[0:3]) / T
    shift = np.concatenate([drift, np.zeros(3)])

    def comoving(t: float, x: np.ndarray) -> np.ndarray:
        return model.rhs(t, x) - shift

    mono = monodromy(comoving, x0, T, jac=model.jac, rtol=rtol, atol=rtol * 1e-1)
    order = np.argsort(-mono.exponents.real, kind="stable")
    longitudinal, lateral = _split(mono.exponents, mono.matrix, T)
    stored = np.array(sp.stored_exponents)
    ours = np.concatenate([longitudinal.real, [lateral.real]])
    return HoverFloquet(
        name=sp.name, x0=x0, period=T, exponents=mono.exponents[order],
        multipliers=mono.multipliers[order], longitudinal=longitudinal, lateral=lateral,
        stored_longitudinal=stored[3:5], stored_lateral=float(stored[5]),
        relative_difference=_relative(ours, stored[3:6]), residual_norm=float(residual),
        closure_error=float(mono.closure_error), mean_velocity=drift,
        liouville_error=float(mono.liouville_error), nfev=nfev + path.nfev + mono.nfev,
        monodromy=mono.matrix)


@lru_cache(maxsize=32)
def _cached(name: str, rtol: float, quadrature: str, n_strips: int, body_rate_term: str
            ) -> HoverFloquet:
    return _build(species(name), rtol, quadrature, n_strips, body_rate_term)


def hover_floquet(name: str, *, backend: Adaptive | str = Adaptive.name,
                  rtol: float | None = None, quadrature: str = "fwuav", n_strips: int = 50,
                  body_rate_term: str = "fwuav") -> HoverFloquet:
    """The hover orbit of FWUAV's insect ``name`` and its six Floquet exponents.

    Parameters
    ----------
    name : str
        ``hawkmoth``, ``bumblebee``, ``fruit_fly`` or ``monarch``.
    backend : "adaptive" or Adaptive, optional
        The path (:mod:`flapping.backends`): FWUAV's model runs on the adaptive one only; its
        ``rtol`` is every integration's (default :class:`~flapping.backends.Adaptive`'s).
    rtol : float, optional
        Shorthand for ``backend``'s ``rtol``: relative tolerance of every integration, in
        [1e-13, 1e-3] (absolute: ``rtol / 10``).
    quadrature : {"fwuav", "gauss"}, optional
        Span quadrature of the aerodynamic force (FWUAV's by default).
    n_strips : int, optional
        Span points per wing, in [2, 10000] (FWUAV: 50).
    body_rate_term : {"fwuav", "rotated"}, optional
        The body-rate term of the strip velocity (see :class:`FwuavHover`); FWUAV's by default.

    Returns
    -------
    HoverFloquet
        Orbit, exponents sorted by real part (three zeros, then the others), FWUAV's stored
        exponents and the relative differences. Results are cached per argument set.

    Raises
    ------
    ValueError
        For an unknown name or an argument out of range.
    ConvergenceError
        If the shooting does not converge (carries the residual and the iterations), an
        integration fails, or the lateral motion is not decoupled; at once for the monarch,
        whose discontinuous force adaptive integration cannot cross (see the chapter "A second
        model").
    """
    species(name)
    spec = as_backend(backend)
    if spec == AUTO:
        spec = Adaptive()
    if not isinstance(spec, Adaptive):
        raise ValueError(f"hover_floquet runs FWUAV's model on the adaptive path only; got "
                         f"backend={backend!r}")
    rtol = spec.rtol if rtol is None else rtol
    # any real type (float32, int, 0-d array) is accepted and converted to float
    rtol = check.real("rtol", rtol, low=1e-13, high=1e-3)
    FwuavHover(name, n_strips=n_strips, quadrature=quadrature,
               body_rate_term=body_rate_term)  # checks the three
    return _cached(name, float(rtol), quadrature, int(n_strips), body_rate_term)


def fwuav_procedure(name: str, *, rtol: float = 1e-6, start: Any = None) -> np.ndarray:
    """FWUAV's own way to its exponents (``floquet_stability.m``), re-run on our model.

    The state and the variational equations, perturbations ``1e-8 I``, integrated over two
    periods with a Dormand-Prince 5(4) pair (scipy's ``RK45``, the pair of MATLAB's ``ode45``)
    at ``rtol = atol``, output on 1001 equally spaced points; the period map is read between the
    251st and the 751st point, ``B = D(T/2)^-1 D(3T/2)``; exponents ``log|eig| f``.

    Parameters
    ----------
    name : str
        One of :data:`NAMES`. The monarch's force jumps at every strip's stroke reversal: its
        Jacobian comes from central differences, and tight tolerances cost many steps.
    rtol : float, optional
        Tolerance, in [1e-12, 1e-3] (FWUAV: 1e-6).
    start : array_like, shape (3,), optional
        Initial velocity (m/s); default FWUAV's ``x_dot0``, which is not on the periodic orbit.

    Returns
    -------
    ndarray, shape (3,)
        The two longitudinal exponents (descending) and the lateral one (1/s).

    Raises
    ------
    ValueError
        For an unknown name or ``rtol`` out of range.
    ConvergenceError
        If the integration fails.
    """
    sp = species(name)
    # any real type (float32, int, 0-d array) is accepted and converted to float
    rtol = check.real("rtol", rtol, low=1e-12, high=1e-3)
    model = FwuavHover(sp)
    v0 = np.array(sp.velocity_guess) if start is None else check.vector("start", start, size=3)
    f = sp.kinematics.f
    t = np.linspace(0.0, 2.0 / f, 1001)

    def augmented(time: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([model.rhs(time, y[:6]),
                               (model.jac(time, y[:6]) @ y[6:].reshape(6, 6)).ravel()])

    y0 = np.concatenate([np.zeros(3), v0, (1e-8 * np.eye(6)).ravel()])
    sol = solve_ivp(augmented, (t[0], t[-1]), y0, method="RK45", t_eval=t, rtol=rtol,
                    atol=rtol)
    if not sol.success:
        raise ConvergenceError(f"FWUAV's procedure: the integration failed ({sol.message})")
    D = sol.y[6:].T.reshape(-1, 6, 6)
    block = np.linalg.solve(D[250], D[750])[3:6, 3:6]
    pair = np.log(np.abs(np.linalg.eigvals(block[np.ix_([0, 2], [0, 2])]))) * f
    return np.array([*np.sort(pair)[::-1], np.log(abs(block[1, 1])) * f])

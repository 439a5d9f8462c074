"""Hover and its Floquet stability in six degrees of freedom.

With both wings flapping alike the plane of symmetry is invariant: the hover orbit of the
six-degree-of-freedom insect (:class:`~flapping.model.sixdof.SixDofDynamics`) is the planar orbit
with v = p = r = roll = 0. :func:`find_sixdof_hover_orbit` therefore starts from the planar orbit
(found on any backend of :func:`~flapping.hover.orbit.find_hover_orbit`), embeds it, and solves the
eight-state periodicity with zero net descent again by shooting (adaptive DOP853), so that the
orbit returned is a solution of the six-degree-of-freedom equations to their own residual.

:func:`sixdof_stability` integrates the variational equations of the eight states over one
period (:func:`flapping.periodic.floquet.monodromy`, central-difference Jacobians): the eight
Floquet multipliers of (u, v, w, p, q, r, roll, theta), with :attr:`SixDofStability.longitudinal`
and :attr:`SixDofStability.lateral` views. Heading and position are left out: they do not feed
back (each would add a multiplier 1).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from flapping import _validation
from flapping.backends import AUTO, Adaptive, Backend, Compiled, as_backend
from flapping.errors import ConvergenceError
from flapping.hover._schema import OrbitViews, StabilityViews
from flapping.hover.orbit import _find_hover_orbit, register_sixdof
from flapping.model import _sixdof_generated
from flapping.model.kinematics import segment_stroke_sign
from flapping.model.morphology import Insect
from flapping.model.sixdof import (
    LATERAL,
    LONGITUDINAL,
    SIXDOF_AERODYNAMIC_MODELS,
    SIXDOF_STATE_NAMES,
    SixDofDynamics,
    body_inertia,
)
from flapping.periodic._readonly import freeze, readonly
from flapping.periodic.floquet import Monodromy, floquet_multipliers, monodromy
from flapping.periodic.integrate import flow
from flapping.periodic.shooting import PeriodicOrbit, find_periodic_orbit
from flapping.results import Floquet, Stats, Status

__all__ = ["SixDofHoverOrbit", "SixDofStability", "ModeSet", "find_sixdof_hover_orbit",
           "sixdof_stability", "embed"]

#: The analysis's integration tolerances. Looser than the planar analysis's 1e-12: the variational
#: equations use central-difference Jacobians (rounding ~1e-10 relative), and at rtol 1e-12 the
#: step control chases that noise (the hawkmoth's monodromy took 1.4 million evaluations against
#: 0.15 million at 3e-11, for a change below 1e-9 in every multiplier). At 3e-11 the hawkmoth's
#: error estimate is 1.9e-9 (1.5e-8 at 1e-10) for 9 % more evaluations.
ANALYSIS_RTOL = 3e-11
ANALYSIS_ATOL = 3e-11
#: The second analysis, for the error estimate, loosens both tolerances by this factor.
ERROR_FACTOR = 10.0
#: The compiled path (linear loads): DOP853 steps per half-stroke of the Newton solve; the
#: analysis runs at twice as many, its error estimate the difference from Newton's last
#: monodromy, and doubles the steps (to at most COMPILED_MAX_STEPS) while that exceeds
#: :attr:`flapping.backends.Compiled.multiplier_tol`. At 24/48 steps the hawkmoth's estimate is
#: ~1e-10 and Liouville's check ~1e-9 (its fastest lateral mode decays by 1e-11 a period: at
#: 16/32 steps Liouville's check, set by that multiplier's relative error, was 2.7e-8).
COMPILED_STEPS = 24
COMPILED_MAX_STEPS = 512


def embed(x4: Any) -> np.ndarray:
    """The planar state (u, w, q, theta) as the eight-state one, lateral states zero."""
    x = np.zeros(8)
    x[list(LONGITUDINAL)] = np.asarray(x4, dtype=float)
    return x


@dataclass(frozen=True)
class SixDofHoverOrbit(OrbitViews):
    """The hover orbit of the insect in six degrees of freedom.

    It has every attribute of the planar :class:`~flapping.hover.orbit.HoverOrbit`, with the
    same meaning (:mod:`flapping.hover._schema`: :attr:`status`, :attr:`is_hover`,
    :attr:`solver`, :attr:`floquet`, the error estimates, ...; its states are the eight), and
    adds its own views (:attr:`planar`, :attr:`amplitude_change`, :attr:`n_steps`,
    :attr:`newton_monodromy`).

    Attributes
    ----------
    insect : Insect
        The insect, its mean stroke angle the orbit's (a trim of the planar solve).
    aerodynamics : str
        ``"small-angle"``, ``"exact"`` or ``"linear"``.
    alpha_m : float
        Mean geometric angle of attack [rad] (the planar orbit's).
    x0 : ndarray, shape (8,)
        (u, v, w, p, q, r, roll, theta) at t = 0.
    amplitude : float
        Stroke amplitude Phi [rad].
    planar : HoverOrbit
        The planar orbit it started from.
    shooting : PeriodicOrbit or None
        The six-degree-of-freedom shooting result, or None where the embedded planar orbit
        already met the residual tolerance (one flow over a period showed it).
    residual_norm : float
        Norm of the eight-state periodicity and altitude residual.
    amplitude_change : float
        Phi of this orbit minus the planar orbit's [rad] (zero to the solvers' tolerances:
        the plane of symmetry is invariant).
    stats : Stats
    solve_status : Status
    dof : int
        6.
    backend : str
        ``"adaptive"`` (the Python path: adaptive DOP853) or ``"compiled"`` (the linear loads'
        compiled path, :mod:`flapping.fast._sixdof`); :func:`sixdof_stability` analyses the
        orbit on the same path by default.
    n_steps : int or None
        The compiled path's DOP853 steps per half-stroke of its Newton solve (None on the
        adaptive path).
    newton_monodromy : ndarray, shape (8, 8), or None
        The compiled path's monodromy at ``n_steps`` where Newton last formed its Jacobian (at
        the solution, or one converged step from it): the coarse analysis of
        :func:`sixdof_stability`'s error estimate, which therefore also bounds that step's
        effect.
    """

    insect: Insect
    aerodynamics: str
    alpha_m: float
    x0: np.ndarray
    amplitude: float
    planar: Any = field(repr=False)
    shooting: PeriodicOrbit | None = field(repr=False)
    residual_norm: float
    amplitude_change: float
    stats: Stats = field(repr=False)
    solve_status: Status = Status.SUCCESS
    dof: int = 6
    backend: str = "adaptive"
    n_steps: int | None = None
    newton_monodromy: np.ndarray | None = field(default=None, repr=False)

    state_names: ClassVar[tuple[str, ...]] = SIXDOF_STATE_NAMES
    #: x(t + T/2) = S x(t): the fore-aft reflection flips u, q, theta and the yaw rate r.
    half_period_symmetry: ClassVar[np.ndarray] = np.diag([-1.0, 1.0, 1.0, 1.0, -1.0, -1.0, 1.0,
                                                          -1.0])

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period

    @property
    def model(self) -> SixDofDynamics:
        """The six-degree-of-freedom model at the orbit's amplitude."""
        return SixDofDynamics(self.insect, self.amplitude, self.alpha_m, self.aerodynamics)

    @property
    def success(self) -> bool:
        """True: a returned orbit solved its equations (a failed solve raises)."""
        return self.solve_status.success

    # ------------------------------------------------------------------ the planar schema
    @property
    def problem(self) -> Any:
        """The planar :class:`~flapping.hover.problem.HoverProblem` its start was solved as."""
        return self.planar.problem

    @property
    def stroke_mean(self) -> float:
        """Mean stroke angle phi_bar [rad] (the planar solve's trim where it is one)."""
        return self.insect.stroke_mean

    @property
    def trims(self) -> tuple[str, ...]:
        """The planar solve's trim unknowns (the eight-state solve frees only Phi)."""
        return tuple(self.planar.trims)

    @property
    def nit(self) -> int:
        """Newton (or Levenberg-Marquardt) iterations of the eight-state solve."""
        return self.stats.nit

    @property
    def nfev(self) -> int:
        """Right-hand-side evaluations of the eight-state solve."""
        return self.stats.nfev

    @property
    def solver(self) -> Backend:
        """The backend object of the path that solved the eight-state equations, with its
        options (:mod:`flapping.backends`)."""
        if self.backend == "compiled":
            return Compiled(n_steps=self.n_steps or COMPILED_STEPS)
        return Adaptive()

    @cached_property
    def _sampled(self) -> tuple[np.ndarray, np.ndarray, float]:
        n = self.planar.x.shape[1] - 1  # the planar orbit's samples per period
        model = self.model
        t = np.linspace(0.0, self.period, n + 1)
        y = flow(_fields(model), (0.0, self.period), np.append(self.x0, 0.0),
                 breakpoints=model.breakpoints, period=self.period, rtol=Adaptive.rtol,
                 atol=Adaptive.atol, t_eval=t, args=(self.amplitude,)).x
        return readonly(t), readonly(np.array(y[:8], dtype=float)), float(y[8, -1])

    @property
    def samples(self) -> Any:
        """A callable giving one period's (t, x), as :attr:`HoverOrbit.samples`."""
        return lambda: self._sampled[:2]

    @property
    def t(self) -> np.ndarray:
        """One period's sample times [s] (uniform, as many as the planar orbit's; integrated
        on first use)."""
        return self._sampled[0]

    @property
    def x(self) -> np.ndarray:
        """The eight states at :attr:`t`, shape (8, len(t))."""
        return self._sampled[1]

    @property
    def z_drift(self) -> float:
        """Net descent z(T) - z(0) over one period [m] (0 to the solver's tolerance)."""
        return self._sampled[2]

    @cached_property
    def mean_inertial_velocity(self) -> dict[str, float]:
        """Cycle means of the inertial velocities [m/s] from the samples: ``forward``, ``climb``
        (up positive) and ``side`` (starboard positive)."""
        velocity = np.array([_sixdof_generated.earth_velocity(*x) for x in self.x[:, :-1].T])
        forward, side, down = velocity.mean(axis=0)
        return {"forward": float(forward), "climb": float(-down), "side": float(side)}

    @property
    def floquet(self) -> Floquet | None:
        """The monodromy of the eight states from the solve's last Newton integration (the
        compiled path); None on the adaptive path (:func:`sixdof_stability` computes them)."""
        if self.newton_monodromy is None:
            return None
        return Floquet.of_matrix(self.newton_monodromy, self.period)

    #: The planar paths' own results: none on the six-degree-of-freedom paths.
    kernel: ClassVar[None] = None
    fixed_step: ClassVar[None] = None
    model_given: ClassVar[None] = None
    mean_velocity: ClassVar[None] = None
    #: The solve's error estimates: none on either six-degree-of-freedom path (NaN, as the
    #: planar adaptive path's).
    amplitude_error: ClassVar[float] = math.nan
    x0_error: ClassVar[float] = math.nan
    multiplier_error: ClassVar[float] = math.nan


def _fields(model: SixDofDynamics) -> list[Any]:
    """Per half-stroke: the eight states and the descent z, with the amplitude a parameter."""
    funs = model.segment_functions()

    def augmented(f: Any) -> Any:
        def field_(t: float, y: np.ndarray, amplitude: Any) -> np.ndarray:
            out = np.empty(9)
            out[:8] = f(t, y[:8], float(np.asarray(amplitude).reshape(-1)[0]))
            out[8] = _sixdof_generated.earth_velocity(*y[:8])[2]  # the descent
            return out
        return field_

    return [augmented(f) for f in funs]


def find_sixdof_hover_orbit(insect: Insect, *, aerodynamics: str = "small-angle",
                            backend: Backend | str = AUTO, tol: float | None = None,
                            planar_orbit: Any = None, **planar: Any) -> SixDofHoverOrbit:
    """The hover orbit in six degrees of freedom (see the module docstring).

    Parameters
    ----------
    insect : Insect
        With its roll and yaw inertia (:func:`~flapping.model.sixdof.body_inertia`).
    aerodynamics : {"small-angle", "exact", "linear"}
        The loads (:data:`~flapping.model.sixdof.SIXDOF_AERODYNAMIC_MODELS`); ``"linear"`` is
        the paper's eq. (29) in six degrees of freedom.
    backend
        The planar solve's backend (:func:`~flapping.hover.orbit.find_hover_orbit`); the
        eight-state solve is adaptive shooting.
    tol : float, optional
        Residual tolerance of both solves (default the adaptive path's).
    planar_orbit : HoverOrbit, optional
        The planar orbit of this insect and aerodynamic model to start from (e.g. found by
        continuation); default: solved here. With ``trims=("amplitude", "stroke_mean")`` the
        mean stroke angle stays the planar orbit's (the eight-state solve frees only Phi).
    **planar
        Further keywords of the planar :func:`~flapping.hover.orbit.find_hover_orbit`
        (``alpha_m``, ``amplitude_guess``, ``x0_guess`` of 4 values, ``n_samples``).

    Returns
    -------
    SixDofHoverOrbit

    Raises
    ------
    ValueError
        For bad arguments, or an insect without roll or yaw inertia.
    ConvergenceError
        If either solve fails.
    """
    started = time.perf_counter()
    body_inertia(insect)  # refuse an insect without its lateral inertia before any work
    if aerodynamics not in SIXDOF_AERODYNAMIC_MODELS:
        raise ValueError(
            f"`aerodynamics` must be one of {SIXDOF_AERODYNAMIC_MODELS} with dof=6; got "
            f"{aerodynamics!r}")
    spec = as_backend(backend)
    compiled = aerodynamics == "linear" and (isinstance(spec, str) or spec.sixdof_compiled)
    if tol is not None:
        planar["tol"] = tol
    if planar_orbit is None:
        # the planar entry (below this module), without the deprecation of the options it
        # forwards
        flat = _find_hover_orbit(insect, aerodynamics=aerodynamics, backend=backend, **planar)
    else:
        flat = planar_orbit
        # The planar orbit does not depend on the lateral inertia: compare the rest.
        lateral = {name: getattr(insect, name) for name in
                   ("roll_inertia", "yaw_inertia", "roll_yaw_product")}
        if (flat.model.aerodynamics != aerodynamics
                or flat.model.insect.with_(stroke_mean=insect.stroke_mean, **lateral) != insect):
            raise ValueError("`planar_orbit` must be an orbit of the same insect and "
                             "aerodynamic model")
    trimmed = insect if flat.stroke_mean == insect.stroke_mean else insect.with_(
        stroke_mean=flat.stroke_mean)
    model = SixDofDynamics(trimmed, flat.amplitude, flat.alpha_m, aerodynamics)
    path = Adaptive()
    tol = path.tol if tol is None else tol
    if compiled:
        return _compiled_orbit(model, flat, tol, started)
    y0 = np.concatenate([embed(flat.x0), [0.0]])
    funs = _fields(model)
    # The plane of symmetry is invariant: the embedded planar orbit usually satisfies the
    # eight-state equations already, and one flow shows it; shooting only if it does not.
    end = flow(funs, (0.0, model.period), y0, breakpoints=model.breakpoints,
               period=model.period, rtol=path.rtol, atol=path.atol, args=(flat.amplitude,))
    residual = float(np.linalg.norm(np.asarray(end.x)[:, -1] - y0))
    if residual <= tol:
        stats = Stats(nit=0, nfev=int(end.nfev), njev=0, time=time.perf_counter() - started)
        return SixDofHoverOrbit(insect=trimmed, aerodynamics=aerodynamics, alpha_m=flat.alpha_m,
                                x0=readonly(embed(flat.x0)), amplitude=flat.amplitude,
                                planar=flat, shooting=None, residual_norm=residual,
                                amplitude_change=0.0, stats=stats)
    result = find_periodic_orbit(
        funs, y0, model.period, autonomous=False, free_params=[flat.amplitude], fixed=(8,),
        breakpoints=model.breakpoints, method=path.method, jacobian="finite-difference",
        rtol=path.rtol, atol=path.atol, tol=tol)
    if not result.success:
        raise ConvergenceError(
            f"six-degree-of-freedom hover did not converge from the planar orbit: residual "
            f"{result.residual_norm:.3e} after {result.nfev} evaluations ({result.message})")
    amplitude = float(np.asarray(result.params).reshape(-1)[0])
    x0 = readonly(np.array(result.x0[:8], dtype=float))
    stats = Stats(nit=int(getattr(result, "nit", 0) or 0), nfev=int(result.nfev),
                  njev=0, time=time.perf_counter() - started)
    return SixDofHoverOrbit(insect=trimmed, aerodynamics=aerodynamics, alpha_m=flat.alpha_m,
                            x0=x0, amplitude=amplitude, planar=flat, shooting=result,
                            residual_norm=float(result.residual_norm),
                            amplitude_change=amplitude - flat.amplitude, stats=stats)


def _compiled_orbit(model: SixDofDynamics, flat: Any, tol: float,
                    started: float) -> SixDofHoverOrbit:
    """Newton on the compiled path (:mod:`flapping.fast._sixdof`) from the embedded planar orbit.

    The linear loads with massless or massive wings; the step count is
    :data:`COMPILED_STEPS` (the stability analysis checks it against half as many).
    """
    from flapping.fast import _sixdof  # compiles on first use

    x0, amplitude, end, residual, nit, nfev = _sixdof.newton(
        model, embed(flat.x0), flat.amplitude, COMPILED_STEPS, tol)
    if not residual <= tol or not 0.0 < amplitude <= 0.5 * math.pi:
        raise ConvergenceError(
            f"six-degree-of-freedom hover (compiled path) did not converge from the planar "
            f"orbit: residual {residual:.3e}, amplitude {amplitude!r} rad after {nit} Newton "
            "iterations")
    stats = Stats(nit=nit, nfev=nfev, njev=0, time=time.perf_counter() - started)
    if amplitude != model.amplitude:
        model = model.with_amplitude(amplitude)
    return SixDofHoverOrbit(insect=model.insect, aerodynamics=model.aerodynamics,
                            alpha_m=flat.alpha_m, x0=readonly(x0), amplitude=amplitude,
                            planar=flat, shooting=None, residual_norm=residual,
                            amplitude_change=amplitude - flat.amplitude, stats=stats,
                            backend="compiled", n_steps=COMPILED_STEPS,
                            newton_monodromy=readonly(end[9:81].reshape(9, 8)[:8].copy()))



register_sixdof(find_sixdof_hover_orbit)  # find_hover_orbit(..., dof=6)

@dataclass(frozen=True)
class ModeSet:
    """The multipliers of one decoupled subsystem (longitudinal or lateral).

    Attributes
    ----------
    names : tuple of str
        Its states.
    monodromy : ndarray, shape (4, 4)
        The diagonal block of the full monodromy.
    multipliers : ndarray, complex, shape (4,)
        The block's eigenvalues, by descending modulus.
    period : float
        T [s] (NaN where it was not given).
    """

    names: tuple[str, ...]
    monodromy: np.ndarray
    multipliers: np.ndarray
    period: float = math.nan

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def floquet(self) -> Floquet:
        """The block and its multipliers as the package's one type
        (:class:`flapping.results.Floquet`)."""
        return Floquet.of_matrix(self.monodromy, self.period, multipliers=self.multipliers)


@dataclass(frozen=True)
class SixDofStability(StabilityViews):
    """Floquet stability of the six-degree-of-freedom hover orbit.

    It has every attribute of the planar :class:`~flapping.hover.stability.HoverStability`,
    with the same meaning over the eight states (:attr:`exponents`, :attr:`eigenvectors`,
    :attr:`det`, :attr:`liouville_det`, :attr:`trace_integral`, :attr:`averaged_jacobian`,
    :attr:`is_stable`, :attr:`unstable_mode`, ...), and adds its views (:attr:`longitudinal`,
    :attr:`lateral`, :attr:`coupling`, :attr:`details`).

    Attributes
    ----------
    orbit : SixDofHoverOrbit
    monodromy : ndarray, shape (8, 8)
        In the order (u, v, w, p, q, r, roll, theta).
    multipliers : ndarray, complex, shape (8,)
        All eight, by descending modulus.
    floquet : Floquet
        The monodromy's :class:`~flapping.results.Floquet` view (exponents, Liouville).
    longitudinal, lateral : ModeSet
        The diagonal blocks of (u, w, q, theta) and (v, p, r, roll).
    coupling : float
        Largest entry of the off-diagonal blocks over the largest entry of the monodromy: zero
        to the finite-difference Jacobian's rounding (~1e-10) for symmetric flapping (the two
        sets decouple).
    multiplier_error : float
        Largest change of a multiplier when the analysis is repeated at tolerances
        :data:`ERROR_FACTOR` times looser: an estimate of the error of that looser analysis,
        so (for a regular convergence) a bound on this one's.
    liouville_error : float
        Relative difference of det M and exp(int_0^T trace J dt).
    details : Monodromy
        The integration's result (factors, evaluations).
    """

    orbit: SixDofHoverOrbit
    monodromy: np.ndarray
    multipliers: np.ndarray
    floquet: Floquet
    longitudinal: ModeSet
    lateral: ModeSet
    coupling: float
    multiplier_error: float
    liouville_error: float
    details: Monodromy = field(repr=False)

    def __post_init__(self) -> None:
        freeze(self)

    # ------------------------------------------------------------------ the planar schema
    @property
    def exponents(self) -> np.ndarray:
        """Floquet exponents log(mu)/T [1/s] (principal branch; -inf for a multiplier 0)."""
        return self.floquet.exponents

    @cached_property
    def eigenvectors(self) -> np.ndarray:
        """Column k is the eigenvector of the monodromy for ``multipliers[k]`` (from eig(M),
        matched by nearest eigenvalue, as the planar analysis's)."""
        values, vectors = np.linalg.eig(self.monodromy)
        match = [int(np.argmin(np.abs(values - mu))) for mu in self.multipliers]
        return readonly(vectors[:, match].astype(complex))

    @property
    def det(self) -> float:
        """det M (from the integration's factors where it has them)."""
        return float(self.details.det)

    @property
    def liouville_det(self) -> float:
        """exp(int_0^T trace J dt): equal to :attr:`det` by Liouville's formula."""
        return float(self.details.liouville_det)

    @property
    def trace_integral(self) -> float:
        """int_0^T trace J dt along the orbit."""
        return float(self.details.trace_integral)

    @cached_property
    def averaged_jacobian(self) -> np.ndarray:
        """(1/T) int_0^T J(t, x(t)) dt along the orbit, shape (8, 8): the first-order averaged
        system (central-difference Jacobians at 32 Gauss-Legendre nodes per half-stroke,
        computed on first use)."""
        return readonly(_averaged(self.orbit, _AVERAGE_NODES)[1])

    @property
    def averaged_eigenvalues(self) -> np.ndarray:
        """Eigenvalues of :attr:`averaged_jacobian` [1/s], by real part (descending)."""
        eig = np.linalg.eigvals(self.averaged_jacobian).astype(complex)
        return readonly(eig[np.argsort(-eig.real, kind="stable")])


def _block(matrix: np.ndarray, index: tuple[int, ...], names: tuple[str, ...],
           period: float) -> ModeSet:
    block = readonly(np.array(matrix[np.ix_(index, index)]))
    return ModeSet(names=names, monodromy=block, multipliers=readonly(floquet_multipliers(block)),
                   period=period)


def _compiled_monodromy(orbit: SixDofHoverOrbit, n_steps: int) -> Monodromy:
    """The monodromy of the compiled path at ``n_steps`` per half-stroke, as a Monodromy."""
    from flapping.fast import _sixdof

    model = orbit.model
    factors, end, trace_integral = _sixdof.monodromy_factors(model, orbit.x0, orbit.amplitude,
                                                             n_steps)
    matrix = np.eye(8)
    for i in range(factors.shape[2]):
        matrix = factors[:, :, i] @ matrix
    multipliers = floquet_multipliers(matrix)
    # The product of the factors' determinants: det M itself loses the digits of its tiny
    # multiplier.
    det = float(np.prod([np.linalg.det(factors[:, :, i]) for i in range(factors.shape[2])]))
    liouville = math.exp(trace_integral)
    x_end = end[:8].copy()
    closure = float(np.linalg.norm(x_end - orbit.x0))
    return Monodromy(
        matrix=readonly(matrix), multipliers=readonly(multipliers),
        exponents=readonly(np.log(multipliers.astype(complex)) / model.period), det=det,
        trace_integral=trace_integral, liouville_det=liouville,
        liouville_error=abs(det - liouville) / abs(liouville), x_end=readonly(x_end),
        closure_error=closure, period=model.period, factors=readonly(factors),
        multiplier_method="eig", nfev=2 * n_steps * _sixdof.N_STAGES, njev=0,
        relative_closure_error=closure / max(1.0, float(np.linalg.norm(orbit.x0))))


def sixdof_stability(orbit: SixDofHoverOrbit, *, rtol: float | None = None,
                     atol: float | None = None, backend: str = AUTO) -> SixDofStability:
    """The eight Floquet multipliers of a six-degree-of-freedom hover orbit.

    Parameters
    ----------
    orbit : SixDofHoverOrbit
    rtol, atol : float, optional
        Integration tolerances of the variational equations (default :data:`ANALYSIS_RTOL`,
        :data:`ANALYSIS_ATOL`); a second analysis at :data:`ERROR_FACTOR` times both gives
        :attr:`SixDofStability.multiplier_error`.

    backend : {"auto", "compiled", "adaptive"}
        ``"auto"``: the orbit's own path (:attr:`SixDofHoverOrbit.backend`); ``"compiled"``
        for an orbit of the linear loads only (the analysis at :attr:`SixDofHoverOrbit.n_steps`
        steps per half-stroke, or more: doubled until the multipliers at half the steps differ
        by at most :attr:`flapping.backends.Compiled.multiplier_tol`; ``rtol`` and ``atol`` do
        not apply); ``"adaptive"``: the Python path.

    Returns
    -------
    SixDofStability

    Raises
    ------
    ValueError
        If ``backend`` is ``"compiled"`` for an orbit of the blade-element loads.
    """
    backend = _validation.choice("backend", backend, (AUTO, "compiled", "adaptive"))
    if backend == "compiled" and orbit.aerodynamics != "linear":
        raise ValueError("`backend='compiled'` analyses six-degree-of-freedom orbits of the "
                         "linear loads only; this orbit's are "
                         f"{orbit.aerodynamics!r}: use the adaptive path")
    if backend == "compiled" or (backend == AUTO and orbit.backend == "compiled"):
        return _compiled_stability(orbit)
    model = orbit.model
    funs = model.segment_functions()
    rtol = ANALYSIS_RTOL if rtol is None else rtol
    atol = ANALYSIS_ATOL if atol is None else atol

    def analysed(factor: float) -> Monodromy:
        return monodromy(funs, orbit.x0, model.period, breakpoints=model.breakpoints,
                         rtol=factor * rtol, atol=factor * atol, args=(orbit.amplitude,))

    result, loose = analysed(1.0), analysed(ERROR_FACTOR)
    error = float(np.max(np.abs(np.asarray(result.multipliers) - np.asarray(loose.multipliers))))
    return _stability_of(orbit, result, error)


def _compiled_stability(orbit: SixDofHoverOrbit) -> SixDofStability:
    """:func:`sixdof_stability` on the compiled path (see there)."""
    n_steps = 2 * (orbit.n_steps or COMPILED_STEPS)
    if orbit.newton_monodromy is not None:
        coarse = floquet_multipliers(orbit.newton_monodromy)
    else:
        coarse = _compiled_monodromy(orbit, n_steps // 2).multipliers
    while True:
        result = _compiled_monodromy(orbit, n_steps)
        error = float(np.max(np.abs(np.sort_complex(result.multipliers)
                                    - np.sort_complex(coarse))))
        if error <= Compiled.multiplier_tol or 2 * n_steps > COMPILED_MAX_STEPS:
            break
        coarse, n_steps = result.multipliers, 2 * n_steps
    return _stability_of(orbit, result, error)


def _stability_of(orbit: SixDofHoverOrbit, result: Monodromy, error: float) -> SixDofStability:
    """The result object of a monodromy and its multipliers' error estimate."""
    matrix = np.asarray(result.matrix)
    lon, lat = list(LONGITUDINAL), list(LATERAL)
    off = max(np.max(np.abs(matrix[np.ix_(lon, lat)])), np.max(np.abs(matrix[np.ix_(lat, lon)])))
    return SixDofStability(
        orbit=orbit, monodromy=readonly(matrix.copy()),
        multipliers=readonly(np.asarray(result.multipliers)),
        floquet=Floquet.of_matrix(matrix, orbit.period, multipliers=result.multipliers,
                                  trace_integral=float(result.trace_integral)),
        longitudinal=_block(matrix, LONGITUDINAL, ("u", "w", "q", "theta"), orbit.period),
        lateral=_block(matrix, LATERAL, ("v", "p", "r", "roll"), orbit.period),
        coupling=float(off / np.max(np.abs(matrix))), multiplier_error=error,
        liouville_error=float(result.liouville_error), details=result)


#: The lateral stability derivatives, in the order of :attr:`LateralDerivatives.dimensional`.
LATERAL_DERIVATIVE_NAMES: tuple[str, ...] = ("Yv", "Yp", "Yr", "Lv", "Lp", "Lr", "Nv", "Np",
                                             "Nr")


@dataclass(frozen=True)
class LateralDerivatives:
    """The cycle-averaged lateral system of a six-degree-of-freedom hover orbit.

    Attributes
    ----------
    dimensional : dict of str to float
        Y_v [N s/m], Y_p, Y_r [N s], L_v, N_v [N s], L_p, L_r, N_p, N_r [N m s]: the cycle means
        of the derivatives of the aerodynamic side force and roll and yaw moments (about the
        centre of gravity, body axes) in v, p and r.
    nondimensional : dict of str to float
        The same in the form of Sun's group (as :mod:`flapping.studies.cfd` for the longitudinal
        ones): reference speed U = 2 Phi_pp f r2 R (Phi_pp = 2 Phi the peak-to-peak amplitude),
        length c (mean chord), time T = 1/f, area S = 2 R c; v+ = v/U, p+ = p T, r+ = r T; the
        force over 0.5 rho U^2 S, the moments over 0.5 rho U^2 S c.
    jacobian : ndarray, shape (4, 4)
        The lateral block (v, p, r, roll) of the cycle-averaged Jacobian of the right-hand side.
    eigenvalues : ndarray, complex, shape (4,)
        Its eigenvalues [1/s], by descending real part: the averaged lateral system's modes.
    """

    dimensional: dict[str, float]
    nondimensional: dict[str, float]
    jacobian: np.ndarray
    eigenvalues: np.ndarray

    def __post_init__(self) -> None:
        freeze(self)


def _central_jacobian(f: Any, x: np.ndarray, n_out: int, step: float = 1e-6) -> np.ndarray:
    """df/dx by central differences, steps step * max(1, |x_j|)."""
    out = np.empty((n_out, x.size))
    for j in range(x.size):
        h = step * max(1.0, abs(x[j]))
        plus, minus = x.copy(), x.copy()
        plus[j] += h
        minus[j] -= h
        out[:, j] = (np.asarray(f(plus)) - np.asarray(f(minus))) / (2.0 * h)
    return out


#: Gauss-Legendre nodes per half-stroke of :attr:`SixDofStability.averaged_jacobian`.
_AVERAGE_NODES = 32


def _averaged(orbit: SixDofHoverOrbit, n_average: int) -> tuple[np.ndarray, np.ndarray]:
    """The cycle means of the lateral load derivatives (3 x 3: Y, L, N in v, p, r) and of the
    right-hand side's Jacobian (8 x 8), central differences at ``n_average`` Gauss-Legendre
    nodes per half-stroke."""
    model = orbit.model
    T = model.period
    nodes, weights = np.polynomial.legendre.leggauss(n_average)
    loads_sum, jac_sum = np.zeros((3, 3)), np.zeros((8, 8))
    funs = model.segment_functions()
    halves = ((0.0, 0.5 * T), (0.5 * T, T))
    times = np.concatenate([0.5 * (b - a) * nodes + 0.5 * (a + b) for a, b in halves])
    states = flow(funs, (0.0, T), orbit.x0, breakpoints=model.breakpoints, period=T,
                  rtol=Adaptive.rtol, atol=Adaptive.atol, t_eval=times,
                  args=(orbit.amplitude,)).x
    for i, (t, x) in enumerate(zip(times, states.T, strict=True)):
        k = i // n_average  # the half-stroke: its stroke sign and its field
        sign = segment_stroke_sign(k)
        w = 0.5 * weights[i % n_average] / 2.0  # (T/2)/2 per node over T
        loads = _central_jacobian(
            lambda y, t=t, sign=sign: model._loads(t, list(y), sign, orbit.amplitude), x, 6)
        loads_sum += w * loads[np.ix_([1, 3, 5], [1, 3, 5])]
        jac_sum += w * _central_jacobian(
            lambda y, t=t, f=funs[k]: f(t, y, orbit.amplitude), x, 8)
    return loads_sum, jac_sum


def averaged_lateral(orbit: SixDofHoverOrbit, n_average: int = 32) -> LateralDerivatives:
    """The cycle-averaged lateral derivatives and the averaged lateral system of an orbit.

    The loads' and the right-hand side's Jacobians (central differences) at ``n_average``
    Gauss-Legendre nodes per half-stroke (the integrand is smooth within one), averaged over the
    period.

    Parameters
    ----------
    orbit : SixDofHoverOrbit
    n_average : int
        Nodes per half-stroke, in [1, 4096].

    Returns
    -------
    LateralDerivatives
    """
    n_average = _validation.integer("n_average", n_average, low=1, high=4096)
    lat = list(LATERAL)
    loads_sum, jac_sum = _averaged(orbit, n_average)
    dimensional = dict(zip(LATERAL_DERIVATIVE_NAMES, loads_sum.ravel().tolist(), strict=True))
    jacobian = readonly(jac_sum[np.ix_(lat, lat)].copy())
    eig = np.linalg.eigvals(jacobian).astype(complex)
    return LateralDerivatives(dimensional=dimensional,
                              nondimensional=_nondimensional(orbit, dimensional),
                              jacobian=jacobian,
                              eigenvalues=readonly(eig[np.argsort(-eig.real, kind="stable")]))


def _nondimensional(orbit: SixDofHoverOrbit, d: dict[str, float]) -> dict[str, float]:
    """Sun's group's form of the lateral derivatives (see :class:`LateralDerivatives`)."""
    insect = orbit.insect
    T, c, R = insect.period, insect.mean_chord, insect.semi_span
    U = 2.0 * (2.0 * orbit.amplitude) * insect.frequency * insect.r2 * R
    S = 2.0 * R * c
    q = 0.5 * insect.air_density * U * U * S
    # (force or moment scale, state scale): v+ = v/U, p+ = p T, r+ = r T.
    load = {"Y": q, "L": q * c, "N": q * c}
    state = {"v": 1.0 / U, "p": T, "r": T}
    return {name: value / load[name[0]] / state[name[1]] for name, value in d.items()}

"""Optimized shooting (flapping.periodic.shooting), validated against literature and closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flapping.errors import ConvergenceError
from flapping.periodic.floquet import monodromy, nontrivial_multipliers
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import (
    forced_oscillator,
    forced_oscillator_jac,
    forced_oscillator_orbit,
    lorenz,
    lorenz_jac,
    rossler,
    rossler_jac,
)

# Literature values. Viswanath (2003) gives the Lorenz orbit AB to 14 digits; ChaosBook the Roessler
# period-1 orbit to 16; Dednam & Botha (2015, Table 1 case) the period to 13. Our integrations at
# rtol = 1e-11 reproduce periods to ~1e-12 relative, so 1e-9 is a margin of 1000, not a fit.
T_AB = 1.5586522107162
X_AB = np.array([-13.763610682134, -19.578751942452, 27.0])
T_ROSSLER = 5.881088455554846
T_DEDNAM = 5.920340248194
DEDNAM_ARGS = (0.15, 0.2, 3.5)
DEDNAM_GUESS = [2.7002161609, 3.4723025491, 3.0]


@pytest.mark.parametrize("perturbation", [(0.04, -0.02, 0.002), (-0.3, 0.4, -0.02), (0.5, 0.5, 0.03)])
def test_lorenz_orbit_ab_from_perturbed_guesses(perturbation):
    # z = 27 held fixed (Poincare section through Viswanath's point); rough guesses converge.
    dx, dy, dT = perturbation
    guess = np.round(X_AB, 1) + [dx, dy, 0.0]
    orbit = find_periodic_orbit(lorenz, guess, round(T_AB, 2) + dT, fixed=[2], jac=lorenz_jac)
    assert orbit.success and orbit.residual_norm <= 1e-10
    assert abs(orbit.period / T_AB - 1.0) <= 1e-9
    np.testing.assert_allclose(orbit.x0, X_AB, atol=1e-8)  # Viswanath's 12 decimals, margin 100


def test_roessler_period_one_orbit_matches_chaosbook():
    orbit = find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, fixed=[0], jac=rossler_jac)
    assert abs(orbit.period / T_ROSSLER - 1.0) <= 1e-9


def test_dednam_botha_table1_case():
    # x3 held fixed, the paper's guess; T and the largest non-trivial multiplier modulus (0.812252,
    # six digits given) are reproduced.
    orbit = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92030065, fixed=[2], jac=rossler_jac,
                                args=DEDNAM_ARGS)
    assert abs(orbit.period / T_DEDNAM - 1.0) <= 1e-10
    mon = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, args=DEDNAM_ARGS)
    largest = np.max(np.abs(nontrivial_multipliers(mon)))
    assert abs(largest - 0.812252) <= 1e-6


def test_variational_and_finite_difference_jacobians_find_the_same_orbit():
    # Two independent Jacobians (variational equations vs differenced residual), same orbit:
    # agreement to the integration accuracy (periods ~1e-12; 1e-10 with margin).
    kw = dict(fixed=[2], args=DEDNAM_ARGS)
    a = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, jacobian="variational", **kw)
    b = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, jacobian="finite-difference", **kw)
    assert abs(a.period - b.period) <= 1e-10 * a.period
    np.testing.assert_allclose(a.x0, b.x0, atol=1e-9)
    assert a.jacobian == "variational" and b.jacobian == "finite-difference"


def test_paper_method_rk4_reaches_rk4_accuracy():
    # The paper's configuration (FD Jacobian, RK4 at 2^-10): the period is limited by RK4's
    # truncation error, O(h^4) with h = T/1024; on this orbit that is below 1e-10 relative.
    orbit = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, fixed=[2], args=DEDNAM_ARGS,
                                jacobian="finite-difference", method="RK4")
    assert abs(orbit.period / T_DEDNAM - 1.0) <= 1e-10
    assert orbit.method == "RK4"


def test_history_and_counters_are_consistent():
    orbit = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, fixed=[2], jac=rossler_jac,
                                args=DEDNAM_ARGS)
    assert orbit.iteration_history[0] > 1e-3 > 1e-10 >= orbit.iteration_history[-1]
    assert len(orbit.residual_history) == orbit.n_residual_evals
    assert orbit.nfev > 0 and orbit.njev > 0


FORCED = (0.1, 1.0, 1.3)  # zeta, omega0, Omega


def test_forced_oscillator_periodic_solution_and_multipliers():
    # Non-autonomous: T = 2 pi / Omega is known; the periodic solution and the multipliers
    # exp(lambda T) have closed forms (1e-10: integration at 1e-11 on an O(1) solution).
    A = 0.7
    x_exact, mu_exact = forced_oscillator_orbit(*FORCED, A)
    T = 2 * math.pi / FORCED[2]
    orbit = find_periodic_orbit(forced_oscillator, [0.0, 0.0], T, autonomous=False,
                                jac=forced_oscillator_jac, args=FORCED + (A,))
    assert orbit.period == T
    np.testing.assert_allclose(orbit.x0, x_exact, atol=1e-10)
    mon = monodromy(forced_oscillator, orbit.x0, T, jac=forced_oscillator_jac, args=FORCED + (A,))
    np.testing.assert_allclose(mon.multipliers, mu_exact, atol=1e-10)


@pytest.mark.parametrize("jacobian", ["variational", "finite-difference"])
def test_free_parameter_with_extra_residual(jacobian):
    # Free forcing amplitude A and the extra condition y(0) = target: A = target / Re(H) exactly.
    A_true = 0.7
    x_exact, _ = forced_oscillator_orbit(*FORCED, A_true)
    orbit = find_periodic_orbit(
        forced_oscillator, [0.0, 0.0], 2 * math.pi / FORCED[2], autonomous=False, args=FORCED,
        free_params=[1.0], extra_residual=lambda x, T, p: [x[0] - x_exact[0]], jacobian=jacobian,
    )
    assert abs(orbit.params[0] - A_true) <= 1e-9
    np.testing.assert_allclose(orbit.x0, x_exact, atol=1e-10)


def test_segment_callables_free_param_and_fixed_state_like_the_hover_problem():
    # The hover engineer's configuration: forced, two half-period callables (jump at T/2),
    # a free parameter (forcing level q), a fixed "altitude" state h with h' = x - 0.1, whose
    # periodicity h(T) = h(0) is the zero-net-drift condition fixing q.
    # x' = -a x + q s(t), s = +1 then -1: periodic x has mean 0 for any q... so use bias b:
    # x' = -a x + q (s(t) + b): mean(x) = q b / a, and h periodic <=> q = 0.1 a / b.
    a, b, T = 1.3, 0.5, 2.0

    def half(sign):
        def f(t, x, p):
            return np.array([-a * x[0] + p[0] * (sign + b), x[0] - 0.1])
        return f

    orbit = find_periodic_orbit([half(1.0), half(-1.0)], [0.0, 0.0], T, autonomous=False,
                                breakpoints=(0.5,), free_params=[1.0], fixed=[1])
    q = 0.1 * a / b
    E = math.exp(-a * T / 2)
    # Periodic x(0) for x' = -a x + q (s + b): superposition of the square wave and the bias.
    x0_exact = -q * (1 - E) / (a * (1 + E)) + q * b / a
    assert abs(orbit.params[0] - q) <= 1e-9
    assert abs(orbit.x0[0] - x0_exact) <= 1e-10
    assert orbit.x0[1] == 0.0  # fixed component untouched


def test_no_periodic_orbit_autonomous_raises_convergence_error():
    # x' = 1 has no periodic orbit; the residual T can only shrink towards the trivial T -> 0.
    with pytest.raises(ConvergenceError) as info:
        find_periodic_orbit(lambda t, x: np.ones(2), [0.0, 0.0], 1.0, n_points=2)
    err = info.value
    assert err.x is not None and err.residual is not None and err.iterations is not None
    assert err.result is not None and not err.result.success


def test_unbounded_drift_forced_system_raises_convergence_error():
    # x' = 1 + cos t: every solution drifts by 2 pi per period; residual constant, no orbit.
    with pytest.raises(ConvergenceError) as info:
        find_periodic_orbit(lambda t, x: np.array([1.0 + math.cos(t)]), [0.0], 2 * math.pi,
                            autonomous=False)
    assert info.value.residual == pytest.approx(2 * math.pi, rel=1e-8)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(period=-1.0), r"`period` must be a real number in \(0, inf\)"),
        (dict(period=math.nan), r"`period` must be a real number in \(0, inf\)"),
        (dict(x0=[[1.0, 2.0, 3.0]]), "`x0` must be a non-empty 1-D array"),
        (dict(x0=[1.0, math.inf, 3.0]), "`x0` must be finite"),
        (dict(fixed=[3]), r"`fixed` must be a sequence of distinct integer indices in \[0, 3\)"),
        (dict(fixed=[0, 0]), "distinct"),
        (dict(n_points=0), r"`n_points` must be an integer in \[1, 1024\]"),
        (dict(breakpoints=(0.5,)), "autonomous=False"),
        (dict(jacobian="broyden"), "`jacobian` must be one of"),
        (dict(delta=1.5), r"`delta` must be a real number in \(0, 1\)"),
        (dict(tol=0.0), "`tol`"),
    ],
)
def test_bad_arguments_raise_valueerror(kwargs, match):
    base = dict(x0=[1.0, 1.0, 20.0], period=1.5, fixed=[2])
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        find_periodic_orbit(lorenz, base.pop("x0"), base.pop("period"), **base)


def test_too_few_residuals_is_a_valueerror():
    # Forced, two states and one free parameter, one residual block and no extra residual:
    # two equations for three unknowns (the plain autonomous call no longer is such a case).
    with pytest.raises(ValueError, match="too few residuals"):
        find_periodic_orbit(lambda t, x, p: -x + p[0], [0.0, 0.0], 1.0, autonomous=False,
                            free_params=[1.0])


def test_wrong_fun_output_shape_raises_valueerror():
    with pytest.raises(ValueError, match="`fun` must return an array of shape"):
        find_periodic_orbit(lambda t, x: np.zeros(2), [1.0, 1.0, 1.0], 1.0, fixed=[0])


@settings(max_examples=30, deadline=None)
@given(
    n_points=st.integers(min_value=-3, max_value=0),
    index=st.integers().filter(lambda i: not 0 <= i < 3),
)
def test_invalid_n_points_and_fixed_indices_always_rejected(n_points, index):
    with pytest.raises(ValueError, match="`n_points`"):
        find_periodic_orbit(lorenz, [1.0, 1.0, 20.0], 1.5, fixed=[2], n_points=n_points)
    with pytest.raises(ValueError, match="`fixed`"):
        find_periodic_orbit(lorenz, [1.0, 1.0, 20.0], 1.5, fixed=[index])


# ---- no false successes ------------------------------------------------------------------------


def van_der_pol(t, x):
    return np.array([x[1], (1.0 - x[0] ** 2) * x[1] - x[0]])


# Van der Pol (mu = 1) limit-cycle period, 6.6632868593231 (e.g. Strogatz; to 13 digits).
T_VDP = 6.6632868593231


def test_van_der_pol_equilibrium_is_refused():
    # Issue 7's reproducer: it returned x0 ~ 1e-29 (the equilibrium) with success=True.
    with pytest.raises(ConvergenceError, match="equilibrium") as info:
        find_periodic_orbit(van_der_pol, [0.1, 0.0], 6.66, fixed=[1])
    assert not info.value.result.success


def test_roessler_equilibrium_is_refused():
    # Issue 7's reproducer: n_points=2 converged to the equilibrium near the origin.
    with pytest.raises(ConvergenceError, match="equilibrium") as info:
        find_periodic_orbit(rossler, [0.1, 5.0, 3.6], 5.0, n_points=2)
    assert not info.value.result.success


def test_van_der_pol_limit_cycle_is_found():
    # The genuine orbit from a reasonable guess, x[1] = 0 held: T to 1e-10 (integration 1e-11).
    orbit = find_periodic_orbit(van_der_pol, [2.0, 0.0], 6.6, fixed=[1])
    assert abs(orbit.period / T_VDP - 1.0) <= 1e-10
    assert abs(orbit.x0[0] - 2.0086198608) <= 1e-9  # amplitude where x' = 0


def test_plain_autonomous_call_chooses_and_reports_a_phase_condition():
    # find_periodic_orbit(fun, x0, period) on an autonomous system: it raised "too few
    # residuals" before. At (1.5, 1) the field is (1, -2.75): x[1] is held, and said so.
    orbit = find_periodic_orbit(van_der_pol, [1.5, 1.0], 6.6)
    assert abs(orbit.period / T_VDP - 1.0) <= 1e-10
    assert orbit.x0[1] == 1.0
    assert orbit.phase_condition.startswith("fixed: x[1]") and "chosen" in orbit.phase_condition


def test_phase_condition_of_user_choices_is_reported():
    kw = dict(args=DEDNAM_ARGS, jac=rossler_jac)
    fixed = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, fixed=[2], **kw)
    assert fixed.phase_condition == "fixed: x[2] held at the guess"
    A = 0.7
    forced = find_periodic_orbit(forced_oscillator, [0.0, 0.0], 2 * math.pi / FORCED[2],
                                 autonomous=False, args=FORCED + (A,))
    assert forced.phase_condition.startswith("none: the period is known")


# ---- no hangs ----------------------------------------------------------------------------------


def test_nan_from_fun_is_a_valueerror_not_a_hang():
    with pytest.raises(ValueError, match="`fun` returned a non-finite value"):
        find_periodic_orbit(lambda t, x: np.full(2, np.nan), [1.0, 1.0], 1.0)


def test_nan_during_the_iteration_is_a_valueerror_naming_fun():
    # Finite at the guess, NaN later in the period (at t >= 0.5): the integration names it.
    def f(t, x):
        return -x + math.cos(t) if t < 0.5 else np.full(1, np.nan)

    with pytest.raises(ValueError, match="`fun` returned a non-finite value at t = 0.5"):
        find_periodic_orbit(f, [0.0], 1.0, autonomous=False)


def test_nan_from_jac_is_a_valueerror_naming_jac():
    with pytest.raises(ValueError, match="`jac` returned a non-finite value"):
        find_periodic_orbit(lorenz, [1.0, 1.0, 20.0], 1.5, fixed=[2],
                            jac=lambda t, x: np.full((3, 3), np.nan))


def test_stiff_forced_problem_fails_early_with_advice():
    with pytest.raises(ConvergenceError, match="method='Radau'"):
        find_periodic_orbit(lambda t, x: -1e9 * (x - np.cos(t)), [1.0], 2 * math.pi,
                            autonomous=False)


# ---- conventions -------------------------------------------------------------------------------


def test_counters_are_named_as_scipy_and_only_so():
    orbit = find_periodic_orbit(rossler, DEDNAM_GUESS, 5.92, fixed=[2], jac=rossler_jac,
                                args=DEDNAM_ARGS)
    assert orbit.nit > 0 and orbit.nfev > 0 and orbit.njev > 0
    for old in ("iterations", "n_rhs_evals", "n_jac_evals"):  # one name per concept
        assert not hasattr(orbit, old)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(period=True), "`period`"),
        (dict(period="1.5"), "`period`"),
        (dict(x0=[True, False, True]), "`x0`"),
        (dict(n_points=1.0), "`n_points`"),
        (dict(autonomous=1), "`autonomous`"),
        (dict(tol=True), "`tol`"),
        (dict(max_steps=-1), "`max_steps`"),
    ],
)
def test_bools_and_strings_are_refused(kwargs, match):
    base = dict(x0=[1.0, 1.0, 20.0], period=1.5, fixed=[2])
    base.update(kwargs)
    with pytest.raises(ValueError, match=match):
        find_periodic_orbit(lorenz, base.pop("x0"), base.pop("period"), **base)


def test_numpy_float32_inputs_are_converted():
    orbit = find_periodic_orbit(rossler, np.array(DEDNAM_GUESS, np.float32), np.float32(5.92),
                                fixed=[np.int64(2)], jac=rossler_jac, args=DEDNAM_ARGS)
    assert orbit.x0.dtype == np.float64 and isinstance(orbit.period, float)
    # the guess's x3 was rounded to float32, so compare with a looser 1e-6 (float32 eps ~ 6e-8)
    assert abs(orbit.period / T_DEDNAM - 1.0) <= 1e-6


# ---- multiple shooting (issue 8) ---------------------------------------------------------------

MULTIFLAP_GUESS = [0.1, 5.0, 3.6]  # multiflap's Roessler example: T = 5, c = 5.7


def test_multiple_shooting_converges_from_multiflaps_roessler_guess():
    # 30 segments started on the guess's own trajectory: the ChaosBook orbit (rtol = 1e-11 gives
    # periods to ~1e-12, margin 1000)
    orbit = find_periodic_orbit(rossler, MULTIFLAP_GUESS, 5.0, jac=rossler_jac, segments=30)
    assert orbit.success and orbit.segments == 30
    assert orbit.segment_states.shape == (3, 30)
    assert abs(orbit.period / T_ROSSLER - 1.0) <= 1e-9
    np.testing.assert_array_equal(orbit.segment_states[:, 0], orbit.x0)


def test_single_shooting_with_fixed_x0_stalls_from_multiflaps_guess():
    # the failure multiple shooting is compared with in the chapter: a local minimum ~7e-2
    with pytest.raises(ConvergenceError) as info:
        find_periodic_orbit(rossler, MULTIFLAP_GUESS, 5.0, jac=rossler_jac, fixed=[0])
    assert 1e-2 < info.value.residual < 0.2


def test_one_segment_is_single_shooting_bit_for_bit():
    a = find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, fixed=[0], jac=rossler_jac)
    b = find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, fixed=[0], jac=rossler_jac,
                            segments=1)
    assert a.period == b.period and np.array_equal(a.x0, b.x0) and a.nfev == b.nfev


def test_multipliers_do_not_depend_on_the_number_of_segments():
    # BifurcationKit.jl issue 343: stable with 3 segments, unstable with 5. Here the orbit and
    # its multipliers agree for M = 1, 5, 30 to the integration accuracy (~1e-10).
    mus = []
    for M in (1, 5, 30):
        orbit = find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, fixed=[0], jac=rossler_jac,
                                    segments=M)
        assert abs(orbit.period / T_ROSSLER - 1.0) <= 1e-9
        mus.append(monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac).multipliers)
    np.testing.assert_allclose(mus[1], mus[0], rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(mus[2], mus[0], rtol=1e-7, atol=1e-9)


@pytest.mark.parametrize("jacobian", ["variational", "finite-difference"])
def test_multiple_shooting_forced_oscillator_closed_form(jacobian):
    args = (0.1, 1.0, 1.3, 0.7)
    x_exact, _ = forced_oscillator_orbit(*args)
    orbit = find_periodic_orbit(forced_oscillator, [0.0, 0.0], 2 * math.pi / 1.3,
                                autonomous=False, jac=forced_oscillator_jac, args=args,
                                segments=4, jacobian=jacobian)
    np.testing.assert_allclose(orbit.x0, x_exact, atol=1e-9)


def test_multiple_shooting_jacobian_matches_finite_differences():
    from flapping._numdiff import central_jacobian
    from flapping.periodic import _segments as seg
    from flapping.periodic._problem import MultipleShootingProblem, ShootingSetup
    settings_ = seg.check_settings("DOP853", 1e-12, 1e-12, 1024, None)
    setup = ShootingSetup((rossler,), (rossler_jac,), (None,), (), np.array(MULTIFLAP_GUESS),
                          5.0, None, (0,), True, (), settings_, 1, 2**-10, None, 0,
                          "variational", 4)
    problem = MultipleShootingProblem(setup)
    z = problem.z0 + 0.01
    _, J = problem._variational_residual(z)
    # central differences of an rtol=1e-12 residual: error ~ 1e-12 / 6e-6 + h^2 ~ 1e-6
    np.testing.assert_allclose(J, central_jacobian(problem._plain_residual, z), atol=1e-5)


@pytest.mark.parametrize("kwargs, match", [
    ({"segments": 0}, "segments"),
    ({"segments": 3, "n_points": 2}, "n_points"),
    ({"segments": 3, "method": "RK4"}, "multiple of `segments`"),
])
def test_bad_segments_are_valueerrors(kwargs, match):
    with pytest.raises(ValueError, match=match):
        find_periodic_orbit(rossler, MULTIFLAP_GUESS, 5.0, **kwargs)


def test_the_test_fields_take_a_batch_of_states_as_solve_ivp_vectorized_passes():
    from flapping.periodic.testproblems import lorenz, lorenz_jac, rossler

    states = np.array([[1.0, -2.0, 0.5], [0.3, 4.0, -1.0], [2.0, 1.0, 25.0]]).T  # (3, m)
    for field in (lorenz, rossler):
        batch = field(0.0, states)
        for j in range(states.shape[1]):
            np.testing.assert_array_equal(batch[:, j], field(0.0, states[:, j]))
    assert lorenz_jac(0.0, [1.0, 2.0, 3.0]).shape == (3, 3)  # a list, as before


# ---- a blow-up in the user's ODE says where (issue 26, item 6) ----------------------------------


def test_a_blow_up_during_shooting_carries_time_state_and_source():
    # x' = x^2, x(0) = 1 blows up at t = 1 < T = 2: the ConvergenceError says when and where,
    # as attributes a caller can read (it used to hold the message alone)
    with pytest.raises(ConvergenceError, match="step budget exceeded") as error:
        find_periodic_orbit(lambda t, x: x**2, [1.0], 2.0, autonomous=False)
    exc = error.value
    assert exc.source == "step budget"
    assert exc.t == pytest.approx(1.0, abs=1e-3)
    assert exc.state.shape == (1,) and exc.state[0] > 1e3


def test_a_blow_up_in_one_segment_of_multiple_shooting_says_where():
    # segments of length 2 from x = 1: the first blows up at t = 1
    with pytest.raises(ConvergenceError, match="segment 0") as error:
        find_periodic_orbit(lambda t, x: x**2, [1.0], 4.0, autonomous=False, segments=2)
    assert error.value.source == "step budget"
    assert error.value.t == pytest.approx(1.0, abs=1e-3)


def test_a_convergence_failure_without_a_failed_integration_has_no_where():
    # Levenberg-Marquardt stopped short (max_nfev = 1): no integration failed, nothing to locate
    with pytest.raises(ConvergenceError) as error:
        find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, max_nfev=1)
    assert error.value.t is None and error.value.state is None and error.value.source is None

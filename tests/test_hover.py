"""The hovering orbit of the hawkmoth and its Floquet stability."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import flapping
from flapping.errors import ConvergenceError
from flapping.hover import HALF_PERIOD_SYMMETRY, find_hover_orbit, forced_orbit, paper_hover_problem
from flapping.stability import hover_stability, perturbation_growth


@pytest.fixture(scope="module")
def insect():
    return flapping.hawkmoth()


@pytest.fixture(scope="module")
def orbit(insect):
    return find_hover_orbit(insect)


@pytest.fixture(scope="module")
def stability(orbit):
    return hover_stability(orbit)


def test_orbit_closes(orbit):
    assert orbit.shooting.success
    assert orbit.residual_norm < 1e-10
    # Re-integrate the found initial state with another integrator (RK45 at 1e-12, so its own
    # error is ~1e-11 of max|x|): the orbit closes to that accuracy, not only in the solver's own
    # discretisation.
    from flapping.periodic.integrate import flow

    rhs, _ = orbit.model.segment_functions()
    res = flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=orbit.model.breakpoints,
               period=orbit.period, method="RK45", rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(res.x[:, -1], orbit.x0, atol=1e-9 * np.abs(orbit.x).max())


def test_orbit_hovers_mean_vertical_velocity_vanishes(orbit):
    v = orbit.mean_inertial_velocity
    scale = np.abs(orbit.x[1]).max()
    assert abs(v["climb"]) < 1e-8 * max(scale, 1.0)


def test_mean_vertical_aerodynamic_force_equals_weight(orbit, insect):
    # Over a closed hover orbit the inertial vertical velocity is periodic, so the cycle mean of the
    # vertical aerodynamic force balances the weight exactly.
    model = orbit.model
    t, x = orbit.t[:-1], orbit.x[:, :-1]
    loads = np.array([model.loads(ti, xi) for ti, xi in zip(t, x.T)]).T
    vertical = loads[1] * np.cos(x[3]) - loads[0] * np.sin(x[3])  # down positive
    # Trapezoid on a uniform periodic grid: error dominated by the |phi_dot| kinks, O(h^2).
    assert np.mean(vertical) == pytest.approx(-insect.weight, rel=1e-4)


def test_half_period_symmetry_of_the_symmetric_stroke(orbit):
    # With x_h = 0 the equations are invariant under t -> t + T/2, (u, w, q, theta) -> S(...),
    # and the orbit is unique, so it has the symmetry to the integration accuracy (the samples
    # come from DOP853 dense output at rtol 1e-11: ~1e-10 of max|x|; 1e-7 leaves a margin).
    assert orbit.half_period_symmetry_error < 1e-7
    shifted = np.roll(orbit.x[:, :-1], -(orbit.x.shape[1] - 1) // 2, axis=1)
    assert np.abs(shifted - HALF_PERIOD_SYMMETRY @ orbit.x[:, :-1]).max() < 1e-7 * np.abs(orbit.x).max()


def test_liouville(stability):
    # det M from the multipliers' product against exp(int trace J): both from integrations at
    # rtol 1e-12 over one period, so they agree to ~1e-11; 1e-9 is the requirement.
    assert stability.liouville_error < 1e-9


def test_multipliers_rk4_agree_with_dop853(orbit, stability):
    rk4 = hover_stability(orbit, method="RK4")
    # RK4 at 2^-10 of a period: global error ~ (h * |lambda|)^4 is far below 1e-6 here.
    np.testing.assert_allclose(np.sort_complex(rk4.multipliers), np.sort_complex(stability.multipliers),
                               rtol=1e-6, atol=1e-8)


def test_hover_is_unstable_and_nonlinear_growth_matches_multiplier(stability):
    assert not stability.is_stable
    growth = perturbation_growth(stability, epsilon=1e-8, n_cycles=30)
    assert growth.growth_per_cycle == pytest.approx(abs(stability.multipliers[0]), rel=2e-3)


def test_averaged_jacobian_has_the_trace_of_liouville(stability):
    # trace of the averaged Jacobian times T is the integral of trace J: a consistency check of
    # the quadrature against the monodromy's determinant.
    T = stability.orbit.period
    assert math.exp(np.trace(stability.averaged_jacobian) * T) == pytest.approx(stability.det, rel=1e-9)


def test_prescribed_amplitude_orbits_climb_or_sink(insect, orbit):
    low = forced_orbit(insect, orbit.amplitude * 0.97)
    high = forced_orbit(insect, orbit.amplitude * 1.03)
    # Less stroke, less lift: the body sinks (z down positive); more stroke: it climbs.
    assert low.z_drift > 0 > high.z_drift


def test_paper_h_condition_leaves_amplitude_undetermined(insect):
    result, sv = paper_hover_problem(insect)
    assert result.success
    # Rank 4 for 6 unknowns: a two-dimensional null space (h0 does not feed back, and the h
    # residual repeats the others), so the amplitude is not fixed by the paper's condition.
    rank = int(np.sum(sv > 1e-8 * sv[0]))
    assert rank == 4


def test_too_heavy_insect_has_no_hover_orbit():
    with pytest.raises(ValueError, match="weight"):
        find_hover_orbit(flapping.hawkmoth(mass=0.05))


def test_bad_guess_raises(insect):
    with pytest.raises(ValueError, match="x0_guess"):
        find_hover_orbit(insect, x0_guess=[0.0, 0.0])
    with pytest.raises(ValueError, match="amplitude"):
        find_hover_orbit(insect, amplitude_guess=2.0)


def _run_cli(*args):
    return subprocess.run([sys.executable, "-m", "flapping", *args], capture_output=True, text=True,
                          timeout=120)


def test_cli_json_parses_and_carries_the_keys():
    out = _run_cli("hover", "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    for key in ("amplitude_deg", "initial_state", "period_s", "multipliers", "det_monodromy",
                "liouville_det", "averaged_eigenvalues"):
        assert key in report
    assert set(report["initial_state"]) == {"u", "w", "q", "theta"}
    assert all(set(m) == {"re", "im"} for m in report["multipliers"])
    assert len(report["multipliers"]) == 4


@pytest.mark.parametrize("args", [("hover", "--insect", "dragonfly"), ("fly",), ("hover", "--bogus")])
def test_cli_bad_arguments_exit_nonzero_with_one_line(args):
    out = _run_cli(*args)
    assert out.returncode != 0
    assert "Traceback" not in out.stderr
    assert len(out.stderr.strip().splitlines()) == 1


def test_blade_element_hover_orbit_closes_and_hovers(insect):
    orbit = find_hover_orbit(insect, aerodynamics="small-angle")
    assert orbit.residual_norm < 1e-10
    # Mean climb from 512 trapezoid samples of the orbit: exact for the zero-mean symmetric
    # parts, ~1e-10 from the residual; the symmetry error as in the linear case, with the
    # blade-element Jacobian by differences (~1e-8 relative) loosening it to 1e-6.
    assert abs(orbit.mean_inertial_velocity["climb"]) < 1e-8
    assert orbit.half_period_symmetry_error < 1e-6


def test_hinge_offset_sign_mirrors_the_orbit(insect):
    # Reflecting the body fore-aft (x_h -> -x_h) must give the same amplitude and multipliers,
    # and the opposite horizontal drift.
    from flapping.stability import hover_sensitivity

    ahead, behind = hover_sensitivity(insect, {"+": {"hinge_offset": 1e-3},
                                               "-": {"hinge_offset": -1e-3}})
    assert ahead.amplitude_deg == pytest.approx(behind.amplitude_deg, rel=1e-9)
    np.testing.assert_allclose(np.abs(ahead.multipliers), np.abs(behind.multipliers), rtol=1e-8)
    assert ahead.mean_forward_velocity == pytest.approx(-behind.mean_forward_velocity, rel=1e-6)
    assert abs(ahead.mean_forward_velocity) > 1e-3


def test_mode_response_grows_by_its_multiplier_each_period(stability):
    from flapping.stability import mode_response

    t, delta = mode_response(stability, n_periods=2, samples_per_period=8)
    mu = stability.multipliers[0].real
    np.testing.assert_allclose(delta[:, 8], mu * delta[:, 0], atol=1e-9)
    np.testing.assert_allclose(delta[:, 16], mu**2 * delta[:, 0], atol=1e-9)
    assert stability.averaged_eigenvalues.dtype == complex
    with pytest.raises(ValueError, match="n_periods"):
        mode_response(stability, n_periods=0)


def test_force_budget_balances_on_the_orbit(orbit):
    from flapping.hover import force_budget

    budget = force_budget(orbit)
    g = orbit.model.insect.gravity
    # The mean of w' over a period vanishes: weight, lift and the body-motion terms balance
    # (trapezoid rule on an integrand with kinks at reversal: error ~1e-6 relative).
    assert abs(sum(budget["w"].values())) < 1e-5 * g
    assert budget["w"]["g cos(theta)"] == pytest.approx(g, rel=1e-3)
    # u and q: every term averages to zero by the half-period symmetry of the orbit.
    for eq in ("u", "q"):
        assert max(abs(v) for v in budget[eq].values()) < 1e-8, eq


def test_speed_pitch_cubic_root_is_an_averaged_eigenvalue(stability):
    from flapping.stability import speed_pitch_cubic

    cubic = speed_pitch_cubic(stability.averaged_jacobian)
    # With x_h = 0 the averaged w-equation decouples, so the cubic's roots are three of the four
    # averaged eigenvalues.
    for root in cubic.roots:
        assert np.min(np.abs(stability.averaged_eigenvalues - root)) < 1e-9 * abs(root)
    assert cubic.coefficients[-1] < 0  # g Mu < 0: a positive real root
    flipped = speed_pitch_cubic(stability.averaged_jacobian, flip_mu=True)
    assert flipped.coefficients[-1] == pytest.approx(-cubic.coefficients[-1])


def test_simulated_perturbation_starts_on_the_orbit_plus_epsilon(orbit):
    from flapping.stability import simulate_perturbation

    t, xp, xo = simulate_perturbation(orbit, 1e-4, n_cycles=2, samples_per_cycle=8)
    assert np.linalg.norm(xp[:, 0] - xo[:, 0]) == pytest.approx(1e-4)
    np.testing.assert_allclose(xo[:, 8], orbit.x0, atol=1e-8)
    with pytest.raises(ValueError, match="epsilon"):
        simulate_perturbation(orbit, -1.0)


def test_z_drift_of_the_hover_orbit_is_its_residual(orbit):
    assert abs(orbit.z_drift) <= orbit.residual_norm


def test_hover_needing_a_stroke_beyond_90_degrees_is_refused_at_once(insect):
    # With alpha_m = 5 deg eq. (40) needs more than 90 deg of stroke: a clear ValueError, not a
    # long iteration ending in a vague residual.
    with pytest.raises(ValueError, match="90 deg"):
        find_hover_orbit(insect, alpha_m=math.radians(5.0))


def test_iterates_beyond_90_degrees_raise_convergence_error(insect):
    # Just heavy enough that the trim at this alpha_m needs ~88 deg, so the hover orbit (which
    # needs a few degrees more than the trim) lies beyond 90 deg: the iteration must stop with
    # ConvergenceError naming the amplitude, whichever model.
    from flapping.model.aerodynamics import trim_angle_of_attack

    alpha_m = trim_angle_of_attack(insect)
    heavy = insect.with_(mass=insect.mass * (math.radians(88.0) / insect.stroke_amplitude) ** 2)
    with pytest.raises(ConvergenceError, match="deg"):
        find_hover_orbit(heavy, alpha_m=alpha_m, aerodynamics="small-angle")


def test_perturbation_growth_validates_its_arguments(stability):
    with pytest.raises(ValueError, match="epsilon"):
        perturbation_growth(stability, epsilon=0.0)
    with pytest.raises(ValueError, match="epsilon"):
        perturbation_growth(stability, epsilon=10.0)
    with pytest.raises(ValueError, match="n_cycles"):
        perturbation_growth(stability, epsilon=1e-8, n_cycles=0)

"""The hovering orbit of the hawkmoth (flapping.hover); its stability is in test_stability.py."""

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import flapping
from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.hover import (
    HALF_PERIOD_SYMMETRY,
    HOVER_SPEED_RTOL,
    find_hover_orbit,
    forced_orbit,
    paper_hover_problem,
)


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
    loads = np.array([model.loads(ti, xi) for ti, xi in zip(t, x.T, strict=True)]).T
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


def test_blade_element_hover_orbit_closes_and_hovers(insect):
    orbit = find_hover_orbit(insect, aerodynamics="small-angle")
    assert orbit.residual_norm < 1e-10
    # Mean climb from 512 trapezoid samples of the orbit: exact for the zero-mean symmetric
    # parts, ~1e-10 from the residual; the symmetry error as in the linear case, with the
    # blade-element Jacobian by differences (~1e-8 relative) loosening it to 1e-6.
    assert abs(orbit.mean_inertial_velocity["climb"]) < 1e-8
    assert orbit.half_period_symmetry_error < 1e-6


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


def _altitude_change(orbit):
    """z(T) - z(0) and the peak-to-peak z within the period, integrated independently.

    scipy's RK45 (not the package's flow, not DOP853) over each half-stroke, with the altitude
    equation written out here: z' = -u sin(theta) + w cos(theta), z down positive.
    """
    model = orbit.model
    rhs, _ = model.segment_functions()
    bounds = np.array((0.0, *model.breakpoints, 1.0)) * orbit.period
    y, z = np.append(orbit.x0, 0.0), [0.0]
    for f, a, b in zip(rhs, bounds[:-1], bounds[1:], strict=True):

        def g(t, y, f=f):
            u, w, _, th = y[:4]
            return np.append(f(t, y[:4]), -u * math.sin(th) + w * math.cos(th))

        sol = solve_ivp(g, (a, b), y, method="RK45", rtol=1e-12, atol=1e-14, dense_output=True)
        assert sol.success
        y = sol.y[:, -1]
        z.extend(sol.sol(np.linspace(a, b, 64))[4])
    return float(y[4]), float(np.ptp(z))


def test_hover_orbit_returns_to_its_altitude(orbit):
    # The hover condition, checked from outside the solver: an independent integration of the
    # altitude equation along the found orbit returns to z(0). Both integrations are accurate to
    # ~1e-12 of the excursion; an amplitude off by 1e-9 (relative) would leave ~1e-10 m, 1e-6 of
    # the excursion, so 1e-9 of it is a bound a wrong hover condition (a sign in z', the paper's
    # h condition, a z left free) cannot meet.
    drift, excursion = _altitude_change(orbit)
    assert excursion > 1e-5  # the body bobs ~0.2 mm within a wingbeat: a real scale
    assert abs(drift) < 1e-9 * excursion
    assert abs(orbit.z_drift - drift) < 1e-9 * excursion


@pytest.mark.parametrize("factor", [0.97, 1.03])
def test_z_drift_of_an_orbit_off_the_hover_amplitude_is_its_altitude_change(insect, orbit, factor):
    # Off the hover amplitude the orbit sinks or climbs by millimetres per wingbeat: the reported
    # z_drift is that change (independent RK45 integration, agreement ~1e-12 relative; 1e-8 is
    # the margin), and minus T times the sampled mean climb rate (trapezoid rule on 512 samples:
    # its error, from the kinks at stroke reversal, is far below 1e-6 relative).
    other = forced_orbit(insect, orbit.amplitude * factor)
    drift, _ = _altitude_change(other)
    assert abs(drift) > 1e-3
    assert other.z_drift == pytest.approx(drift, rel=1e-8)
    assert other.z_drift == pytest.approx(-other.period * other.mean_inertial_velocity["climb"],
                                          rel=1e-6)
    assert not other.is_hover


def test_default_hawkmoth_hovers_without_warning(insect):
    with warnings.catch_warnings():
        warnings.simplefilter("error", HoverDriftWarning)
        orbit = find_hover_orbit(insect)
    assert orbit.is_hover
    # The symmetric stroke cancels the forward speed to round-off (~1e-12 m/s, 1e-12 of the
    # wingtip speed), far inside the tolerance.
    assert orbit.mean_horizontal_speed < 1e-9
    assert orbit.mean_horizontal_speed < HOVER_SPEED_RTOL * orbit.wingtip_speed


@pytest.mark.parametrize("hinge_offset", [1e-3, -1e-3])
def test_offset_hinge_orbit_drifts_and_is_reported(insect, hinge_offset):
    # Reproducer (issue 7): with the hinge 1 mm off the centre of gravity the "hover" orbit holds
    # its altitude but flies at ~0.44 m/s, towards the side of the hinge. It must be reported: a
    # warning, is_hover False, the speed in mean_horizontal_speed.
    with pytest.warns(HoverDriftWarning, match="not hover"):
        orbit = find_hover_orbit(insect.with_(hinge_offset=hinge_offset))
    assert not orbit.is_hover
    assert orbit.mean_horizontal_speed > 0.1
    assert np.sign(orbit.mean_inertial_velocity["forward"]) == np.sign(hinge_offset)
    assert abs(orbit.mean_inertial_velocity["climb"]) < 1e-8  # it does hold its altitude


def test_wingtip_speed_is_the_mean_of_the_tip_speed_over_a_stroke(orbit, insect):
    # The scale of is_hover's tolerance against the kinematics: R |phi_dot(t)| averaged over a
    # period (midpoint rule on 20000 points of a smooth |cos|-shaped integrand: ~1e-8).
    from flapping.model.kinematics import flapping_rate

    n = 20000
    t = (np.arange(n) + 0.5) * orbit.period / n
    tip = insect.semi_span * np.abs(flapping_rate(t, orbit.amplitude, insect.frequency))
    assert orbit.wingtip_speed == pytest.approx(np.mean(tip), rel=1e-6)


@pytest.mark.parametrize("kwargs, name", [
    ({"n_samples": 7}, "n_samples"),
    ({"n_samples": 0}, "n_samples"),
    ({"n_samples": 8.0}, "n_samples"),
    ({"x0_guess": [0.0, float("nan"), 0.0, 0.0]}, "x0_guess"),
])
def test_find_hover_orbit_refuses_bad_arguments_by_name(insect, kwargs, name):
    with pytest.raises(ValueError, match=name):
        find_hover_orbit(insect, **kwargs)


def test_force_budget_takes_tolerances_and_checks_them(orbit):
    from flapping.hover import force_budget

    default = force_budget(orbit)
    loose = force_budget(orbit, rtol=1e-8, atol=1e-10)
    # The tolerances reach the integration (the budget moves), and a looser one changes it only
    # at its own level.
    w, w_loose = default["w"]["Zw w"], loose["w"]["Zw w"]
    assert w != w_loose
    assert w_loose == pytest.approx(w, rel=1e-6)
    with pytest.raises(ValueError, match="rtol"):
        force_budget(orbit, rtol=0.0)
    with pytest.raises(ValueError, match="orbit"):
        force_budget("orbit")


# --------------------------------------------------------------- two trims: Phi and phi_bar
@pytest.mark.parametrize("hinge_offset", [2e-3, -2e-3])
def test_two_trims_find_a_true_hover_orbit_with_a_hinge_offset(hinge_offset):
    insect = flapping.hawkmoth(hinge_offset=hinge_offset)
    with pytest.warns(flapping.errors.HoverDriftWarning):
        drifting = flapping.find_hover_orbit(insect)
    assert drifting.mean_horizontal_speed > 0.4  # Phi alone cannot cancel the mean moment
    orbit = flapping.find_hover_orbit(insect, trims=("amplitude", "stroke_mean"))
    assert orbit.trims == ("amplitude", "stroke_mean") and drifting.trims == ("amplitude",)
    assert orbit.is_hover
    assert orbit.mean_horizontal_speed < 1e-9
    assert abs(orbit.mean_inertial_velocity["climb"]) < 1e-9
    # The mean stroke leans against the offset: a hinge ahead of the CG strokes further back.
    assert np.sign(orbit.stroke_mean) == -np.sign(hinge_offset)
    assert 0.01 < abs(orbit.stroke_mean) < 0.2


def test_two_trims_at_zero_offset_keep_the_symmetric_hover():
    one = flapping.find_hover_orbit(flapping.hawkmoth())
    two = flapping.find_hover_orbit(flapping.hawkmoth(), trims=("amplitude", "stroke_mean"))
    assert abs(two.stroke_mean) < 1e-10
    assert abs(two.amplitude - one.amplitude) < 1e-10


@pytest.mark.parametrize("trims", [("stroke_mean",), ("amplitude", "x"), 3, ()])
def test_bad_trims_are_named(trims):
    with pytest.raises(ValueError, match="trims"):
        flapping.find_hover_orbit(flapping.hawkmoth(), trims=trims)


def test_two_trims_refuse_the_compiled_kernel():
    with pytest.raises(ValueError, match="no mean stroke angle"):
        flapping.find_hover_orbit(flapping.hawkmoth(), trims=("amplitude", "stroke_mean"),
                                  backend="compiled")


def test_two_trims_with_the_blade_element_loads_agree_with_the_linear_model():
    # The small-angle loads differ from eq. (29) at second order in the states (~1e-3 of Phi).
    insect = flapping.hawkmoth(hinge_offset=2e-3)
    linear = flapping.find_hover_orbit(insect, trims=("amplitude", "stroke_mean"))
    blade = flapping.find_hover_orbit(insect, aerodynamics="small-angle",
                                      trims=("amplitude", "stroke_mean"))
    assert blade.is_hover and blade.mean_horizontal_speed < 1e-9
    assert abs(blade.stroke_mean - linear.stroke_mean) < 1e-3 * abs(linear.stroke_mean)
    assert abs(blade.amplitude - linear.amplitude) < 1e-3 * linear.amplitude

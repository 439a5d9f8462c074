"""The stability atlas helpers (flapping.studies.atlas): homotopy, per-species numbers, sweeps."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import flapping
from flapping.errors import ConvergenceError
from flapping.hover import find_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.model.presets import preset
from flapping.studies.atlas import (
    attitude_fixed_exponents,
    frequency_sweep,
    hover_by_homotopy,
    interpolate_insects,
    morphology_sensitivity,
    robust_hover_orbit,
    species_stability,
)

#: The monarch flapping 6 % slower than its preset (FWUAV's hover, 11.72 Hz): the default guess
#: fails (the first Newton steps throw the amplitude past 90 deg), the continuation does not.
MONARCH_SLOW_HZ = 11.0


# ------------------------------------------------------------------ interpolation
def test_interpolation_ends_are_the_two_insects():
    a, b = flapping.hawkmoth(), preset("fruit_fly")
    start = interpolate_insects(a, b, 0.0)
    assert start.with_(name=a.name) == a
    assert interpolate_insects(a, b, 1.0) == b


def test_scales_are_interpolated_geometrically():
    a, b = flapping.hawkmoth(), preset("fruit_fly")
    mid = interpolate_insects(a, b, 0.5)
    assert mid.mass == pytest.approx(math.sqrt(a.mass * b.mass), rel=1e-13)
    assert mid.r2 == pytest.approx(0.5 * (a.r2 + b.r2), rel=1e-13)


@settings(max_examples=50, deadline=None)
@given(s=st.floats(0.0, 1.0))
def test_every_intermediate_planform_exists(s):
    # r1 < r2 < sqrt(r1) is convex, so Insect's validation never fails along the path.
    insect = interpolate_insects(preset("monarch"), preset("fruit_fly"), s)
    assert insect.r1 < insect.r2 < math.sqrt(insect.r1)


def test_interpolation_refuses_a_fraction_outside_0_1():
    with pytest.raises(ValueError, match="`s`"):
        interpolate_insects(flapping.hawkmoth(), preset("monarch"), 1.5)


# ------------------------------------------------------------------ homotopy
def test_homotopy_finds_an_orbit_the_default_guess_misses():
    target = preset("monarch", frequency=MONARCH_SLOW_HZ)
    with pytest.raises(ConvergenceError):
        # LM shooting steps the amplitude past 90 deg (the kernel's Newton does not: see
        # tests/test_hover_problem.py)
        find_hover_orbit(target, backend="adaptive")
    result = hover_by_homotopy(target, backend="adaptive")
    assert result.path[-1] == 1.0 and result.start == "hawkmoth"
    orbit = result.orbit
    assert orbit.model.insect == target
    assert orbit.shooting.success and orbit.is_hover
    assert orbit.residual_norm < 1e-10


def test_homotopy_and_default_guess_agree_where_both_converge():
    target = preset("bumblebee")
    direct = find_hover_orbit(target)
    continued = hover_by_homotopy(target).orbit
    # Two solves of the same equations to tol 1e-10: the unknowns agree to ~1e-9.
    assert continued.amplitude == pytest.approx(direct.amplitude, abs=1e-9)
    np.testing.assert_allclose(continued.x0, direct.x0, atol=1e-8)


def test_robust_orbit_uses_the_default_guess_when_it_works():
    orbit, homotopy = robust_hover_orbit(preset("honeybee"))
    assert homotopy is None and orbit.is_hover


def test_homotopy_refuses_guesses_it_sets_itself():
    with pytest.raises(ValueError, match="amplitude_guess"):
        hover_by_homotopy(preset("honeybee"), amplitude_guess=1.0)


def test_homotopy_reports_where_it_stalls():
    # No halving allowed and a first step too long to converge: the error says where it stopped.
    heavy = flapping.hawkmoth(mass=3.5e-3)  # needs nearly 90 deg; far from the start
    with pytest.raises((ConvergenceError, ValueError)):
        find_hover_orbit(heavy)
    with pytest.raises(ConvergenceError, match="stalled at s = 0"):
        hover_by_homotopy(heavy, n_steps=1, max_failures=0)


# ------------------------------------------------------------------ per species
@pytest.fixture(scope="module")
def moth():
    orbit = find_hover_orbit(flapping.hawkmoth())
    return orbit, hover_stability(orbit)


def test_species_numbers_are_consistent(moth):
    orbit, stab = moth
    row = species_stability(orbit=orbit)
    mu1 = abs(stab.multipliers[0])
    assert row.rate == pytest.approx(math.log(mu1) / orbit.period, rel=1e-12)
    assert row.rate_per_frequency == pytest.approx(math.log(mu1), rel=1e-12)
    assert row.doubling_time == pytest.approx(math.log(2) / row.rate, rel=1e-15)
    assert row.doubling_wingbeats == pytest.approx(row.doubling_time * 26.3, rel=1e-15)
    assert row.averaging_error == pytest.approx(row.averaged_rate / row.rate - 1, rel=1e-12)
    assert row.mode.shape == (4,) and np.max(np.abs(row.mode)) == pytest.approx(1.0, rel=1e-15)
    assert row.mode_per_pitch[3] == pytest.approx(1.0, rel=1e-15)


def test_fixed_attitude_exponents_obey_liouville(moth):
    # The (u, w) subsystem's exponents sum to the cycle mean of its trace, which is the trace of
    # the averaged (u, w) block, which is the sum of its eigenvalues: two independent routes.
    orbit, stab = moth
    floquet, averaged = attitude_fixed_exponents(orbit, stab)
    trace = np.trace(stab.averaged_jacobian[:2, :2])
    assert np.sum(floquet).real == pytest.approx(trace, rel=1e-9)
    assert np.sum(averaged).real == pytest.approx(trace, rel=1e-12)


def test_fixed_attitude_removes_the_hawkmoth_instability(moth):
    # With pitch held on its schedule the translational modes decay (as in FWUAV's analysis).
    floquet, _ = attitude_fixed_exponents(*moth)
    assert np.all(floquet.real < 0)


def test_species_stability_needs_an_insect_or_an_orbit():
    with pytest.raises(ValueError, match="insect"):
        species_stability()


# ------------------------------------------------------------------ sweeps
def test_sweep_at_constant_wingtip_speed_keeps_alpha_m():
    rows = frequency_sweep(flapping.hawkmoth(), [26.3, 40.0, 60.0])
    alphas = [r.alpha_m_deg for r in rows]
    np.testing.assert_allclose(alphas, alphas[0], rtol=1e-12)


def test_averaging_error_falls_as_the_square_of_the_time_scale_ratio():
    # First-order averaging of a system symmetric over the half period errs at second order in
    # (rate / f): halving the ratio divides the error by ~4 once the ratio is small.
    rows = frequency_sweep(flapping.hawkmoth(), np.geomspace(26.3, 480.0, 8))
    errors = np.array([abs(r.averaging_error) for r in rows])
    ratios = np.array([r.rate_per_frequency for r in rows])
    assert np.all(np.diff(errors) < 0)
    slope = np.log(errors[-1] / errors[-3]) / np.log(ratios[-1] / ratios[-3])
    assert 1.7 < slope < 2.3


def test_sensitivity_bars_bracket_the_nominal_and_flag_infeasible_ends():
    bars = morphology_sensitivity("hoverfly", fields=["pitch_inertia", "stroke_amplitude"])
    nominal = abs(hover_stability(find_hover_orbit(preset("hoverfly"))).multipliers[0])
    by_field = {b.field: b for b in bars}
    inertia = by_field["pitch_inertia"]
    assert inertia.mu_nominal == pytest.approx(nominal, rel=1e-9)
    # A heavier body pitches more slowly: the instability weakens monotonically with I_y.
    assert inertia.mu_low > inertia.mu_nominal > inertia.mu_high
    amplitude = by_field["stroke_amplitude"]
    assert math.isnan(amplitude.mu_low) and "low:" in amplitude.note  # cannot trim (eq. 40)
    assert [b.spread for b in bars] == sorted((b.spread for b in bars), reverse=True)


def test_sensitivity_refuses_a_field_without_a_range():
    with pytest.raises(ValueError, match="fields"):
        morphology_sensitivity("bumblebee", fields=["mass"])  # verified: no range


# ------------------------------------------------------------------------------ geometry
@pytest.fixture(scope="module")
def hoverfly_cases():
    from flapping.studies.atlas import geometry_comparison
    return geometry_comparison("hoverfly")


def test_geometry_comparison_solves_the_three_cases_in_order(hoverfly_cases):
    from flapping.studies.atlas import GEOMETRY_CASES
    assert tuple(c.case for c in hoverfly_cases) == GEOMETRY_CASES
    paper, hinge, winged = hoverfly_cases
    assert paper.insect == preset("hoverfly")
    assert hinge.insect.wing_mass == 0.0 and winged.insect.wing_mass > 0.0
    for case in hoverfly_cases:
        assert abs(case.stability.climb_speed) < 1e-8  # every case is a hover, not a climb
        assert case.stability.liouville_error < 1e-7


def test_a_hinge_straight_above_the_cg_needs_no_mean_stroke_angle(hoverfly_cases):
    # Symmetry: with x_h = 0 the fore-aft mirror of the stroke is the same insect, so phi_bar = 0.
    for case in hoverfly_cases:
        assert abs(case.stroke_mean_deg) < 1e-6


def test_a_hinge_ahead_of_the_cg_sweeps_the_mean_stroke_back():
    # x_h > 0 puts the hinge ahead of the CG: the mean lift returns over the CG with phi_bar < 0.
    from flapping.studies.atlas import TWO_TRIMS
    moth = preset("hawkmoth", geometry="source", wing_mass=0.0)
    orbit = find_hover_orbit(moth, trims=TWO_TRIMS)
    assert moth.hinge_offset > 0.0 and orbit.stroke_mean < 0.0
    assert orbit.is_hover


def test_mode_type_and_period_follow_the_leading_multiplier(hoverfly_cases):
    import dataclasses
    case = hoverfly_cases[0]
    mu = 1.05 * np.exp(0.1j)
    stab = dataclasses.replace(case.stability, multipliers=np.array([mu, mu.conjugate(), 0.9, 0.8]))
    oscillating = dataclasses.replace(case, stability=stab)
    assert oscillating.mode_type == "oscillatory"
    assert oscillating.oscillation_period == pytest.approx(2 * np.pi / 0.1 * case.insect.period)
    flip = dataclasses.replace(case, stability=dataclasses.replace(
        case.stability, multipliers=np.array([-1.2, 0.9, 0.8, 0.7])))
    assert flip.mode_type == "flip" and math.isinf(flip.oscillation_period)


@pytest.mark.parametrize("name", ["bumblebee", "hoverfly"])
def test_the_mode_turns_oscillatory_where_the_averaged_speed_pitch_moment_changes_sign(name):
    # Second route for speed_pitch_neutral_height: Floquet multipliers either side of it.
    from flapping.studies.atlas import TWO_TRIMS, speed_pitch_neutral_height
    neutral = speed_pitch_neutral_height(preset(name))
    below, above = (hover_stability(find_hover_orbit(preset(name, hinge_height=f * neutral),
                                                     trims=TWO_TRIMS)).multipliers[0]
                    for f in (0.85, 1.15))
    assert abs(below.imag) < 1e-9 and below.real > 1.0
    assert abs(above.imag) > 1e-3


def test_speed_pitch_neutral_height_refuses_an_offset_hinge():
    from flapping.studies.atlas import speed_pitch_neutral_height
    with pytest.raises(ValueError, match="hinge_offset"):
        speed_pitch_neutral_height(preset("hawkmoth", hinge_offset=1e-3))

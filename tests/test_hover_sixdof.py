"""Hover and Floquet stability in six degrees of freedom (flapping.hover.sixdof, dof=6)."""

import numpy as np
import pytest

import flapping
from flapping.fast.kernel import numba_available
from flapping.hover.sixdof import SixDofHoverOrbit, SixDofStability, find_sixdof_hover_orbit
from flapping.model.sixdof import LATERAL


@pytest.fixture(scope="module")
def moth():
    return flapping.hawkmoth()  # with its estimated roll and yaw inertia


@pytest.fixture(scope="module")
def orbit(moth):
    return flapping.find_hover_orbit(moth, dof=6)


@pytest.fixture(scope="module")
def stability(orbit):
    return flapping.hover_stability(orbit)


@pytest.fixture(scope="module")
def planar(orbit):
    return flapping.hover_stability(orbit.planar, backend="adaptive")


def test_the_orbit_is_the_planar_one_with_the_lateral_states_zero(orbit):
    assert isinstance(orbit, SixDofHoverOrbit)
    assert orbit.dof == 6 and orbit.aerodynamics == "small-angle"
    assert orbit.residual_norm < 1e-9
    # The plane of symmetry is invariant: the shooting (if it ran) leaves it only by rounding.
    assert np.max(np.abs(orbit.x0[list(LATERAL)])) < 1e-12
    assert abs(orbit.amplitude - orbit.planar.amplitude) < 1e-10


@pytest.mark.slow
def test_eight_multipliers_with_longitudinal_and_lateral_views(stability):
    assert isinstance(stability, SixDofStability)
    assert stability.multipliers.shape == (8,)
    assert stability.longitudinal.multipliers.shape == (4,)
    assert stability.lateral.multipliers.shape == (4,)
    assert stability.lateral.names == ("v", "p", "r", "roll")
    both = np.sort_complex(np.concatenate([stability.longitudinal.multipliers,
                                           stability.lateral.multipliers]))
    np.testing.assert_allclose(both, np.sort_complex(stability.multipliers), atol=1e-9)


@pytest.mark.slow
def test_symmetric_flapping_decouples_the_two_sets(stability):
    # Zero to the rounding of the central-difference Jacobians (~1e-10 of the largest entry).
    assert stability.coupling < 1e-8


@pytest.mark.slow
def test_the_longitudinal_multipliers_are_the_planar_ones(stability, planar):
    np.testing.assert_allclose(stability.longitudinal.multipliers, planar.multipliers,
                               rtol=0, atol=1e-8)


@pytest.mark.slow
def test_liouville_and_the_error_estimate(stability):
    assert stability.liouville_error < 1e-8
    assert stability.multiplier_error < 1e-8


def test_the_exact_loads_hover_in_six_dof(moth):
    orbit = flapping.find_hover_orbit(moth, dof=6, aerodynamics="exact")
    assert orbit.residual_norm < 1e-9 and orbit.aerodynamics == "exact"


def test_six_dof_refuses_what_it_cannot_do(moth):
    with pytest.raises(ValueError, match="aerodynamics"):
        flapping.find_hover_orbit(moth, dof=6, aerodynamics="quasi-steady")
    with pytest.raises(ValueError, match="roll_inertia"):
        flapping.find_hover_orbit(moth.with_(roll_inertia=None), dof=6)
    with pytest.raises(ValueError, match="dof"):
        flapping.find_hover_orbit(moth, dof=5)


def test_a_six_dof_orbit_refuses_another_backend(orbit):
    with pytest.raises(ValueError, match="compiled"):
        flapping.hover_stability(orbit, backend="fixed-step")


@pytest.mark.slow
def test_the_command_line_adds_the_lateral_multipliers():
    from flapping.cli import UNITS, hover_report

    report = hover_report("hawkmoth", dof=6)
    assert set(report) >= set(UNITS) | {"dof", "lateral_multipliers", "lateral_stable", "sixdof"}
    assert report["dof"] == 6 and report["aerodynamics"] == "small-angle"
    assert len(report["lateral_multipliers"]) == 4
    assert set(report["lateral_multipliers"][0]) == set(report["multipliers"][0]) == {"re", "im"}
    assert set(report["units"]) >= set(report) - {"units"}


@pytest.fixture(scope="module")
def linear(moth):
    """The paper's linear loads (eq. 29) in six degrees of freedom, on the Python path."""
    orbit = flapping.find_hover_orbit(moth, dof=6, aerodynamics="linear", backend="adaptive")
    return orbit, flapping.hover_stability(orbit)


def test_the_linear_loads_hover_in_six_dof(linear):
    orbit, _ = linear
    assert orbit.aerodynamics == "linear" and orbit.planar.model.aerodynamics == "linear"
    assert orbit.residual_norm < 1e-9
    assert np.max(np.abs(orbit.x0[list(LATERAL)])) < 1e-12


@pytest.mark.slow
def test_the_linear_loads_longitudinal_multipliers_are_the_planar_ones(linear):
    orbit, stability = linear
    planar = flapping.hover_stability(orbit.planar, backend="adaptive")
    np.testing.assert_allclose(stability.longitudinal.multipliers, planar.multipliers,
                               rtol=0, atol=1e-8)
    assert stability.coupling < 1e-8
    assert stability.liouville_error < 1e-8
    assert stability.multiplier_error < 1e-8


@pytest.fixture(scope="module")
def compiled(moth):
    """The linear loads on the compiled six-degree-of-freedom path (the default for them)."""
    orbit = flapping.find_hover_orbit(moth, dof=6, aerodynamics="linear")
    return orbit, flapping.hover_stability(orbit)


def test_the_compiled_path_is_the_default_for_the_linear_loads(compiled):
    orbit, stability = compiled
    assert orbit.backend == "compiled" and orbit.residual_norm < 1e-9
    assert np.max(np.abs(orbit.x0[list(LATERAL)])) < 1e-12
    assert stability.multipliers.shape == (8,)
    assert stability.coupling < 1e-8
    assert stability.liouville_error < 1e-8 and stability.multiplier_error < 1e-8


@pytest.mark.slow
def test_the_compiled_path_agrees_with_the_python_path(compiled, linear):
    (orbit, stability), (python_orbit, python) = compiled, linear
    assert python_orbit.backend == "adaptive"
    np.testing.assert_allclose(orbit.x0, python_orbit.x0, rtol=0, atol=1e-9)
    assert abs(orbit.amplitude - python_orbit.amplitude) < 1e-10
    np.testing.assert_allclose(np.sort_complex(stability.multipliers),
                               np.sort_complex(python.multipliers), rtol=0, atol=1e-8)
    # The Python analysis of the compiled orbit, and the compiled analysis of the Python one.
    again = flapping.hover_stability(python_orbit, backend="compiled")
    np.testing.assert_allclose(again.multipliers, stability.multipliers, rtol=0, atol=1e-8)


def test_the_compiled_path_with_wing_mass_agrees_with_the_python_path(moth):
    insect = moth.with_(wing_mass=4.7e-5, hinge_height=2e-3)
    orbit = flapping.find_hover_orbit(insect, dof=6, aerodynamics="linear")
    assert orbit.backend == "compiled"
    python = flapping.hover_stability(orbit, backend="adaptive")
    ours = flapping.hover_stability(orbit)
    np.testing.assert_allclose(np.sort_complex(ours.multipliers),
                               np.sort_complex(python.multipliers), rtol=0, atol=1e-8)
    assert ours.liouville_error < 1e-8


# --------------------------------------------------------------------------- blade-element loads
needs_numba = pytest.mark.skipif(not numba_available(), reason="the compiled path needs numba")


@needs_numba
def test_the_compiled_path_is_the_default_for_the_blade_element_loads(orbit, stability):
    assert orbit.backend == "compiled"
    assert stability.details.nfev > 0 and stability.multiplier_error < 1e-8
    # Liouville on the compiled path: det M (the product of the factors' determinants) against
    # exp of the trace's integral, integrated apart.
    assert stability.liouville_error < 1e-8


@pytest.fixture(scope="module")
def python_path(moth):
    """The Python path (adaptive shooting, central-difference Jacobians): the cross-check."""
    orbit = flapping.find_hover_orbit(moth, dof=6, backend="adaptive")
    return orbit, flapping.hover_stability(orbit)


@needs_numba
@pytest.mark.slow
def test_the_compiled_blade_element_path_agrees_with_the_python_path(orbit, stability,
                                                                     python_path):
    python_orbit, python = python_path
    assert python_orbit.backend == "adaptive"
    np.testing.assert_allclose(orbit.x0, python_orbit.x0, rtol=0, atol=1e-9)
    assert abs(orbit.amplitude - python_orbit.amplitude) < 1e-10
    # To the two paths' stated errors (each ~2e-9 to 5e-9 for the hawkmoth).
    bound = stability.multiplier_error + python.multiplier_error
    np.testing.assert_allclose(np.sort_complex(stability.multipliers),
                               np.sort_complex(python.multipliers), rtol=0, atol=bound)
    # The compiled analysis of the Python orbit.
    again = flapping.hover_stability(python_orbit, backend="compiled")
    np.testing.assert_allclose(np.sort_complex(again.multipliers),
                               np.sort_complex(python.multipliers), rtol=0, atol=bound)


@needs_numba
@pytest.mark.parametrize("aerodynamics", ["small-angle", "exact"])
def test_the_compiled_path_with_wing_mass_and_hinge(moth, aerodynamics):
    """Wing mass (a phase-dependent mass matrix) and the hinge off the centre of gravity: the
    compiled orbit closes to the tolerance on the compiled map at four times the steps (its
    integration error of the residual), and on the Python field integrated adaptively at
    rtol 1e-13 (whose own error, crossing the loads' kinks, is ~1e-9: 5e-8 at rtol 1e-11), and
    its multipliers are the Python analysis's to the stated errors."""
    from flapping.fast import _sixdof_loads
    from flapping.hover.sixdof import _fields
    from flapping.periodic.integrate import flow

    insect = moth.with_(wing_mass=4.7e-5, hinge_height=2e-3, hinge_offset=1e-3)
    with pytest.warns(flapping.HoverDriftWarning):  # x_h breaks the symmetry: it drifts
        orbit = flapping.find_hover_orbit(insect, dof=6, aerodynamics=aerodynamics)
    assert orbit.backend == "compiled"
    model = orbit.model
    y0 = np.append(orbit.x0, 0.0)
    finer = _sixdof_loads.Flow(model)(orbit.x0, orbit.amplitude, 4 * orbit.n_steps, False)
    assert np.linalg.norm(finer - y0) < 1e-9
    end = flow(_fields(model), (0.0, model.period), y0, breakpoints=model.breakpoints,
               period=model.period, rtol=1e-13, atol=1e-13, args=(orbit.amplitude,))
    assert np.linalg.norm(np.asarray(end.x)[:, -1] - y0) < 1e-8
    ours = flapping.hover_stability(orbit)
    python = flapping.hover_stability(orbit, backend="adaptive")
    bound = ours.multiplier_error + python.multiplier_error
    np.testing.assert_allclose(np.sort_complex(ours.multipliers),
                               np.sort_complex(python.multipliers), rtol=0, atol=bound)
    assert ours.liouville_error < 1e-8


# --------------------------------------------------------------------------- the tolerance
@pytest.mark.parametrize("path", ["auto", pytest.param("adaptive", marks=pytest.mark.slow)])
def test_the_hinge_10_mm_above_the_centre_of_gravity_converges_at_the_defaults(moth, path):
    insect = moth.with_(hinge_height=0.01)
    orbit = flapping.find_hover_orbit(insect, dof=6, backend=path)
    assert orbit.residual_norm <= 1e-10
    assert np.max(np.abs(orbit.x0[list(LATERAL)])) < 1e-12


@needs_numba
@pytest.mark.slow
def test_every_hinge_height_of_the_stabilisation_chapter_converges(moth):
    """book/control.md's passive sweep: 25 hinge heights from 0 to one body length."""
    from flapping.studies.control import BODY_LENGTHS

    for height in np.linspace(0.0, BODY_LENGTHS["hawkmoth"], 25):
        orbit = flapping.find_hover_orbit(moth.with_(hinge_height=float(height)), dof=6)
        assert orbit.backend == "compiled" and orbit.residual_norm <= 1e-10
        # The plane of symmetry is invariant: Phi is the planar orbit's to the tolerances.
        assert abs(orbit.amplitude_change) < 1e-10


@pytest.mark.slow
def test_a_tolerance_below_the_integrations_error_is_raised_to_it(moth):
    """The adaptive path's residual cannot be resolved below its flow's error: a tolerance
    asked below it is met at that error (it raised ConvergenceError before)."""
    insect = moth.with_(hinge_height=0.01)
    flat = flapping.find_hover_orbit(insect, aerodynamics="small-angle")
    orbit = find_sixdof_hover_orbit(insect, backend="adaptive", planar_orbit=flat, tol=1e-13)
    assert orbit.residual_norm < 1e-9


# --------------------------------------------------------------------------- one schema
def _public(obj) -> set[str]:
    return {name for name in dir(obj) if not name.startswith("_")}


#: What the six-degree-of-freedom results add to the planar schema (their own views).
SIXDOF_ORBIT_VIEWS = {"planar", "amplitude_change", "n_steps", "newton_monodromy"}
SIXDOF_STABILITY_VIEWS = {"longitudinal", "lateral", "coupling", "details"}


def test_planar_and_six_dof_orbits_have_one_schema(compiled):
    # Reproducer (issue 35): SixDofHoverOrbit lacked 29 of HoverOrbit's public attributes
    # (status, is_hover, solver, floquet, amplitude_deg, the error estimates...).
    orbit, stability = compiled
    planar = orbit.planar
    assert _public(orbit) - _public(planar) == SIXDOF_ORBIT_VIEWS
    assert _public(planar) <= _public(orbit)
    assert _public(stability) - _public(flapping.hover_stability(planar)) == (
        SIXDOF_STABILITY_VIEWS)


def test_the_six_dof_orbit_s_views_mean_the_planar_ones(compiled):
    orbit, stability = compiled
    planar = orbit.planar
    assert orbit.status == planar.status == "hover" and orbit.is_hover and orbit.success
    assert orbit.dof == 6 and planar.dof == 4
    assert orbit.amplitude_deg == pytest.approx(planar.amplitude_deg, rel=1e-9)
    assert orbit.x.shape == (8, planar.x.shape[1]) and orbit.t[-1] == planar.t[-1]
    # The plane of symmetry is invariant: the states and speeds are the planar ones to the
    # integrations' tolerance (rtol 1e-11 over one period).
    lon = np.asarray([0, 2, 4, 7])
    np.testing.assert_allclose(orbit.x[lon], planar.x, atol=1e-8)
    assert abs(orbit.mean_inertial_velocity["side"]) < 1e-12
    assert abs(orbit.z_drift) < 1e-9 and orbit.half_period_symmetry_error < 1e-6
    assert orbit.solver.n_steps == orbit.n_steps and orbit.nit == orbit.stats.nit
    assert np.isnan(orbit.amplitude_error) and orbit.kernel is None
    assert orbit.floquet is not None and orbit.floquet.matrix.shape == (8, 8)
    assert stability.is_stable == stability.stable and stability.exponents.shape == (8,)
    assert stability.det == pytest.approx(stability.liouville_det, rel=1e-7)
    v = stability.unstable_mode
    assert np.max(np.abs(v)) == pytest.approx(1.0)
    np.testing.assert_allclose(stability.monodromy @ stability.eigenvectors,
                               stability.eigenvectors * stability.multipliers, atol=1e-9)


def test_the_six_dof_averaged_jacobian_holds_the_planar_one(compiled):
    orbit, stability = compiled
    lon = np.ix_([0, 2, 4, 7], [0, 2, 4, 7])
    planar = flapping.hover_stability(orbit.planar)
    # Central differences (step 1e-6) against the planar path's analytic Jacobian.
    np.testing.assert_allclose(stability.averaged_jacobian[lon], planar.averaged_jacobian,
                               rtol=1e-5, atol=1e-5)
    assert stability.averaged_eigenvalues.shape == (8,)

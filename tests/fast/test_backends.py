"""find_hover_orbit and hover_stability on the compiled kernel against the adaptive reference."""

import warnings

import numpy as np
import pytest

import flapping
from flapping.fast import kernel

pytest.importorskip("numba")


@pytest.fixture(scope="module")
def both():
    insect = flapping.hawkmoth()
    out = {}
    for backend in ("compiled", "adaptive"):
        orbit = flapping.find_hover_orbit(insect, backend=backend)
        out[backend] = orbit, flapping.hover_stability(orbit, backend=backend)
    return out


def test_compiled_orbit_and_stability_agree_with_the_adaptive_ones(both):
    (o_c, s_c), (o_a, s_a) = both["compiled"], both["adaptive"]
    assert abs(o_c.amplitude_deg - o_a.amplitude_deg) < 1e-9  # the kernel's promise
    np.testing.assert_allclose(s_c.multipliers, s_a.multipliers, rtol=0, atol=1e-8)
    np.testing.assert_allclose(o_c.x, o_a.x, rtol=0, atol=1e-8)  # samples, SI
    # The averaged Jacobian: the same Gauss rule on orbits that agree to ~3e-9 (the kernel's x0
    # error at 12 steps), so entries agree to ~1e-9 in absolute terms (those that vanish by the
    # half-period symmetry are ~2e-9 instead of ~1e-12).
    np.testing.assert_allclose(s_c.averaged_jacobian, s_a.averaged_jacobian, rtol=1e-8, atol=1e-8)
    assert s_c.liouville_error < 1e-9 and o_c.is_hover
    assert o_c.kernel is not None and o_a.kernel is None
    # One result type: the kernel's counters on the orbit, no shooting result of its own.
    assert o_c.shooting is None and o_c.nit == o_c.kernel.nit and o_c.backend == "compiled"


def test_hover_stability_of_an_adaptive_orbit_on_the_kernel(both):
    # No kernel solution attached: the monodromy is integrated by the kernel at the given x0.
    o_a, s_a = both["adaptive"]
    s = flapping.hover_stability(o_a, backend="compiled")
    np.testing.assert_allclose(s.multipliers, s_a.multipliers, rtol=0, atol=1e-8)


def test_auto_is_the_kernel_for_the_linear_model_only():
    insect = flapping.hawkmoth()
    assert flapping.find_hover_orbit(insect, backend="auto").kernel is not None
    assert flapping.find_hover_orbit(insect, backend="auto", method="RK45").kernel is None
    with pytest.raises(ValueError, match="linear"):
        flapping.find_hover_orbit(insect, aerodynamics="exact", backend="compiled")
    with pytest.raises(ValueError, match="backend"):
        flapping.find_hover_orbit(insect, backend="numba")


def test_auto_without_numba_falls_back_to_the_adaptive_path_and_says_so(monkeypatch):
    monkeypatch.setattr(kernel, "numba_available", lambda: False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        orbit = flapping.find_hover_orbit(flapping.hawkmoth(), backend="auto")
    assert orbit.kernel is None
    assert any("numba is not installed" in str(w.message) for w in caught)
    with pytest.raises(ImportError):
        flapping.find_hover_orbit(flapping.hawkmoth(), backend="compiled")


def test_kernel_follows_the_hinge_height():
    insect = flapping.hawkmoth(hinge_height=5e-3)
    fast = flapping.find_hover_orbit(insect, backend="compiled")
    slow = flapping.find_hover_orbit(insect, backend="adaptive")
    assert abs(fast.amplitude - slow.amplitude) < 1e-10
    np.testing.assert_allclose(fast.x0, slow.x0, atol=1e-9)


def test_kernel_refuses_a_mean_stroke_angle_and_auto_falls_back():
    insect = flapping.hawkmoth(stroke_mean=0.01)
    with pytest.raises(ValueError, match="stroke_mean"):
        flapping.find_hover_orbit(insect, backend="compiled")
    with pytest.raises(ValueError, match="stroke_mean"):
        kernel.KernelProblem.of(insect)
    with pytest.warns(flapping.errors.HoverDriftWarning, match="stroke_mean"):
        orbit = flapping.find_hover_orbit(insect, backend="auto")
    assert orbit.kernel is None  # the adaptive path, which follows phi_bar
    assert orbit.amplitude != flapping.find_hover_orbit(flapping.hawkmoth()).amplitude

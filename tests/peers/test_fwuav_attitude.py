"""FWUAV's hover with the thorax pitch free (flapping.peers.fwuav.attitude)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flapping.peers.fwuav import FwuavHover
from flapping.peers.fwuav.attitude import (
    FwuavPitchFree,
    PitchFreeFloquet,
    _reduced,
    pitch_free_floquet,
    pitch_free_model,
)
from flapping.peers.fwuav.data import species
from flapping.periodic.floquet import monodromy


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
@pytest.mark.parametrize("name", ["hawkmoth", "fruit_fly"])
def test_held_pitch_is_the_prescribed_model(name: str, body_rate_term: str) -> None:
    """With the pitch held on FWUAV's sinusoid, the four-body equations give FwuavHover's
    translational acceleration (a different code path: Newton-Euler solved as a linear system)."""
    held = FwuavPitchFree(name, pitch="prescribed", body_rate_term=body_rate_term)
    reference = FwuavHover(name, body_rate_term=body_rate_term)
    for t in np.linspace(0.0, held.period, 7):
        v = np.array([0.13, 0.0, -0.21])
        a, _ = held.accelerations(t, np.array([0.0, 0.0, 0.0, v[0], v[2], 0.0]))
        expected = reference.rhs(t, np.concatenate([np.zeros(3), v]))[3:6]
        np.testing.assert_allclose(a, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


def test_free_pitch_conserves_momentum_without_external_loads() -> None:
    """No aerodynamics, no gravity: linear and angular momentum of the four bodies are constant
    (fails if the moment equation, an inertia or an appendage acceleration is wrong)."""
    model = FwuavPitchFree("hawkmoth", aerodynamics=False, gravity=False)
    y0 = np.array([0.001, 0.002, 1.0, 0.1, -0.2, 3.0])
    sol = solve_ivp(model.rhs, (0.0, 0.6 * model.period), y0, method="DOP853", rtol=1e-11,
                    atol=1e-13)
    P0, H0 = model.momentum(0.0, y0)
    P1, H1 = model.momentum(sol.t[-1], sol.y[:, -1])
    assert abs(sol.y[2, -1] - y0[2]) > 1e-3  # the pitch did move
    np.testing.assert_allclose(P1, P0, atol=1e-9 * np.abs(P0).max())
    np.testing.assert_allclose(H1, H0, atol=1e-8 * np.abs(H0).max())


def test_pitch_free_moves_differently_from_held() -> None:
    """Free, the pitch answers the aerodynamic moment: its acceleration differs from FWUAV's
    prescribed one at the same instant and state."""
    free = FwuavPitchFree("hawkmoth")
    held = FwuavPitchFree("hawkmoth", pitch="prescribed")
    theta, q, dd = held._prescribed_pitch(0.01)
    state = np.array([0.0, 0.0, theta, 0.0, 0.0, q])
    assert abs(free.accelerations(0.01, state)[1] - dd) > 1.0


def test_slip_enters_only_through_the_strip_velocity() -> None:
    """``Q W`` and ``Q^T W`` differ only in the strip velocity: identical loads without a body
    rate (q = 0) or without aerodynamics, different ones with both."""
    state = np.array([0.0, 0.0, 1.05, 0.1, -0.1, 0.0])
    spun = state + np.array([0.0, 0.0, 0.0, 0.0, 0.0, 4.0])
    for kwargs, y, same in (({}, state, True), ({"aerodynamics": False}, spun, True),
                            ({}, spun, False)):
        a = FwuavPitchFree("hawkmoth", body_rate_term="fwuav", **kwargs).rhs(0.004, y)
        b = FwuavPitchFree("hawkmoth", body_rate_term="rotated", **kwargs).rhs(0.004, y)
        assert np.array_equal(a, b) is same


def test_liouville_formula_for_the_monodromy() -> None:
    """det M = exp(int_0^T trace J dt): M from central differences of the flow (no Jacobian),
    the trace from the model's Jacobian; a Jacobian 1 % off fails the same check."""
    model = FwuavPitchFree("hawkmoth")
    fun, jac = _reduced(model)
    y0 = np.array([1.05, -0.1, 0.1, 0.3])

    def end(y: np.ndarray) -> np.ndarray:
        return solve_ivp(fun, (0.0, model.period), y, method="DOP853", rtol=1e-11,
                         atol=1e-12).y[:, -1]

    h = 1e-5
    M = np.column_stack([(end(y0 + h * e) - end(y0 - h * e)) / (2 * h) for e in np.eye(4)])
    good = monodromy(fun, y0, model.period, jac=jac, rtol=1e-8, atol=1e-9)
    bad = monodromy(fun, y0, model.period, jac=lambda t, y: 1.01 * jac(t, y), rtol=1e-8,
                    atol=1e-9)
    det = np.linalg.det(M)
    assert abs(det / np.exp(good.trace_integral) - 1.0) < 1e-5
    assert abs(det / np.exp(bad.trace_integral) - 1.0) > 1e-3
    assert good.liouville_error < 1e-6


def test_bad_arguments_are_named() -> None:
    with pytest.raises(ValueError, match="pitch"):
        FwuavPitchFree("hawkmoth", pitch="loose")
    with pytest.raises(ValueError, match="insect"):
        FwuavPitchFree("monarch")
    with pytest.raises(ValueError, match="rtol"):
        pitch_free_floquet("hawkmoth", rtol=1e-2)


def _retrimmed_model(result: PitchFreeFloquet) -> FwuavPitchFree:
    base = species(result.name)
    changes: dict[str, Any] = dict(zip(result.trim_parameters, result.trim_values, strict=True))
    sp = dataclasses.replace(base, kinematics=dataclasses.replace(base.kinematics, **changes))
    return FwuavPitchFree(sp, body_rate_term=result.body_rate_term)


# at rtol 1e-6 the monodromy's own integration closes the orbit to ~2e-6, just above its
# CLOSURE_TOL of 1e-6 (the integration error, not the orbit: at the book's 1e-8 it closes to 3e-9)
_LOOSE = pytest.mark.filterwarnings("ignore::flapping.errors.ClosureWarning")


@pytest.mark.slow
@_LOOSE
def test_trimmed_pitch_free_orbit_hovers() -> None:
    """Re-trimmed (phi_m, phi_0), FWUAV's pitch-free hawkmoth flies a closed orbit with zero mean
    velocity: checked by an independent integration of the six states (position included) with
    the trimmed kinematics. Untrimmed it sinks at ~0.15 m/s; the trim's residual is 1e-6 m of
    position per period (3e-5 m/s), the integrations' error ~1e-6 relative."""
    result = pitch_free_floquet("hawkmoth", rtol=1e-6, trim=True)
    assert result.trim_parameters == ("phi_m", "phi_0")
    model = _retrimmed_model(result)
    y0 = np.concatenate([[0.0, 0.0], result.y0])
    end = solve_ivp(model.rhs, (0.0, model.period), y0, method="DOP853", rtol=1e-10,
                    atol=1e-12).y[:, -1]
    mean_velocity = end[:2] / model.period
    assert np.abs(mean_velocity).max() < 1e-4  # m/s
    np.testing.assert_allclose(end[2:], result.y0, atol=1e-5)
    assert np.abs(result.mean_velocity).max() < 1e-4
    assert result.residual_norm <= 1e-6


@pytest.mark.slow
@_LOOSE
def test_trim_moves_the_kinematics_a_little() -> None:
    """The trim is a correction of FWUAV's kinematics, not another insect: the stroke amplitude
    and the mean stroke angle move, each by less than 5 degrees, and the amplitude grows (the
    untrimmed orbit sinks: it needs more lift)."""
    result = pitch_free_floquet("hawkmoth", rtol=1e-6, trim=True)
    k = species("hawkmoth").kinematics
    d_amplitude = result.trim_values[0] - k.phi_m
    d_mean = result.trim_values[1] - k.phi_0
    assert 0.0 < d_amplitude < np.radians(5.0)
    assert 1e-4 < abs(d_mean) < np.radians(5.0)
    assert result.trim_nfev > 0


@pytest.mark.parametrize("trim", [("phi_m",), ("phi_m", "phi_m"), ("f", "phi_0"), "phi_m",
                                  ("phi_m", "phi_0", "beta"), 1])
def test_bad_trim_is_refused(trim: object) -> None:
    with pytest.raises(ValueError, match="`trim` must be True, False or two different names"):
        pitch_free_floquet("hawkmoth", trim=trim)  # type: ignore[arg-type]


def test_untrimmed_result_has_no_trim_fields() -> None:
    """Old construction of the result still works: the trim fields default to 'no trim'."""
    fields = {f.name for f in dataclasses.fields(PitchFreeFloquet) if f.default is
              dataclasses.MISSING}
    assert "trim_parameters" not in fields and "trim_values" not in fields


def test_a_failed_trim_says_what_failed(monkeypatch: pytest.MonkeyPatch) -> None:
    """A trim that does not converge raises ConvergenceError naming the insect and the trimmed
    parameters, with the shooting's residual and iteration count (the solver is replaced by
    one that fails, so the test is fast)."""
    from flapping.errors import ConvergenceError
    from flapping.peers.fwuav import attitude

    def fail(*args: object, **kwargs: object) -> None:
        raise ConvergenceError("stalled", x=np.zeros(6), residual=0.25, iterations=7)

    monkeypatch.setattr(attitude, "find_periodic_orbit", fail)
    with pytest.raises(ConvergenceError, match="hawkmoth by adjusting beta, phi_0") as info:
        pitch_free_floquet("hawkmoth", rtol=1e-6, trim=("beta", "phi_0"))
    assert info.value.residual == 0.25 and info.value.iterations == 7


def test_pitch_free_model_carries_the_trimmed_kinematics() -> None:
    # a result as the trim returns it (the orbit's numbers do not enter the model)
    zero = np.zeros(4)
    result = PitchFreeFloquet(
        name="hawkmoth", body_rate_term="rotated", y0=zero, period=0.03, multipliers=zero,
        exponents=zero, mean_pitch=0.0, pitch_amplitude=0.0, mean_velocity=np.zeros(2),
        residual_norm=0.0, liouville_error=0.0, monodromy=np.eye(4),
        trim_parameters=("phi_m", "phi_0"), trim_values=(0.9, -0.07))
    model = pitch_free_model(result)
    k, base = model.species.kinematics, species("hawkmoth").kinematics
    assert (k.phi_m, k.phi_0) == (0.9, -0.07) and k.beta == base.beta and k.f == base.f
    assert model.hover.body_rate_term == "rotated"
    untrimmed = pitch_free_model(dataclasses.replace(result, trim_parameters=(), trim_values=()))
    assert untrimmed.species.kinematics == base
    with pytest.raises(ValueError, match="result"):
        pitch_free_model("hawkmoth")  # type: ignore[arg-type]

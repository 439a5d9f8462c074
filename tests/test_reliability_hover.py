"""Bad input to the hover layer and the studies answered at the root: one reproducer each."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import flapping
from flapping.hover import (
    HOVER_SPEED_ATOL,
    HoverStatus,
    find_hover_orbit,
    force_budget,
)
from flapping.hover.branch import continue_hover
from flapping.hover.stability import hover_stability, perturbation_growth, simulate_perturbation


@pytest.fixture(scope="module")
def orbit():
    return find_hover_orbit(flapping.hawkmoth(), backend="adaptive")


def test_hover_is_also_an_absolute_speed(orbit):
    # Reproducer: at a wingtip speed of ~1e11 m/s the relative test alone called an orbit that
    # flies at 4406 m/s "hover". The tolerance is the smaller of the two.
    assert orbit.hover_speed_tol == min(1e-6 * orbit.wingtip_speed, HOVER_SPEED_ATOL)
    fast = dataclasses.replace(orbit, mean_velocity=np.array([4406.0, 0.0]))
    object.__setattr__(fast, "amplitude", 1e9)  # a wingtip speed that swallows any drift
    assert fast.wingtip_speed * 1e-6 > 4406.0
    assert fast.status == HoverStatus.DRIFTING and not fast.is_hover


@pytest.mark.parametrize(("index", "value"), [(0, 1e300), (1, -1e3), (2, 1e6), (3, 100.0)])
def test_an_absurd_state_guess_is_refused_with_its_component(index, value):
    # Reproducer: x0_guess of 1e300 ended in "`fun` returned a non-finite value".
    guess = [0.0, 0.0, 0.0, 0.0]
    guess[index] = value
    with pytest.raises(ValueError, match=rf"`x0_guess\[{index}\]`"):
        find_hover_orbit(flapping.hawkmoth(), x0_guess=guess)


def test_a_branch_towards_a_value_no_insect_has_is_refused_at_once():
    # Reproducer: continue_hover towards a negative frequency walked for ever.
    with pytest.raises(ValueError, match="`end` = -5.0 is outside the range of 'frequency'"):
        continue_hover(flapping.hawkmoth(), "frequency", -5.0)
    with pytest.raises(ValueError, match="`end`"):
        continue_hover(flapping.hawkmoth(), "frequency", math.nan)


def test_sizes_are_capped(orbit):
    # Reproducer: force_budget(n_samples=10**7) ran for ever.
    with pytest.raises(ValueError, match="`n_samples`"):
        force_budget(orbit, 10**7)
    stability = hover_stability(orbit)
    with pytest.raises(ValueError, match="`n_periods`"):
        perturbation_growth(stability, n_periods=10**9)
    with pytest.raises(ValueError, match="`samples_per_period`"):
        simulate_perturbation(orbit, 1e-6, samples_per_period=10**8)


def test_a_perturbation_is_a_perturbation(orbit):
    # Reproducer: epsilon 1e300 blew the simulation up with a message about `fun`.
    with pytest.raises(ValueError, match="`epsilon`"):
        simulate_perturbation(orbit, 1e300)


def test_sensitivity_fields_name_what_can_be_varied():
    from flapping.studies.atlas import morphology_sensitivity

    # Reproducer: the paper's hawkmoth has no ranged field and the message listed "()".
    with pytest.raises(ValueError, match="has no number with a plausible range"):
        morphology_sensitivity("hawkmoth", fields=["foo"])
    with pytest.raises(ValueError, match="`fields` must be a sequence"):
        morphology_sensitivity("hawkmoth", fields="r2")

"""The hover orbit continued in an insect field (flapping.hover.branch)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from flapping.hover import find_hover_orbit
from flapping.hover.branch import continue_hover
from flapping.model.morphology import hawkmoth
from flapping.periodic.floquet import monodromy


@pytest.fixture(scope="module")
def frequency_branch():
    return continue_hover(hawkmoth(), "frequency", 28.0, ds=0.5, ds_max=1.0)


def test_each_point_is_the_hover_orbit_find_hover_orbit_finds(frequency_branch):
    # two independent routes (Levenberg-Marquardt at one frequency; continuation from 26.3 Hz)
    # to the same orbit and amplitude: tolerances 1e-10/1e-9, so agreement to ~1e-8
    assert frequency_branch.success and frequency_branch.p[-1] == 28.0
    for k in (len(frequency_branch) // 2, -1):
        insect = dataclasses.replace(hawkmoth(), frequency=float(frequency_branch.p[k]))
        orbit = find_hover_orbit(insect)
        assert abs(orbit.amplitude - frequency_branch.params[k, 0]) < 1e-8
        np.testing.assert_allclose(frequency_branch.x0[k, :4], orbit.x0, atol=1e-8)
        assert frequency_branch.x0[k, 4] == 0.0  # z(0) held


def test_branch_multipliers_are_the_orbits_floquet_multipliers(frequency_branch):
    orbit = find_hover_orbit(hawkmoth())
    rhs, jac = orbit.model.segment_functions()
    mon = monodromy(rhs, orbit.x0, orbit.period, jac=jac, breakpoints=orbit.model.breakpoints)
    np.testing.assert_allclose(frequency_branch.multipliers[0], mon.multipliers, rtol=1e-7)
    # one multiplier outside the unit circle all along (the hawkmoth's unstable hover), and it
    # shrinks as the frequency rises
    mods = np.abs(frequency_branch.multipliers)
    assert (mods[:, 0] > 1).all() and (mods[:, 1:] < 1).all()
    assert np.all(np.diff(mods[:, 0]) < 0)
    assert frequency_branch.bifurcations == ()


def test_centre_of_pressure_branch():
    branch = continue_hover(hawkmoth(), "center_of_pressure", 0.35, ds=0.05, ds_max=0.05)
    assert branch.success and branch.bifurcations == ()
    mods = np.abs(branch.multipliers)
    assert (mods[:, 0] > 1).all() and np.all(np.diff(mods[:, 0]) > 0)


def test_unknown_field_is_a_valueerror():
    with pytest.raises(ValueError, match="numeric field of Insect"):
        continue_hover(hawkmoth(), "wingspan", 1.0)

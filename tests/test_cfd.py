"""CFD derivatives as data and our model on their insect (flapping.studies.cfd, issue 28)."""

import math

import numpy as np
import pytest

import flapping.studies.cfd
from flapping.studies import cfd

# ------------------------------------------------------------------ item 1: the data

#: Half a unit of the last printed digit of each published number, relative: the rounding the
#: reproduced value may differ by (0.32 s, 0.1 s, 0.024 s, 0.37 s in Sun & Xiong's abstract).
ROUNDING = {"oscillation_period": 0.005 / 0.32, "doubling_time": 0.05 / 0.1,
            "fast_halving": 0.0005 / 0.024, "slow_halving": 0.005 / 0.37}


def test_every_number_has_a_source_a_table_and_a_known_status():
    for s in cfd.STUDIES.values():
        assert set(s.derivatives) == set(cfd.DERIVATIVES)
        for n in [*s.derivatives.values(), *s.reference.values()]:
            assert n.status in cfd.STATUSES and n.source and n.table
            assert math.isfinite(n.value)
        assert all(n.status == "read" for n in s.derivatives.values())


def test_a_number_with_an_unknown_status_is_refused():
    with pytest.raises(ValueError, match="status"):
        cfd.Number(1.0, "somebody", "-", "guessed")


def test_an_unknown_study_names_the_known_ones():
    with pytest.raises(ValueError, match="sun2005"):
        cfd.study("nobody2099")


def test_sun_xiong_reference_quantities_follow_their_definitions():
    s = cfd.study("sun2005")
    u = 2.0 * math.radians(116.0) * (1.0 / 6.4e-3) * 0.55 * 13.2e-3
    assert s.speed == pytest.approx(u, rel=1e-14)
    assert s.period == pytest.approx(6.4e-3, rel=1e-14)
    assert s.gravity_ratio == pytest.approx(9.81 * 6.4e-3 / u, rel=1e-14)
    # m+ = m / (0.5 rho U S T) with S the two wings
    assert s.mass_ratio() == pytest.approx(175e-6 / (0.5 * 1.225 * u * 2 * 13.2e-3 * 4.01e-3
                                                      * 6.4e-3), rel=1e-14)


def test_the_published_matrix_maps_to_the_dimensional_one_and_back():
    """A = D A+ D^-1 / T and A+ = T D^-1 A D are inverse; the derivatives come back."""
    s = cfd.study("sun2005")
    a_plus = s.matrix(80.0, 12.0)
    d = s.scaling()
    a = d @ a_plus @ np.linalg.inv(d) / s.period
    assert a[0, 3] == pytest.approx(-9.81, rel=1e-12)  # -g theta in SI
    back = s.period * np.linalg.solve(d, a) @ d
    np.testing.assert_allclose(cfd._derivatives_of(back, 80.0, 12.0), s.derivative_vector(),
                               rtol=1e-12)


def test_sun_xiong_derivatives_reproduce_their_published_modes():
    """Four published numbers, two identified (m+, I+): each reproduced within its rounding.

    The doubling time is printed to one figure (0.1 s), so it bounds little; the period and the
    two halving times (two figures) are three conditions on two unknowns.
    """
    check = cfd.check_transcription("sun2005")
    errors = check.relative_errors()
    for name, tol in ROUNDING.items():
        assert abs(errors[name]) <= tol, (name, errors[name], tol)
    assert cfd.mode_summary(check.eigenvalues)["type"] == "oscillatory"
    assert check.eigenvalues[0].real > 0.0 > check.eigenvalues[2].real


def test_a_transcription_slip_breaks_the_reproduction():
    """The check can fail: M_u+ read as 2.839 (two digits swapped) misses the rounding bounds."""
    s = cfd.study("sun2005")
    slipped = dict(s.derivatives)
    slipped["Mu"] = cfd.Number(2.839, "test", "-", "estimated")
    bad = cfd.CFDStudy(s.key, s.insect, slipped, s.reference, s.modes)
    mp, ip = cfd.identify_mass_and_inertia(bad)
    ev = np.linalg.eigvals(bad.matrix(mp, ip)) / bad.period
    numbers = cfd._mode_numbers(ev)
    rel = (numbers - bad.modes.targets()) / np.abs(bad.modes.targets())
    assert np.max(np.abs(rel[[1, 2, 3]])) > min(ROUNDING.values())


def test_identified_mass_and_inertia_are_those_of_a_bumblebee():
    """m+ within 10 % of the morphology's (rho, S of the CFD not read: 6 % apart), and I_y
    between the ellipsoid estimates of a 15-20 mm, 5-8 mm body (1e-9 .. 6e-9 kg m^2)."""
    check = cfd.check_transcription("sun2005")
    assert check.mass_ratio == pytest.approx(check.mass_ratio_morphology, rel=0.10)
    assert 1e-9 < check.pitch_inertia < 6e-9


def test_the_unattributed_table_is_kept_out():
    assert cfd.UNATTRIBUTED and all("why" in t for t in cfd.UNATTRIBUTED)
    for s in cfd.STUDIES.values():
        assert s.derivatives["Xu"].value != -1.28


def test_mode_summary_reads_the_leading_mode():
    osc = cfd.mode_summary([1.0 + 2.0j, 1.0 - 2.0j, -3.0])
    assert osc["type"] == "oscillatory" and osc["period"] == pytest.approx(math.pi)
    assert osc["doubling_time"] == pytest.approx(math.log(2.0))
    real = cfd.mode_summary([0.5, -1.0 + 1.0j, -1.0 - 1.0j])
    assert real["type"] == "real" and real["period"] == math.inf
    assert cfd.mode_summary([-1.0, -2.0])["doubling_time"] == math.inf


def test_the_module_is_importable_by_its_dotted_name():
    assert flapping.studies.cfd.compare is cfd.compare

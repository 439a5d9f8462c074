"""Tests of the insect morphology (flapping.model.morphology): beta chord distribution, span integrals
I_mn (paper, after eq. 29), the lift slope of eq. (4), and input validation.
"""

from __future__ import annotations

import dataclasses
import math
import re
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate, special

from flapping.errors import PlausibilityWarning
from flapping.model.morphology import Insect, beta_shape_parameters, hawkmoth, lev_lift_slope


@pytest.fixture(scope="module")
def moth():
    return hawkmoth()


def span_integral_by_quad(insect, m, n):
    """2 int_0^R r^m c(r)^n dr by adaptive quadrature of Insect.chord, independent of the
    closed form. The substitution r = R v**g with g = 1/(1 + n(p-1)) turns the root singularity
    r^(n(p-1)) dr into a bounded integrand (v^(g m) times the smooth tip factor)."""
    R = insect.semi_span
    g = 1.0 / (1.0 + n * (insect.beta_p - 1.0))

    def integrand(v):
        r = R * v**g
        return r**m * insect.chord(r) ** n * R * g * v ** (g - 1.0)

    value, _ = integrate.quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-13, limit=200)
    return 2.0 * value


# ----------------------------------------------------------------------------- span integrals
@pytest.mark.parametrize("n", range(5))
@pytest.mark.parametrize("m", range(4))
def test_span_integral_closed_form_matches_quadrature(moth, m, n):
    # Two independent evaluations of I_mn; QUADPACK reaches ~1e-13 on the regularised integrand.
    assert moth.span_integral(m, n) == pytest.approx(span_integral_by_quad(moth, m, n),
                                                     rel=1e-11)


@pytest.mark.parametrize("k", [1, 2])
def test_first_moments_of_area_reproduce_ellington_radii(moth, k):
    # Ellington's radii: r_k^k = int r^k c dr / (S R^k) for one wing, so I_k1 = 2 S R^k r_k^k.
    r_k = {1: moth.r1, 2: moth.r2}[k]
    assert moth.span_integral(k, 1) == pytest.approx(
        2.0 * moth.wing_area * moth.semi_span**k * r_k**k, rel=1e-13)


def test_chord_integrates_to_wing_area(moth):
    area, _ = integrate.quad(moth.chord, 0.0, moth.semi_span, limit=200, epsrel=1e-12)
    assert area == pytest.approx(moth.wing_area, rel=1e-9)   # endpoint singularity: QUADPACK
    assert moth.span_integral(0, 1) == pytest.approx(2.0 * moth.wing_area, rel=1e-13)
    assert moth.mean_chord == pytest.approx(moth.wing_area / moth.semi_span, rel=1e-15)


def test_chord_vanishes_outside_the_wing(moth):
    R = moth.semi_span
    np.testing.assert_array_equal(moth.chord(np.array([-1e-3, R, 1.5 * R])), 0.0)
    assert np.all(moth.chord(np.linspace(1e-6, R * (1 - 1e-6), 50)) > 0.0)


def test_divergent_span_integral_raises(moth):
    # n(p-1) + m + 1 <= 0: the root singularity of c^n is not integrable.
    n = math.ceil(1.0 / (1.0 - moth.beta_p)) + 1
    with pytest.raises(ValueError, match="diverges"):
        moth.span_integral(0, n)


@settings(max_examples=60, deadline=None)
@given(r1=st.floats(0.05, 0.95), fraction=st.floats(0.01, 0.99))
def test_beta_moments_reproduce_r1_and_r2(r1, fraction):
    # The beta distribution with the fitted (p, q) has mean r1 and mean square r2^2.
    r2 = r1 + fraction * (math.sqrt(r1) - r1)
    k = r1 * (1.0 - r1) / (r2**2 - r1**2) - 1.0
    if min(r1 * k, (1.0 - r1) * k) <= 0.5:  # the squared chord would not be integrable
        with pytest.raises(ValueError, match="`r2`"):
            beta_shape_parameters(r1, r2)
        return
    p, q = beta_shape_parameters(r1, r2)
    assert p > 0.5 and q > 0.5
    assert p / (p + q) == pytest.approx(r1, rel=1e-12)
    assert p * (p + 1.0) / ((p + q) * (p + q + 1.0)) == pytest.approx(r2**2, rel=1e-10)


def test_hawkmoth_shape_and_lift_slope(moth):
    # Appendix: r1 = 0.44, r2 = 0.525 give p < 1 (chord singular at the root) and q > 1.
    assert moth.beta_p == pytest.approx(0.88174, abs=1e-5)
    assert moth.beta_q == pytest.approx(1.12222, abs=1e-5)
    assert moth.aspect_ratio == pytest.approx(2 * 51.9**2 / 947.8, rel=1e-12)
    assert moth.with_(aspect_ratio_convention="single").aspect_ratio == pytest.approx(
        51.9**2 / 947.8, rel=1e-12)


def test_lift_slope_limits():
    # eq. (4): A -> a0/2 for an infinite wing, A ~ pi AR / 4 for a slender one.
    assert lev_lift_slope(1e9) == pytest.approx(math.pi, rel=1e-8)
    assert lev_lift_slope(1e-6) == pytest.approx(math.pi * 1e-6 / 4, rel=1e-9)


# ----------------------------------------------------------------------------- validation
POSITIVE_FIELDS = ["semi_span", "wing_area", "frequency", "mass", "pitch_inertia",
                   "air_density", "a0", "stroke_amplitude"]


@settings(max_examples=80, deadline=None)
@given(name=st.sampled_from(POSITIVE_FIELDS),
       value=st.one_of(st.floats(max_value=0.0), st.just(math.nan), st.just(math.inf),
                       st.just(-math.inf)))
def test_non_positive_or_non_finite_sizes_raise_naming_the_parameter(name, value):
    with pytest.raises(ValueError, match=name):
        hawkmoth(**{name: value})


@pytest.mark.parametrize("name", ["gravity", "mu1", "mu2", "hinge_offset", "r1", "r2",
                                  "pitch_axis", "center_of_pressure"])
def test_nan_parameters_raise_naming_the_parameter(name):
    with pytest.raises(ValueError, match=name):
        hawkmoth(**{name: math.nan})


@pytest.mark.parametrize("name", ["gravity", "mu1", "mu2"])
def test_negative_nonnegative_parameters_raise(name):
    with pytest.raises(ValueError, match=name):
        hawkmoth(**{name: -0.1})


@settings(max_examples=60, deadline=None)
@given(r1=st.floats(0.05, 0.95), offset=st.floats(0.0, 0.5))
def test_r2_outside_the_beta_range_raises(r1, offset):
    # A beta distribution needs r1 < r2 < sqrt(r1) (positive variance, positive p and q).
    for r2 in (r1 - offset, math.sqrt(r1) + offset):
        with pytest.raises(ValueError, match="r2"):
            hawkmoth(r1=r1, r2=r2)


@pytest.mark.parametrize("r1", [0.0, 1.0, -0.2, 1.5])
def test_r1_outside_unit_interval_raises(r1):
    with pytest.raises(ValueError, match="r1"):
        beta_shape_parameters(r1, 0.5)


@pytest.mark.parametrize("amplitude", [math.pi / 2 + 1e-12, 2.0, math.pi])
def test_stroke_amplitude_above_ninety_degrees_raises(amplitude):
    with pytest.raises(ValueError, match="stroke_amplitude"):
        hawkmoth(stroke_amplitude=amplitude)
    hawkmoth(stroke_amplitude=math.pi / 2)      # the limit itself is allowed


@pytest.mark.parametrize("name, value", [("pitch_axis", 1.2), ("center_of_pressure", -0.1),
                                         ("aspect_ratio_convention", "both")])
def test_other_out_of_range_parameters_raise(name, value):
    with pytest.raises(ValueError, match=name):
        hawkmoth(**{name: value})


def test_with_revalidates_and_insect_is_hashable(moth):
    with pytest.raises(ValueError, match="mass"):
        moth.with_(mass=-1.0)
    assert moth.with_(mass=moth.mass) == moth
    assert hash(moth.with_(mass=moth.mass)) == hash(moth)
    assert isinstance(moth, Insect)


# ----------------------------------------------------------------------------- types on entry
NUMERIC_FIELDS = POSITIVE_FIELDS + ["gravity", "mu1", "mu2", "hinge_offset", "r1", "r2",
                                    "pitch_axis", "center_of_pressure"]


@pytest.mark.parametrize("value", ["0.001648", True, np.bool_(False), None, 1e-3 + 0j, [1e-3]])
def test_mass_that_is_not_a_real_number_is_refused(value):
    # "0.001648" was accepted and failed later with a TypeError; True was 1 kg.
    with pytest.raises(ValueError, match=r"`mass` must be a real number in \[1e-11, 20\] kg"):
        hawkmoth(mass=value)


@settings(max_examples=80, deadline=None)
@given(name=st.sampled_from(NUMERIC_FIELDS),
       value=st.sampled_from([True, False, "1", None, b"1", 1j]))
def test_bools_strings_and_none_are_refused_naming_the_field(name, value):
    with pytest.raises(ValueError, match=f"`{name}`"):
        hawkmoth(**{name: value})


@pytest.mark.parametrize("convert", [np.float32, np.float64, np.array, float])
def test_every_field_is_stored_as_a_python_float(moth, convert):
    # A float32 mass used to leak into the derivatives (hover then failed after 107 s).
    values = {name: convert(getattr(moth, name)) for name in NUMERIC_FIELDS}
    insect = hawkmoth(**values)
    for name in NUMERIC_FIELDS:
        assert type(getattr(insect, name)) is float, name
        assert getattr(insect, name) == float(convert(getattr(moth, name)))


def test_numpy_integers_are_accepted_as_floats():
    insect = hawkmoth(frequency=np.int64(26), gravity=np.int32(10), hinge_offset=np.int8(0))
    assert (insect.frequency, insect.gravity, insect.hinge_offset) == (26.0, 10.0, 0.0)
    assert all(type(v) is float for v in (insect.frequency, insect.gravity, insect.hinge_offset))
    assert insect == hawkmoth(frequency=26.0, gravity=10.0, hinge_offset=0.0)


def test_float32_insect_equals_and_hashes_as_its_float64_value():
    m32 = np.float32(1.648e-3)
    assert hawkmoth(mass=m32) == hawkmoth(mass=float(m32))
    assert hash(hawkmoth(mass=m32)) == hash(hawkmoth(mass=float(m32)))


def test_name_must_be_a_string():
    with pytest.raises(ValueError, match="`name`"):
        hawkmoth(name=1)


@pytest.mark.parametrize("m, n", [(True, 1), ("1", 1), (1, None)])
def test_span_integral_orders_must_be_numbers(moth, m, n):
    with pytest.raises(ValueError, match="`[mn]`"):
        moth.span_integral(m, n)


def test_lift_slope_arguments_are_checked():
    with pytest.raises(ValueError, match="`aspect_ratio`"):
        lev_lift_slope(0.0)
    with pytest.raises(ValueError, match="`a0`"):
        lev_lift_slope(5.0, a0=True)


# ----------------------------------------------------------------------------- fast copies
def _copy_by_constructor(insect, **changes):
    """The copy as the constructor builds it (every field validated again)."""
    values = {f.name: getattr(insect, f.name) for f in dataclasses.fields(insect) if f.init}
    return Insect(**{**values, **changes})


@settings(max_examples=60, deadline=None)
@given(st.dictionaries(
    st.sampled_from(["frequency", "mass", "r1", "r2", "semi_span", "hinge_offset", "mu1",
                     "stroke_amplitude", "center_of_pressure", "name"]),
    st.one_of(st.floats(-1.0, 60.0), st.integers(-3, 50), st.just("x"), st.booleans()),
    max_size=3))
def test_with_equals_the_constructor_field_by_field(moth, changes):
    # with_ checks only the changed fields: its copy (or its error) must be the constructor's.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)  # the next test checks them
        try:
            expected = _copy_by_constructor(moth, **changes)
        except (ValueError, TypeError) as exc:
            with pytest.raises(type(exc), match=re.escape(str(exc))):
                moth.with_(**changes)
            return
        copy = moth.with_(**changes)
    assert copy == expected and copy.name == expected.name
    assert (copy.beta_p, copy.beta_q) == (expected.beta_p, expected.beta_q)
    assert all(type(getattr(copy, f)) is type(getattr(expected, f))
               for f in ("frequency", "mass", "r1", "r2"))


def test_with_warns_and_refuses_as_the_constructor(moth):
    with pytest.warns(PlausibilityWarning, match="frequency"):
        moth.with_(frequency=5e3)  # inside the physical range [0.1, 1e4] Hz, beyond 2000 Hz
    with pytest.raises(ValueError, match=r"`frequency` must be a real number in \[0.1, 10000\]"):
        moth.with_(frequency=1e5)
    with pytest.raises(TypeError, match="wing_span"):
        moth.with_(wing_span=1.0)
    with pytest.raises(ValueError, match="r2"):
        moth.with_(r1=0.6)  # r2 = 0.525 < r1: the pair is checked again when r1 changes


def test_span_integrals_are_exact_whatever_the_type_of_the_orders(moth):
    # Integer orders skip validation and cached values are reused: the closed form must not
    # move by a single bit (the book glues numbers built on it).
    for m, n in [(0, 1), (2, 1), (3, 4), (1, 2)]:
        value = moth.span_integral(m, n)
        assert value == moth.span_integral(float(m), np.float64(n))
        p, q = moth.beta_p, moth.beta_q
        a, b = m + n * (p - 1.0) + 1.0, n * (q - 1.0) + 1.0
        direct = 2.0 * math.exp((m + 1.0) * math.log(moth.semi_span)
                                + n * (math.log(moth.mean_chord) - special.betaln(p, q))
                                + special.betaln(a, b))
        assert value == direct

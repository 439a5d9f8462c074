"""The paper's printed numbers (flapping_book.paper): each is what its comment says it is, and the
consistency checks on eq. (66) agree with one another."""

import math

import numpy as np
import pytest

import flapping
from flapping_book import paper


@pytest.fixture(scope="module")
def moth():
    return flapping.hawkmoth()


@pytest.fixture(scope="module")
def eq66(moth):
    return paper.check_monodromy_eq66(moth)


def test_printed_period_is_the_appendix_frequency_not_the_text_one(moth):
    # T = 0.0380 s is 1/26.3 Hz (the appendix, our hawkmoth) rounded to the 4 decimals printed;
    # 1/26.5 Hz (the text) would print as 0.0377.
    assert moth.frequency == pytest.approx(26.3)
    assert round(1.0 / moth.frequency, 4) == paper.TEXT_PERIOD_S
    assert round(1.0 / paper.TEXT_FREQUENCY_HZ, 4) != paper.TEXT_PERIOD_S


def test_appendix_mean_chord_is_s_over_r_rounded(moth):
    s_over_r_mm = moth.wing_area / moth.semi_span * 1e3
    assert s_over_r_mm == pytest.approx(18.26, abs=0.005)
    assert round(s_over_r_mm, 1) == paper.APPENDIX_MEAN_CHORD_MM


def test_step_size_is_two_to_the_minus_ten_of_a_period():
    assert paper.STEPS_PER_PERIOD == 1024 == round(2.0 ** 10)


def test_table1_angles_are_a_tenth_of_a_degree_in_radians():
    assert paper.TABLE1_GUESS["q"] == paper.TABLE1_GUESS["theta"] == pytest.approx(
        math.radians(0.1), rel=1e-15)


def test_table2_theta_is_two_pi_plus_a_small_angle_and_inside_fig6_ticks():
    # "theta = 6.3345 is 2 pi + 0.0513 if in radians", to the 4 decimals printed.
    assert paper.TABLE2_STATE["theta"] - 2 * math.pi == pytest.approx(0.0513, abs=5e-5)
    low, high = paper.FIG6_PANEL4_TICKS
    assert low < paper.TABLE2_STATE["theta"] < high


def test_eq67_multipliers_are_the_eigenvalues_of_eq66_to_the_printed_digits(eq66):
    # Both are printed with 4 decimals: they agree within half a unit of the last one.
    def ordered(mu):
        return sorted(mu, key=lambda z: (-round(abs(z), 6), z.imag))

    for ours, printed in zip(ordered(eq66.eigenvalues_eq66), ordered(paper.MULTIPLIERS_EQ67),
                             strict=True):
        assert abs(ours - printed) < 5e-5


def test_eq66_determinant_is_the_product_of_its_eigenvalues_and_within_the_sign_range(eq66):
    assert eq66.det_eq66 == pytest.approx(np.prod(eq66.eigenvalues_eq66).real, rel=1e-12)
    low, high = eq66.det_range
    assert low <= eq66.det_eq66 <= high
    # The lost signs move the determinant in the fourth decimal only (products of small terms).
    assert high - low < 1e-3


def test_liouville_determinant_is_the_product_of_the_uncoupled_diagonal(eq66):
    # exp(mean(Xu) T) exp(mean(Zw) T) exp(mean(Mq) T) = exp(int trace J dt): two routes, one number.
    assert np.prod(eq66.diagonal_uncoupled) == pytest.approx(eq66.liouville_det, rel=1e-12)
    # The paper's model damps u, w and q on average (Xu, Zw, Mq < 0).
    assert np.all(eq66.diagonal_uncoupled[:3] < 1.0)
    assert eq66.diagonal_uncoupled[3] == 1.0


def test_eq66_is_not_a_monodromy_of_the_papers_model_whatever_its_signs(eq66):
    # The book's finding: Liouville's formula fixes det = liouville_det, far below every
    # determinant the printed matrix can have with any choice of the lost signs.
    assert eq66.liouville_det < 0.5 * eq66.det_range[0]
    np.testing.assert_array_equal(eq66.diagonal_eq66, np.diag(paper.MONODROMY_EQ66))
    assert np.sum(eq66.diagonal_eq66 == 1.0) == 3


def test_liouville_determinant_converges_at_second_order(moth):
    # Trapezoid rule on a periodic integrand with kinks at stroke reversal: error ~ h^2, so
    # doubling the samples divides it by about 4 (3.9 to 4.1 measured at 256..2048 samples).
    reference = paper.check_monodromy_eq66(moth, 16384).liouville_det
    errors = [abs(paper.check_monodromy_eq66(moth, n).liouville_det - reference)
              for n in (512, 1024)]
    assert 3.0 < errors[0] / errors[1] < 5.0
    assert errors[1] < 1e-5 * reference

"""The one validator module: numbers become float64, bools and strings are refused, messages name
the argument and the accepted range."""

import math

import numpy as np
import pytest

from flapping import _validation as check


@pytest.mark.parametrize("value", [np.float32(0.5), np.int64(2), np.array(0.25), 3])
def test_numpy_scalars_become_python_floats(value):
    out = check.real("x", value)
    assert type(out) is float and out == float(value)


@pytest.mark.parametrize("value", [True, np.bool_(False), "1.0", None, 1 + 0j])
def test_bools_strings_and_complex_are_refused_naming_the_argument(value):
    with pytest.raises(ValueError, match="`mass`"):
        check.positive("mass", value)


def test_the_message_gives_the_range():
    with pytest.raises(ValueError, match=r"\(0, pi/2\) rad"):
        check.real("alpha_m", math.pi / 2, low=0.0, high=math.pi / 2, low_open=True,
                   high_open=True, unit="rad")


def test_integral_floats_are_not_counts():
    assert check.integer("n", np.int32(4), low=1) == 4
    with pytest.raises(ValueError, match="`n`"):
        check.integer("n", 4.0)


@pytest.mark.parametrize("value", [[True, False], ["1", "2"], [1.0, np.nan], [], [[1.0]]])
def test_vector_refuses_bools_strings_non_finite_and_wrong_shapes(value):
    with pytest.raises(ValueError, match="`x0`"):
        check.vector("x0", value)


def test_vector_is_a_float64_copy():
    source = np.array([1, 2], dtype=np.int32)
    out = check.vector("x0", source)
    assert out.dtype == np.float64 and out is not source
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        check.vector("x0", [1.0, 2.0], size=3)


@pytest.mark.parametrize("value", [10**400, -(10**400), 10**5000],
                         ids=["1e400", "-1e400", "1e5000"])
def test_integers_beyond_float64_are_a_value_error_naming_the_argument(value):
    # hawkmoth(mass=10**400) was an OverflowError from float(); 10**5000 has no repr at all
    # (Python's int-to-string limit), so the message must not print it in full.
    with pytest.raises(ValueError, match=r"`mass` must be a real number in \(0, inf\) kg") as e:
        check.positive("mass", value, unit="kg")
    assert "float64" in str(e.value) and len(str(e.value)) < 300


def test_a_huge_count_is_named_without_printing_every_digit():
    with pytest.raises(ValueError, match=r"`n_points` must be an integer in \[1, 100\]") as e:
        check.integer("n_points", 10**5000, low=1, high=100)
    assert len(str(e.value)) < 300


# ---- user callables: args and non-finite values (issue 26, item 6) ------------------------------


@pytest.mark.parametrize("value", [5, 1.5, None, "ab", b"ab"])
def test_args_that_are_not_a_sequence_are_named(value):
    # args=5 used to reach Python's "'int' object is not iterable" inside an integration
    with pytest.raises(ValueError, match=r"`args` must be a tuple"):
        check.call_args(value)


@pytest.mark.parametrize(("value", "expected"), [((), ()), ((1, 2), (1, 2)), ([1, 2], (1, 2)),
                                                 (np.array([1.0]), (1.0,))])
def test_args_sequences_become_tuples(value, expected):
    assert check.call_args(value) == expected


def test_finite_output_raises_a_valueerror_carrying_where():
    from flapping.errors import NonFiniteError

    with pytest.raises(NonFiniteError, match=r"`jac` returned a non-finite value at t = 0\.25") \
            as error:
        check.finite_output("jac", np.array([[np.inf]]), 0.25, [2.0])
    assert isinstance(error.value, ValueError)
    assert error.value.source == "jac" and error.value.t == 0.25
    assert error.value.state.tolist() == [2.0]
    assert "blowing up" not in str(error.value)  # a moderate state: the callable's own fault


def test_finite_output_at_a_huge_state_says_the_solution_blows_up():
    with pytest.raises(ValueError, match=r"the solution is blowing up: max \|x\| = 1e\+200"):
        check.finite_output("fun", np.array([np.inf]), 1.0, [1e200])

"""The variational right-hand side of continuation (flapping.periodic._branchflow).

Its hot loop calls the user's functions directly and checks the output once; these tests pin
that the result equals the plain formulas, (f, J [Phi | S] + [0 | df/dp]), and that a bad
output is still reported by name.
"""

from __future__ import annotations

import numpy as np
import pytest

from flapping.periodic import _segments as seg
from flapping.periodic._branchflow import _Field, _Params, _VariationalField
from flapping.periodic.testproblems import rossler, rossler_jac


def _field(fun, jac, c=2.5):
    field = _Field(fun, np.array([c]), _Params(0), 3, seg.Counter())
    return _VariationalField(field, jac, 1)


def f_rossler(t, x, c):
    return rossler(t, x, c=c)


def j_rossler(t, x, c):
    return rossler_jac(t, x, c=c)


def test_variational_field_is_the_state_the_stm_and_the_sensitivity():
    rng = np.random.default_rng(1)
    x, block = rng.normal(size=3), rng.normal(size=(3, 4))
    out = _field(f_rossler, j_rossler)(0.3, np.concatenate([x, block.ravel()]))
    J = rossler_jac(0.3, x, c=2.5)
    assert np.array_equal(out[:3], rossler(0.3, x, c=2.5))
    np.testing.assert_allclose(out[3:].reshape(3, 4)[:, :3], J @ block[:, :3], rtol=1e-15)
    dfdc = np.array([0.0, 0.0, -x[2]])  # Roessler: z' = b + z (x - c)
    np.testing.assert_allclose(out[3:].reshape(3, 4)[:, 3], J @ block[:, 3] + dfdc, atol=1e-7)


def test_without_jac_the_jacobian_comes_from_differences():
    x = np.array([1.0, -2.0, 0.5])
    y = np.concatenate([x, np.hstack([np.eye(3), np.zeros((3, 1))]).ravel()])
    with_jac = _field(f_rossler, j_rossler)(0.0, y)
    np.testing.assert_allclose(_field(f_rossler, None)(0.0, y), with_jac, atol=1e-7)


@pytest.mark.parametrize(("fun", "jac", "message"), [
    (lambda t, x, c: np.zeros(2), j_rossler, "`fun` must return an array of shape"),
    (f_rossler, lambda t, x, c: np.zeros((3, 2)), "`jac` must return an array of shape"),
    (lambda t, x, c: np.full(3, np.nan), j_rossler, "`fun` returned a non-finite value"),
    (f_rossler, lambda t, x, c: np.full((3, 3), np.inf), "`jac` returned a non-finite value"),
])
def test_bad_output_is_named(fun, jac, message):
    y = np.concatenate([np.ones(3), np.hstack([np.eye(3), np.zeros((3, 1))]).ravel()])
    with pytest.raises(ValueError, match=message):
        _field(fun, jac)(0.0, y)


@pytest.mark.filterwarnings("ignore::RuntimeWarning")  # the user's function meets inf
def test_non_finite_state_is_a_divergence():
    y = np.concatenate([[np.inf, 0.0, 0.0], np.hstack([np.eye(3), np.zeros((3, 1))]).ravel()])
    with pytest.raises(seg.Diverged):
        _field(f_rossler, j_rossler)(0.0, y)

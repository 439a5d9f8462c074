"""The package's own DOP853 tableau against scipy's (the fixed-step solver and the compiled kernel
do not import scipy's private module, so a scipy release that moved it cannot break them, and this
test says if the coefficients ever differ)."""

import numpy as np
import pytest

from flapping.periodic import _tableau as _dop853

scipy_tableau = pytest.importorskip("scipy.integrate._ivp.dop853_coefficients")


def test_tableau_equals_scipys_bit_for_bit():
    n = scipy_tableau.N_STAGES
    assert n == _dop853.N_STAGES
    assert np.array_equal(_dop853.A, scipy_tableau.A[:n, :n])  # exact: the same decimal literals
    assert np.array_equal(_dop853.B, scipy_tableau.B)
    assert np.array_equal(_dop853.C, scipy_tableau.C[:n])


def test_tableau_is_consistent_and_read_only():
    # Row sums of A equal the nodes (to rounding of the 30-digit literals), weights sum to 1.
    np.testing.assert_allclose(_dop853.A.sum(axis=1), _dop853.C, rtol=0, atol=1e-14)
    assert abs(_dop853.B.sum() - 1.0) < 1e-14
    for array in (_dop853.A, _dop853.B, _dop853.C):
        assert not array.flags.writeable


def test_the_kernel_reads_the_same_arrays():
    from flapping.fast import _dop853 as kernel_tableau

    for name in ("A", "B", "C", "N_STAGES"):
        assert getattr(kernel_tableau, name) is getattr(_dop853, name)

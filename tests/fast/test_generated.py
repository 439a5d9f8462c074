"""The kernel's derivatives are generated from the SymPy derivation and equal the model's."""

from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.fast import _generated
from flapping.fast.kernel import KernelProblem
from flapping.model.dynamics import LongitudinalDynamics

GENERATED = Path(flapping.__file__).parent / "fast" / "_generated.py"


def test_generated_kernel_code_is_what_the_derivation_produces():
    pytest.importorskip("sympy")
    from flapping.model import derivation

    assert GENERATED.read_text() == derivation.generate_numba_source()


@pytest.mark.parametrize("hinge_offset", [0.0, 1.5e-3])  # x_h != 0 exercises every term
def test_generated_kernel_derivatives_equal_the_models(hinge_offset):
    # Same expressions, other printing (trig values passed in, constants packed in an array):
    # the values agree to rounding, 1e-13 relative to each derivative's scale over the period.
    insect = flapping.hawkmoth(hinge_offset=hinge_offset)
    problem = KernelProblem.of(insect)
    amplitude = 1.05
    model = LongitudinalDynamics(insect, amplitude=amplitude)
    omega = 2 * np.pi * insect.frequency
    times = np.linspace(0.013, 0.987, 11) * insect.period
    ours, ref = np.empty((times.size, 24)), np.empty((times.size, 24))
    for i, t in enumerate(times):
        phi, phidot = amplitude * np.cos(omega * t), -omega * amplitude * np.sin(omega * t)
        args = (phi, phidot, abs(phidot), np.sin(phi), np.cos(phi), np.sin(2 * phi),
                np.cos(2 * phi), problem.k, ours[i])
        _generated.derivatives_and_amplitude(*args)
        ref[i, :12] = model.derivatives(t)
        ref[i, 12:] = np.array(model.amplitude_derivatives(t)) * amplitude
    scale = np.abs(ref).max(axis=0)
    assert np.all(np.abs(ours - ref) <= 1e-13 * scale), np.max(np.abs(ours - ref) / scale, axis=0)
    plain = np.empty(12)
    _generated.derivatives(*args[:-1], plain)
    np.testing.assert_allclose(plain, ours[-1, :12], rtol=1e-13, atol=0)

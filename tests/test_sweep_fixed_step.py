"""Sweeps of the blade-element loads: the fixed-step path by name (and by "auto"), rows built from
the HoverOrbit as on the other paths."""

import math

import numpy as np
import pytest

import flapping
from flapping.hover import find_hover_orbit
from flapping.hover.stability import hover_stability

pytest.importorskip("pandas")
pytest.importorskip("tqdm")
from flapping.studies.sweep import sweep_hover  # noqa: E402

GRID = {"hinge_height": [0.0, 1e-3]}


@pytest.mark.slow  # 1-2 min: three blade-element orbits and their fixed-step analyses, in Python
def test_a_blade_element_sweep_runs_the_fixed_step_path():
    table = sweep_hover(flapping.hawkmoth(), GRID, progress=False, aerodynamics="small-angle",
                        backend="fixed-step")
    assert table.backend.tolist() == ["fixed-step", "fixed-step"]
    assert table.converged.all() and (table.message == "").all()
    assert (table.n_steps >= 64).all() and (table.amplitude_error_deg < 1e-8).all()
    # The first point starts cold: its row is the orbit find_hover_orbit finds on that path,
    # and the multipliers and their error estimate are hover_stability's on that path, exactly.
    orbit = find_hover_orbit(flapping.hawkmoth(), aerodynamics="small-angle",
                             backend="fixed-step")
    row = table.iloc[0]
    assert row.amplitude_deg == orbit.amplitude_deg and row.nit == orbit.nit
    assert row.amplitude_error_deg == math.degrees(orbit.fixed_step.unknowns_error[4])
    stability = hover_stability(orbit, backend="fixed-step")
    np.testing.assert_array_equal([row[f"mu{i}_real"] for i in range(1, 5)],
                                  stability.multipliers.real)
    assert row.multiplier_error == stability.multiplier_error > 0.0


def test_the_kernel_is_refused_at_once_for_the_blade_element_loads():
    with pytest.raises(ValueError, match="backend='compiled' does not apply"):
        sweep_hover(flapping.hawkmoth(), GRID, progress=False, aerodynamics="exact",
                    backend="compiled")
    with pytest.raises(ValueError, match="aerodynamics"):
        sweep_hover(flapping.hawkmoth(), GRID, progress=False, aerodynamics="quasi-steady")
    with pytest.raises(ValueError, match="backend"):
        sweep_hover(flapping.hawkmoth(), GRID, progress=False, backend="fixed_step")

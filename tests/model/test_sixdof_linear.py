"""The paper's linear loads (eq. 29) in six degrees of freedom (flapping.model.sixdof_linear_derivation).

Checked against the planar derivation's derivatives (its own SymPy path and generated code), the
small-angle blade-element loads of the six-degree-of-freedom model (central differences at the
zero state), and mirror symmetry (the lateral and longitudinal sets decouple).
"""

from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import flapping
from flapping.model import sixdof_linear_derivation
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.sixdof import LATERAL, LONGITUDINAL, SixDofDynamics

GENERATED = Path(sixdof_linear_derivation.__file__).with_name("_sixdof_linear_generated.py")
LATERAL_INERTIA = dict(roll_inertia=1.6e-8, yaw_inertia=2.1e-7, roll_yaw_product=3e-9)
GEOMETRIES = {
    "paper": {},
    "hinge": dict(hinge_offset=2e-3, hinge_height=3e-3, stroke_mean=0.1),
    "wings": dict(wing_mass=4.7e-5, hinge_offset=1e-3, hinge_height=-2e-3),
}
#: Loads (X, Z, M) and velocities (u, w, q) of the plane of symmetry; (Y, L, N) and (v, p, r).
LON, LAT = [0, 2, 4], [1, 3, 5]


def moth(**changes):
    return flapping.hawkmoth().with_(**{**LATERAL_INERTIA, **changes})


def test_the_generated_code_is_what_the_derivation_prints():
    assert GENERATED.read_text() == sixdof_linear_derivation.generate_source()


@pytest.mark.parametrize("geometry", list(GEOMETRIES))
def test_the_plane_of_symmetry_gives_the_planar_derivatives(geometry):
    insect = moth(**GEOMETRIES[geometry])
    six = SixDofDynamics(insect, aerodynamics="linear")
    four = LongitudinalDynamics(insect)
    m, iy = insect.mass, insect.pitch_inertia
    times = np.linspace(0.0, insect.period, 61)[:-1] + 1e-3 * insect.period
    ours, planar = [], []
    for t in times:
        loads0, d = six.linear_loads(t)
        ours.append([loads0[0], loads0[2], loads0[4], d[0, 0] / m, d[0, 2] / m, d[0, 4] / m,
                     d[2, 0] / m, d[2, 2] / m, d[2, 4] / m, d[4, 0] / iy, d[4, 2] / iy,
                     d[4, 4] / iy])
        planar.append(four.derivatives(t))
    ours, planar = np.array(ours), np.array(planar)
    scale = np.max(np.abs(planar), axis=0)  # each derivative's size over the stroke
    assert np.all(scale > 0.0)
    np.testing.assert_array_less(np.abs(ours - planar) / scale, 1e-12)


def test_lateral_and_longitudinal_sets_decouple_symbolically():
    loads0, d = sixdof_linear_derivation.linear_loads()
    for i in LAT:
        assert sp.simplify(loads0[i]) == 0
        for j in LON:
            assert sp.simplify(d[i, j]) == 0 and sp.simplify(d[j, i]) == 0
    # ... and the lateral derivatives do not vanish: Y_v, L_p, N_r are the damping ones.
    for i in LAT:
        assert sp.simplify(d[i, i]) != 0


@pytest.mark.parametrize("geometry", ["hinge", "wings"])
def test_the_derivatives_are_those_of_the_small_angle_loads(geometry):
    insect = moth(**GEOMETRIES[geometry])
    linear = SixDofDynamics(insect, aerodynamics="linear")
    blade = SixDofDynamics(insect, aerodynamics="small-angle", n_nodes=64)
    rng = np.random.default_rng(11)
    for t in rng.uniform(0.0, insect.period, 8):
        loads0, d = linear.linear_loads(t)
        np.testing.assert_allclose(blade.loads(t, np.zeros(8)), loads0, rtol=1e-10,
                                   atol=1e-12 * np.max(np.abs(loads0)))
        h = 1e-6
        numeric = np.empty((6, 6))
        for j in range(6):
            step = np.zeros(8)
            step[j] = h
            numeric[:, j] = (blade.loads(t, step) - blade.loads(t, -step)) / (2.0 * h)
        # Each load's row against its largest derivative (the rows differ in units).
        scale = np.max(np.abs(d), axis=1, keepdims=True)
        np.testing.assert_array_less(np.abs(numeric - d) / scale, 1e-6)


def test_the_linear_loads_are_affine_in_the_velocities():
    insect = moth(**GEOMETRIES["hinge"])
    model = SixDofDynamics(insect, aerodynamics="linear")
    rng = np.random.default_rng(5)
    t = 0.3 * insect.period
    x = rng.normal(size=8) * [0.5, 0.5, 0.5, 5.0, 5.0, 5.0, 0.3, 0.3]
    loads0, d = model.linear_loads(t)
    np.testing.assert_allclose(model.loads(t, x), loads0 + d @ x[:6], rtol=1e-13,
                               atol=1e-15)


@pytest.mark.parametrize("geometry", list(GEOMETRIES))
def test_the_plane_of_symmetry_is_the_planar_linear_model(geometry):
    insect = moth(**GEOMETRIES[geometry])
    six = SixDofDynamics(insect, aerodynamics="linear")
    four = LongitudinalDynamics(insect, aerodynamics="linear")
    rng = np.random.default_rng(7)
    for _ in range(12):
        t = rng.uniform(0.0, insect.period)
        x4 = rng.normal(size=4) * [0.5, 0.5, 5.0, 0.3]
        x8 = np.zeros(8)
        x8[list(LONGITUDINAL)] = x4
        f8, f4 = six.rhs(t, x8), four.rhs(t, x4)
        np.testing.assert_allclose(f8[list(LONGITUDINAL)], f4, rtol=1e-11, atol=1e-12)
        np.testing.assert_allclose(f8[list(LATERAL)], 0.0, atol=1e-12 * np.max(np.abs(f4)))

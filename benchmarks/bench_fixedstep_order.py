"""Order of the fixed-step DOP853 period map on the hover fields, per aerodynamic model and mesh.

Why the hover problem's fixed-step backend grades its mesh: on a *uniform* mesh the period map of
:mod:`flapping.periodic._fixedmap` converges at order 8 on eq. (29)'s linear loads, but at order
1-4 (erratically) on the blade-element loads, even with the kinks marked as switching functions
(U = 0 at the wing root, u - q h_w = 0, and at the tip, (u - q h_w) cos(phi) + phi_dot R = 0).
After the tip crossing, ~1.7e-4 T past stroke reversal at u = 0.02 m/s, the sign-change station
r* = -u_c / phi_dot ~ 1/t sweeps in from the tip: the loads are analytic there but vary on the
time scale of that crossing, which a uniform step of T/2n resolves only for n in the thousands.

Measured on the uniform mesh (hawkmoth, x = (0.02, -0.05, 0.3, 0.01), Phi at its nominal value,
error of x(T) against 512-1024 steps per half-stroke):

    n     linear    small-angle   small-angle + switches   exact
    8     3.8e-08   1.1e-04       3.4e-05                  1.4e-04
    16    1.5e-10   4.8e-05       1.5e-05                  2.0e-05
    32    5.1e-13   1.6e-05       6.4e-06                  6.5e-07
    64    2.7e-15   8.8e-07       2.0e-06                  2.1e-07
    128   (floor)   1.4e-06       3.9e-07                  2.5e-08

The graded mesh of :meth:`flapping.hover.HoverProblem.graded_fields` (t = T (k + g(s)) / 2 per
half-stroke, g' ~ sin^4(pi s): steps shrink as s^4 towards the reversals) with the root and tip
switches (the backend adds q = 0, the rotational damping's kink, which matters for the monodromy)
restores order ~8 (hinge height 10 mm, against 1024 steps; the script uses 512):

    n     small-angle graded + switches   (graded, no switches)
    16    2.9e-07                          9.4e-07
    32    9.2e-10                          1.5e-08
    64    6.7e-12                          6.0e-10
    128   1.4e-13                          5.2e-11

and the exact loads behave alike (1.5e-06, 2.5e-09, 1.4e-11, 5.7e-14 at h = 0). Run:
``python benchmarks/bench_fixedstep_order.py [small-angle|exact|linear] [uniform|graded]``
(~1 min per model and mesh).
"""

from __future__ import annotations

import math
import sys

import numpy as np

from flapping.hover.problem import HoverProblem
from flapping.model.morphology import hawkmoth
from flapping.periodic._fixedmap import PeriodMap


def switches(problem: HoverProblem) -> list:
    """The blade-element loads' kinks: U = 0 at the root and at the tip of the wing."""
    insect = problem.insect
    R, h_w, omega = insect.semi_span, insect.hinge_height, 2.0 * math.pi * insect.frequency

    def root(t, y, p):
        return y[0] - y[2] * h_w

    def tip(t, y, p):
        phi = insect.stroke_mean + p[0] * math.cos(omega * t)
        return (y[0] - y[2] * h_w) * math.cos(phi) - omega * p[0] * math.sin(omega * t) * R

    return [root, tip]


def errors(aerodynamics: str, marked: bool, steps=(8, 16, 32, 64, 128),
           graded: bool = False) -> list[float]:
    """max |x(T) - x_ref(T)| of the period map at each step count."""
    if graded:
        problem = HoverProblem(hawkmoth(hinge_height=10e-3), aerodynamics)
        funs, marks = problem.graded_fields()
        gs = marks if marked else ()
        pmap = PeriodMap(funs, [None, None], [None, None], (), 2.0, (0.5,), True, 10**9, gs)
    else:
        problem = HoverProblem(hawkmoth(), aerodynamics)
        funs = problem.fields()[0]
        gs = [switches(problem)] * 2 if marked else ()
        pmap = PeriodMap(funs, [None, None], [None, None], (), problem.period,
                         problem.model.breakpoints, True, 10**9, gs)
    x, p = np.array([[0.02, -0.05, 0.3, 0.01, 0.0]]), problem.guess()[None, :]
    reference = pmap.flow(x, p, 512)[0]
    return [float(np.max(np.abs(pmap.flow(x, p, n)[0] - reference))) for n in steps]


def main(model: str = "small-angle", mesh: str = "graded") -> None:
    for marked in (False, True) if model != "linear" else (False,):
        found = errors(model, marked, graded=mesh == "graded")
        orders = np.log2(np.array(found[:-1]) / np.array(found[1:]))
        print(f"{model}, {mesh} mesh{' + switches' if marked else ''}: errors {np.array(found)}, "
              f"observed orders {np.round(orders, 2)}")


if __name__ == "__main__":
    main(*sys.argv[1:3])

"""Numbers printed in the paper, in one place, and consistency checks on them.

These are the paper's *results* (Elsadek, El-Bayoumi & Taha, Sec. IV), kept so that the book can
set them beside ours and test them for consistency with the paper's own model. They are never used
as targets of a computation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flapping.model.derivatives import stability_derivatives
from flapping.model.morphology import Insect

__all__ = [
    "APPENDIX_MEAN_CHORD_MM",
    "TEXT_FREQUENCY_HZ",
    "TEXT_PERIOD_S",
    "STEPS_PER_PERIOD",
    "FIG6_PANEL4_TICKS",
    "FIG6_Q_TICK_MAX",
    "TABLE1_GUESS",
    "TABLE2_STATE",
    "HOVER_AMPLITUDE_DEG",
    "MONODROMY_EQ66",
    "MULTIPLIERS_EQ67",
    "MonodromyConsistency",
    "check_monodromy_eq66",
]

#: Appendix A prints the mean chord as 18.3 mm; S/R of its R and S is 18.26 mm [mm].
APPENDIX_MEAN_CHORD_MM = 18.3

#: Sec. III writes the flapping frequency as 26.5 Hz [Hz] ...
TEXT_FREQUENCY_HZ = 26.5

#: ... and the period as T = 0.0380 s, which is 1/26.3 Hz, the appendix's frequency [s].
TEXT_PERIOD_S = 0.0380

#: Integration steps per period of the paper's fixed-step scheme: "Botha chose the step size to be
#: 2^-10. The same step size is used in this work." (Sec. III.A; also the shooting offset delta).
STEPS_PER_PERIOD = 2**10

#: Tick-label range of the fourth panel of the paper's Fig. 6 (labelled "h m", around Table 2's
#: theta0), as printed.
FIG6_PANEL4_TICKS = (6.332, 6.336)

#: Largest tick label of the q panel of Fig. 6 (axis labelled "q (m/sec)"), as printed.
FIG6_Q_TICK_MAX = 20.0

#: Table 1, the initial guess (u [m/s], w [m/s], q [rad/s], theta [rad], h [m/s]).
TABLE1_GUESS = {"u": 0.1, "w": 0.1, "q": 0.1 * math.pi / 180, "theta": 0.1 * math.pi / 180,
                "h": 2.0}

#: Table 2, the initial state of the periodic orbit as printed (units not stated in the table;
#: Fig. 6 labels u, w in m/s and q in "m/sec"; theta = 6.3345 is 2 pi + 0.0513 if in radians).
TABLE2_STATE = {"u": -0.083375, "w": 1.777, "q": -1.1677, "theta": 6.3345}

#: The stroke amplitude "required to achieve hovering" (Sec. IV) [deg].
HOVER_AMPLITUDE_DEG = 61.0107

#: The monodromy matrix, eq. (66), signs as extracted (the minus signs were lost in the text).
MONODROMY_EQ66 = np.array([
    [1.0, 0.0007, 0.0497, 0.3725],
    [0.001, 1.0, 0.0027, 0.0195],
    [0.0001, 0.0027, 0.5933, 0.0001],
    [0.0, 0.0195, 0.0001, 1.0],
])

#: The Floquet multipliers, eq. (67).
MULTIPLIERS_EQ67 = np.array([0.5933 + 0j, 1.0258 + 0j, 0.9871 + 0.0108j, 0.9871 - 0.0108j])


@dataclass(frozen=True)
class MonodromyConsistency:
    """Tests of eq. (66) against what the paper's own model implies.

    Attributes
    ----------
    det_eq66 : float
        det of the printed matrix (with the extracted signs; ``|det|`` does not depend on the
        signs of the off-diagonal entries only to first order, see ``det_range``).
    det_range : tuple of float
        (min, max) of det over all 2^12 sign choices of the off-diagonal entries.
    liouville_det : float
        exp(int_0^T trace J dt) for the linear model eq. (29): trace J = Xu + Zw + Mq does not
        depend on the orbit (the f(x) part of eq. 45 has zero trace), so this is the determinant
        any monodromy of the paper's model must have.
    diagonal_eq66 : ndarray
        The printed diagonal.
    diagonal_uncoupled : ndarray
        exp(mean(Xu) T), exp(mean(Zw) T), exp(mean(Mq) T), 1: the diagonal the matrix would have
        if the states were uncoupled, an order-of-magnitude check of each entry.
    eigenvalues_eq66 : ndarray
        Eigenvalues of the printed matrix (compare with eq. 67).
    """

    det_eq66: float
    det_range: tuple[float, float]
    liouville_det: float
    diagonal_eq66: np.ndarray
    diagonal_uncoupled: np.ndarray
    eigenvalues_eq66: np.ndarray


def check_monodromy_eq66(insect: Insect, n_samples: int = 4096) -> MonodromyConsistency:
    """Test the printed monodromy (66) for consistency with the model's derivatives (eq. 29).

    Parameters
    ----------
    insect : Insect
        The insect (the hawkmoth for the paper's numbers).
    n_samples : int
        Uniform samples per period for the cycle means (trapezoid rule on a periodic integrand).
    """
    T = insect.period
    t = np.linspace(0.0, T, n_samples, endpoint=False)
    amp = math.radians(HOVER_AMPLITUDE_DEG)
    means = stability_derivatives(insect, t, amplitude=amp).cycle_mean()
    trace_integral = (means["Xu"] + means["Zw"] + means["Mq"]) * T
    off = [(i, j) for i in range(4) for j in range(4) if i != j]
    dets = []
    for bits in range(1 << len(off)):
        M = MONODROMY_EQ66.copy()
        for k, (i, j) in enumerate(off):
            if bits >> k & 1:
                M[i, j] = -M[i, j]
        dets.append(np.linalg.det(M))
    eig = np.linalg.eigvals(MONODROMY_EQ66)
    return MonodromyConsistency(
        det_eq66=float(np.linalg.det(MONODROMY_EQ66)),
        det_range=(float(min(dets)), float(max(dets))),
        liouville_det=math.exp(trace_integral),
        diagonal_eq66=np.diag(MONODROMY_EQ66).copy(),
        diagonal_uncoupled=np.exp(np.array([means["Xu"], means["Zw"], means["Mq"], 0.0]) * T),
        eigenvalues_eq66=eig[np.argsort(-np.abs(eig))],
    )

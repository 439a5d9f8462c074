"""The tableau of the 8th-order Runge-Kutta formula of Dormand and Prince (DOP853), 12 stages.

The coefficients of Hairer's Fortran code ``dop853.f`` (E. Hairer, S. P. Norsett and G. Wanner,
*Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993, sec. II.5 and II.10; the
method of P. J. Prince and J. R. Dormand, J. Comp. Appl. Math. 7 (1981) 67-75), written with the
same decimal literals as scipy's ``scipy/integrate/_ivp/dop853_coefficients.py`` (BSD-3-Clause),
so the float64 values are the same bit for bit (a test compares them with scipy's arrays). Only
what a fixed-step integration needs is kept: the 12 stages' nodes ``C``, couplings ``A`` and the
weights ``B`` of the 8th-order solution (no embedded error estimators, no dense output: both
solvers estimate their error by Richardson extrapolation instead).

Plain NumPy, no numba. Two integrators read it: the fixed-step periodic-orbit solver
(:mod:`flapping.periodic.fixedstep`) and the compiled hover kernel, which reads these arrays as
global constants through :mod:`flapping.fast._dop853` (the periodic layer lies below ``fast``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["N_STAGES", "A", "B", "C"]

#: Stages of the formula.
N_STAGES = 12

#: Nodes c_i of the stages.
C = np.array([
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
])

#: The non-zero couplings a_ij (i > j) as (i, j, a_ij).
_A_ENTRIES = (
    (1, 0, 5.26001519587677318785587544488e-2),
    (2, 0, 1.97250569845378994544595329183e-2),
    (2, 1, 5.91751709536136983633785987549e-2),
    (3, 0, 2.95875854768068491816892993775e-2),
    (3, 2, 8.87627564304205475450678981324e-2),
    (4, 0, 2.41365134159266685502369798665e-1),
    (4, 2, -8.84549479328286085344864962717e-1),
    (4, 3, 9.24834003261792003115737966543e-1),
    (5, 0, 3.7037037037037037037037037037e-2),
    (5, 3, 1.70828608729473871279604482173e-1),
    (5, 4, 1.25467687566822425016691814123e-1),
    (6, 0, 3.7109375e-2),
    (6, 3, 1.70252211019544039314978060272e-1),
    (6, 4, 6.02165389804559606850219397283e-2),
    (6, 5, -1.7578125e-2),
    (7, 0, 3.70920001185047927108779319836e-2),
    (7, 3, 1.70383925712239993810214054705e-1),
    (7, 4, 1.07262030446373284651809199168e-1),
    (7, 5, -1.53194377486244017527936158236e-2),
    (7, 6, 8.27378916381402288758473766002e-3),
    (8, 0, 6.24110958716075717114429577812e-1),
    (8, 3, -3.36089262944694129406857109825),
    (8, 4, -8.68219346841726006818189891453e-1),
    (8, 5, 2.75920996994467083049415600797e1),
    (8, 6, 2.01540675504778934086186788979e1),
    (8, 7, -4.34898841810699588477366255144e1),
    (9, 0, 4.77662536438264365890433908527e-1),
    (9, 3, -2.48811461997166764192642586468),
    (9, 4, -5.90290826836842996371446475743e-1),
    (9, 5, 2.12300514481811942347288949897e1),
    (9, 6, 1.52792336328824235832596922938e1),
    (9, 7, -3.32882109689848629194453265587e1),
    (9, 8, -2.03312017085086261358222928593e-2),
    (10, 0, -9.3714243008598732571704021658e-1),
    (10, 3, 5.18637242884406370830023853209),
    (10, 4, 1.09143734899672957818500254654),
    (10, 5, -8.14978701074692612513997267357),
    (10, 6, -1.85200656599969598641566180701e1),
    (10, 7, 2.27394870993505042818970056734e1),
    (10, 8, 2.49360555267965238987089396762),
    (10, 9, -3.0467644718982195003823669022),
    (11, 0, 2.27331014751653820792359768449),
    (11, 3, -1.05344954667372501984066689879e1),
    (11, 4, -2.00087205822486249909675718444),
    (11, 5, -1.79589318631187989172765950534e1),
    (11, 6, 2.79488845294199600508499808837e1),
    (11, 7, -2.85899827713502369474065508674),
    (11, 8, -8.87285693353062954433549289258),
    (11, 9, 1.23605671757943030647266201528e1),
    (11, 10, 6.43392746015763530355970484046e-1),
)

#: The non-zero weights b_j of the 8th-order solution as (j, b_j).
_B_ENTRIES = (
    (0, 5.42937341165687622380535766363e-2),
    (5, 4.45031289275240888144113950566),
    (6, 1.89151789931450038304281599044),
    (7, -5.8012039600105847814672114227),
    (8, 3.1116436695781989440891606237e-1),
    (9, -1.52160949662516078556178806805e-1),
    (10, 2.01365400804030348374776537501e-1),
    (11, 4.47106157277725905176885569043e-2),
)


def _dense(shape: tuple[int, ...], entries: tuple[tuple[float, ...], ...]) -> np.ndarray:
    """A read-only zero array of ``shape`` with the given (index..., value) entries set."""
    out = np.zeros(shape)
    for *index, value in entries:
        out[tuple(int(i) for i in index)] = value
    out.flags.writeable = False
    return out


#: Couplings a_ij, shape (12, 12), strictly lower triangular.
A = _dense((N_STAGES, N_STAGES), _A_ENTRIES)

#: Weights b_j of the 8th-order solution, shape (12,).
B = _dense((N_STAGES,), _B_ENTRIES)

C.flags.writeable = False

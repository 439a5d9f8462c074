"""What the studies that compare derivative sets share: the nine longitudinal derivatives' names,
the swap groups and the leading mode of a set of eigenvalues.

Private: :mod:`flapping.studies.cfd` and :mod:`flapping.studies.fwuav` re-export these names (a
study imports no other study, so what two share lives here).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["DERIVATIVES", "SWAP_GROUPS", "REAL_TOL", "mode_summary"]

#: The nine longitudinal derivatives, in the order of the matrix rows (X, Z, M) and columns
#: (u, w, q).
DERIVATIVES: tuple[str, ...] = ("Xu", "Xw", "Xq", "Zu", "Zw", "Zq", "Mu", "Mw", "Mq")

#: The groups a swap table swaps beyond the single terms: the speed-pitch coupling and its
#: damping (the u-q-theta block that carries the oscillation), and whole rows.
SWAP_GROUPS: tuple[tuple[str, ...], ...] = (
    ("Xu", "Mu"), ("Mu", "Mq"), ("Xu", "Mu", "Mq"), ("Xu", "Xq", "Mu", "Mq"),
    ("Xu", "Xw", "Xq"), ("Zu", "Zw", "Zq"), ("Mu", "Mw", "Mq"), DERIVATIVES)

#: An eigenvalue whose imaginary part is below this fraction of its modulus is real.
REAL_TOL = 1e-8


def mode_summary(eigenvalues: ArrayLike) -> dict[str, Any]:
    """The leading mode of a set of eigenvalues [1/s]: its type, rate, period and doubling time.

    Parameters
    ----------
    eigenvalues : array_like of complex
        Eigenvalues of a (dimensional) system matrix, or Floquet exponents [1/s].

    Returns
    -------
    dict
        ``type`` (``"oscillatory"`` if the eigenvalue of largest real part is complex, else
        ``"real"``), ``rate`` (its real part [1/s]), ``period`` [s] (inf if real) and
        ``doubling_time`` [s] (ln 2 / rate; inf if the rate is not positive).
    """
    ev = np.asarray(eigenvalues, dtype=complex)
    lead = ev[np.argmax(ev.real)]
    oscillatory = abs(lead.imag) > REAL_TOL * abs(lead)
    return {"type": "oscillatory" if oscillatory else "real", "rate": float(lead.real),
            "period": 2.0 * math.pi / abs(lead.imag) if oscillatory else math.inf,
            "doubling_time": math.log(2.0) / lead.real if lead.real > 0.0 else math.inf}

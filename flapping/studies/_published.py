"""Published numbers with their provenance, shared by the studies that read them.

:class:`Number` (a value with its source, table and status) and the reference quantities of
Sun & Xiong's (2005) bumblebee, which both the longitudinal comparison
(:mod:`flapping.studies.cfd`) and the lateral one (:mod:`flapping.studies.lateral`) use: data, not
a study, so that no study imports another.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from flapping import _validation

#: Statuses of a :class:`Number`: read in the source during this work, or not.
STATUSES: tuple[str, ...] = ("read", "estimated")


@dataclass(frozen=True)
class Number:
    """One published (or estimated) number with where it comes from.

    Attributes
    ----------
    value : float
        SI value (angles in rad), or the non-dimensional value of a derivative.
    source : str
        Who gives it (a {cite} key of ``book/references.bib`` first, then prose).
    table : str
        Where in the source ("Table 1", "abstract"), or "-" for an estimate.
    status : str
        One of :data:`STATUSES`.
    note : str
        How an estimate was made, or what to keep in mind.
    """

    value: float
    source: str
    table: str
    status: str
    note: str = ""

    def __post_init__(self) -> None:
        _validation.choice("status", self.status, STATUSES)


_SX = "sun2005"
_SX_MEMORY = ("sun2005 after dudley1990 (bumblebee BB01): from an earlier reading note and the "
              "bumblebee preset, not re-read here")


_BUMBLEBEE_BODY_LENGTH = 18e-3  # [m], dudley1990 (unverified)


def sun_xiong_2005_reference() -> dict[str, Number]:
    """Sun & Xiong's (2005) bumblebee: its reference quantities, each with its provenance."""
    body = _BUMBLEBEE_BODY_LENGTH
    return {
        "mass": Number(175e-6, _SX + "; berman2007", "-", "read",
                       "175 mg, as the bumblebee preset (verified there in FWUAV's data)"),
        "semi_span": Number(13.2e-3, _SX_MEMORY, "-", "estimated"),
        "mean_chord": Number(4.01e-3, _SX_MEMORY, "-", "estimated",
                             "Berman & Wang's 4.02 mm (verified) is 0.25 % longer"),
        "r2": Number(0.55, _SX_MEMORY, "-", "estimated"),
        "stroke_amplitude": Number(math.radians(116.0), _SX_MEMORY, "-", "estimated",
                                   "peak to peak"),
        "frequency": Number(1.0 / 6.4e-3, _SX, "abstract", "read",
                            "wingbeat period 6.4 ms"),
        "air_density": Number(1.225, "sea-level standard air", "-", "estimated",
                              "the density of the CFD not read"),
        "gravity": Number(9.81, "standard gravity", "-", "estimated"),
        "body_length": Number(body, "dudley1990 (bumblebee body length, unverified)", "-",
                              "estimated", "sets the hinge height below; not read in sun2005"),
        "hinge_height": Number(0.13 * body, "sun2007 (hoverfly: wing root to CG 0.13 body "
                               "lengths, the CG hanging below it) scaled to a bumblebee body "
                               "length of 18 mm (dudley1990, unverified)", "-", "estimated",
                               "Sun & Xiong's own hinge-to-CG distance and body angle were "
                               "not read: by analogy with Sun's group's hoverfly"),
        "hinge_offset": Number(0.0, "the CG directly below the wing root (a freely hanging "
                               "body, as Sun's group define their body angle)", "-",
                               "estimated"),
        "wing_mass": Number(4.6e-7, "berman2007 (verified in FWUAV's data, bumblebee preset)",
                            "-", "read", "used only in physics_table: the CFD derivatives are "
                            "aerodynamic"),
    }

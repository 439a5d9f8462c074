"""Lateral stability of the hovering insect, per preset, beside the published lateral results.

The six-degree-of-freedom hover layer (:mod:`flapping.hover.sixdof`) gives the eight Floquet
multipliers of (u, v, w, p, q, r, roll, theta) and their lateral block (v, p, r, roll), and the
cycle-averaged lateral derivatives (:func:`~flapping.hover.sixdof.averaged_lateral`). This study
reads them as modes:

- :func:`classify_multipliers`: the modes of a set of multipliers (a complex pair is one
  oscillatory mode; a positive real multiplier a divergence or a subsidence; a negative one a
  flip), with their growth rate, doubling or halving time in wingbeats and in ms, and the period
  of an oscillation;
- :func:`analyse`: one preset's orbit, stability and averaged lateral system (cached per
  preset and aerodynamic model);
- :func:`lateral_table`, :func:`mode_table`, :func:`derivative_table`: per preset, as pandas
  tables;
- :func:`inertia_sensitivity`: the leading lateral multiplier with the ESTIMATED roll and yaw
  inertia scaled (no preset has measured values);
- :data:`PUBLISHED_LATERAL` and :func:`compare_published`: what the CFD studies say about the
  lateral modes at hover, each record with its source, set beside ours mode by mode, mode type
  first.

Which presets: every preset with a roll and yaw inertia (:data:`LATERAL_PRESETS`). The monarch has
none: its body is FWUAV's measured thorax and abdomen, not the prolate ellipsoid of
:func:`flapping.model.presets.lateral_inertia_estimate`, and no roll or yaw inertia is recorded
for it.

Published lateral derivatives (Y_v ... N_r of Zhang & Sun 2010, Xu & Sun 2013, Xu & Sun 2015,
Zhu, Meng & Sun 2020) could not be read: the stored sources hold their abstracts (Zhang & Sun's
first page, Xu & Sun 2015's method section up to its inertia table, Zhu et al.'s introduction,
and for Xu & Sun 2013 the publisher's press release), and no derivative value. What was read is
kept as data (:data:`LATERAL_STUDIES`, :class:`LateralStudy`): the definitions of the
non-dimensional derivatives and the model dronefly's reference quantities (Xu & Sun 2015), and
the published modes (abstracts). :data:`PUBLISHED_LATERAL_DERIVATIVES` stays empty, and
:func:`check_lateral_transcription` says which terms are missing instead of checking them.

Sun's group's non-dimensional lateral system (:func:`lateral_system`, read in Xu & Sun 2015):
reference speed U = 2 Phi n r2 (Phi the stroke amplitude, peak to peak; r2 the radius of
gyration of the wing area), length c (mean chord), time T = 1/n, area S_t of both wings; forces
over 0.5 rho U^2 S_t, moments over 0.5 rho U^2 S_t c, v+ = v/U, p+ = p T, r+ = r T, t+ = t/T;
m+ = m / (0.5 rho U S_t T), I+ = I / (0.5 rho U^2 S_t c T^2), g+ = g T / U. Hover (u_e = 0,
theta_e = 0; x horizontal)::

    d/dt+ [v+, p+, r+, phi] = A+ [v+, p+, r+, phi]

    A+ = [[Y_v+/m+,          Y_p+/m+,          Y_r+/m+,          g+],
          [(I_z+ L+ + I_xz+ N+)_v / D, ..._p / D, ..._r / D,       0 ],
          [(I_xz+ L+ + I_x+ N+)_v / D, ..._p / D, ..._r / D,       0 ],
          [0,                1,                0,                0 ]],   D = I_x+ I_z+ - I_xz+^2

The dimensional eigenvalues are those of A+ over T. :func:`compare_lateral` puts our averaged
derivatives (:func:`~flapping.hover.sixdof.averaged_lateral`, whose ``nondimensional`` follows
these definitions; tests/test_lateral.py recomputes them from the definitions) into this system
beside the published modes, and :func:`term_table` asks which term decides the mode type.

What the evidence supports (tests/test_lateral.py checks each statement): in Sun's system with
our derivatives, only L_v+ and L_p+ change the mode types when changed alone, and L_v+'s sign
decides divergence against oscillation (the characteristic polynomial's constant term is
-g+ L_v+ over the inertia; :func:`lv_threshold` finds the change at L_v+ ~ 0). Our presets
have their wing roots at the CG and L_v+ > 0: a real divergence. Of Sun's group's dronefly
geometry (:func:`geometry_table`), the body inclined at 53.3 deg (a product of inertia I_xz,
:func:`inclined_body_inertia`) gives Zhang & Sun's mode types, averaged and Floquet alike; the
wing roots 0.13 body lengths above the CG bring L_v+ to about zero, where the averaged system
turns stable and Floquet keeps a slower divergence.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from types import MappingProxyType
from typing import Any

import numpy as np

from flapping import _validation as check
from flapping.errors import PlausibilityWarning
from flapping.hover.sixdof import (
    ANALYSIS_ATOL,
    ANALYSIS_RTOL,
    LATERAL_DERIVATIVE_NAMES,
    LateralDerivatives,
    SixDofHoverOrbit,
    SixDofStability,
    averaged_lateral,
    find_sixdof_hover_orbit,
    require_six_dof,
    sixdof_stability,
)
from flapping.model import presets
from flapping.model.sixdof import LATERAL, SIXDOF_AERODYNAMIC_MODELS
from flapping.periodic.floquet import floquet_multipliers, monodromy
from flapping.studies._published import Number, sun_xiong_2005_reference

__all__ = [
    "LATERAL_PRESETS", "NO_LATERAL_INERTIA", "Mode", "classify_multipliers", "LateralAnalysis",
    "analyse", "lateral_table", "mode_table", "derivative_table", "inertia_sensitivity",
    "PublishedLateral", "PUBLISHED_LATERAL", "PUBLISHED_LATERAL_DERIVATIVES",
    "compare_published", "published_rows", "MODE_KINDS",
    "LATERAL_STATES", "RATIO_NAMES", "LateralScales", "orbit_ratios", "lateral_system",
    "eigenvalue_modes", "LateralStudy", "LATERAL_STUDIES", "lateral_study",
    "check_lateral_transcription", "LateralComparison", "compare_lateral", "TERM_CHANGES",
    "term_table", "lv_threshold", "inclined_body_inertia", "geometry_table",
]

#: A multiplier is real when its imaginary part is below this fraction of its modulus.
REAL_TOL = 1e-9

#: The kinds of mode: (type, stable) -> the flight-dynamics name.
MODE_KINDS: dict[tuple[str, bool], str] = {
    ("real", False): "divergence",
    ("real", True): "subsidence",
    ("oscillatory", False): "oscillating divergence",
    ("oscillatory", True): "damped oscillation",
    ("flip", False): "unstable flip",
    ("flip", True): "stable flip",
}


#: The presets with a (estimated) roll and yaw inertia: the six-degree-of-freedom ones.
LATERAL_PRESETS: tuple[str, ...] = ("hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly")
#: The presets without, and why.
NO_LATERAL_INERTIA: dict[str, str] = {
    "monarch": "its body is FWUAV's measured thorax and abdomen, not the ellipsoid of "
               "lateral_inertia_estimate, and no roll or yaw inertia is recorded for it",
}


@dataclass(frozen=True)
class Mode:
    """One mode of a set of Floquet multipliers.

    Attributes
    ----------
    multiplier : complex
        The multiplier (of a complex pair, the one with positive imaginary part).
    type : str
        ``"real"`` (positive real), ``"oscillatory"`` (a complex pair) or ``"flip"`` (negative
        real: the sign alternates every period).
    stable : bool
        Modulus below 1.
    growth_rate : float
        ln(modulus) / T [1/s] (negative: decays).
    time_wingbeats : float
        ln 2 / abs(ln modulus): the doubling time (unstable) or the halving time (stable), in
        wingbeats; inf for a modulus of exactly 1.
    time_ms : float
        The same in ms.
    period_ms : float
        2 pi T / abs(arg multiplier) for an oscillatory mode [ms]; nan otherwise.
    """

    multiplier: complex
    type: str
    stable: bool
    growth_rate: float
    time_wingbeats: float
    time_ms: float
    period_ms: float

    @property
    def kind(self) -> str:
        """The flight-dynamics name: divergence, subsidence, oscillating divergence, ..."""
        return MODE_KINDS[(self.type, self.stable)]


def classify_multipliers(multipliers: Sequence[complex] | np.ndarray,
                         period: float) -> tuple[Mode, ...]:
    """The modes of a set of Floquet multipliers, by descending modulus.

    A complex-conjugate pair is one oscillatory mode; each real multiplier is one mode, real
    (positive) or flip (negative).

    Parameters
    ----------
    multipliers : sequence of complex
        The multipliers (e.g. :attr:`SixDofStability.lateral` ``.multipliers``), finite; a zero
        one (an underflowed subsidence) is a real stable mode with a halving time of 0.
    period : float
        The flapping period T [s].

    Returns
    -------
    tuple of Mode

    Raises
    ------
    ValueError
        If ``period`` is not positive, or a multiplier is not finite, or a complex
        multiplier has no conjugate partner.
    """
    period = check.positive("period", period, unit="s")
    mu = np.asarray(multipliers, dtype=complex).ravel()
    if mu.size == 0 or not np.all(np.isfinite(mu)):
        raise ValueError(f"`multipliers` must be finite (and at least one); got {mu!r}")
    modes = []
    complex_ = np.abs(mu.imag) > REAL_TOL * np.abs(mu)
    upper, lower = np.sort_complex(mu[complex_ & (mu.imag > 0)]), np.sort_complex(
        np.conj(mu[complex_ & (mu.imag < 0)]))
    if upper.size != lower.size or not np.allclose(upper, lower, rtol=1e-6, atol=0.0):
        raise ValueError(f"`multipliers` must come in complex-conjugate pairs; got {mu!r}")
    for m in list(mu[~complex_].real.astype(complex)) + list(upper):
        modulus = abs(m)
        # A multiplier of exactly 0 (a subsidence so fast that it underflows): halves at once.
        log_mod = -math.inf if modulus == 0.0 else math.log(modulus)
        time = math.inf if log_mod == 0.0 else math.log(2.0) / abs(log_mod)
        if m.imag != 0.0:
            kind, period_ms = "oscillatory", 1e3 * 2.0 * math.pi * period / abs(
                math.atan2(m.imag, m.real))
        else:
            kind, period_ms = ("flip" if m.real < 0 else "real"), math.nan
        modes.append(Mode(multiplier=complex(m), type=kind, stable=modulus < 1.0,
                          growth_rate=log_mod / period, time_wingbeats=time,
                          time_ms=1e3 * time * period, period_ms=period_ms))
    return tuple(sorted(modes, key=lambda mode: -abs(mode.multiplier)))


@dataclass(frozen=True)
class LateralAnalysis:
    """One preset's lateral stability.

    Attributes
    ----------
    name : str
        The preset.
    orbit : SixDofHoverOrbit
    stability : SixDofStability
        Its eight multipliers; the lateral modes are read from ``stability.lateral``.
    averaged : LateralDerivatives
        The cycle-averaged lateral derivatives and the averaged lateral system.
    modes : tuple of Mode
        The lateral block's modes (:func:`classify_multipliers`).
    """

    name: str
    orbit: SixDofHoverOrbit
    stability: SixDofStability
    averaged: LateralDerivatives
    modes: tuple[Mode, ...]

    @property
    def leading(self) -> Mode:
        """The lateral mode of largest modulus."""
        return self.modes[0]

    @property
    def stable(self) -> bool:
        """Every lateral multiplier inside the unit circle."""
        return all(m.stable for m in self.modes)


def _check_name(name: str) -> str:
    if name in NO_LATERAL_INERTIA:
        raise ValueError(f"`name` {name!r} has no roll or yaw inertia "
                         f"({NO_LATERAL_INERTIA[name]}); the presets with one: {LATERAL_PRESETS}")
    return check.choice("name", name, LATERAL_PRESETS)


@lru_cache(maxsize=16)
def _analysed(name: str, aerodynamics: str) -> LateralAnalysis:
    orbit = find_sixdof_hover_orbit(presets.preset(name), aerodynamics=aerodynamics)
    stability = sixdof_stability(orbit)
    return LateralAnalysis(name=name, orbit=orbit, stability=stability,
                           averaged=averaged_lateral(orbit),
                           modes=classify_multipliers(stability.lateral.multipliers,
                                                      orbit.period))


def analyse(name: str, aerodynamics: str = "small-angle") -> LateralAnalysis:
    """One preset's six-degree-of-freedom orbit, its eight multipliers and its lateral system.

    Cached per (preset, aerodynamic model): the analysis takes ~10-30 s.

    Parameters
    ----------
    name : str
        A preset of :data:`LATERAL_PRESETS`.
    aerodynamics : {"small-angle", "exact", "linear"}

    Returns
    -------
    LateralAnalysis

    Raises
    ------
    ValueError
        For a preset without lateral inertia (the monarch) or an unknown one, or an aerodynamic
        model not derived in six degrees of freedom.
    """
    name = _check_name(name)
    aerodynamics = check.choice("aerodynamics", aerodynamics, SIXDOF_AERODYNAMIC_MODELS)
    return _analysed(name, aerodynamics)


def _names(names: Iterable[str] | None) -> list[str]:
    if names is None:
        return list(LATERAL_PRESETS)
    if isinstance(names, str):
        names = [names]
    return [_check_name(n) for n in names]


def lateral_table(names: Iterable[str] | None = None,
                  aerodynamics: str = "small-angle") -> Any:
    """Per preset: the lateral multipliers, the leading mode and the averaged modes.

    Parameters
    ----------
    names : iterable of str, optional
        Presets (default :data:`LATERAL_PRESETS`).
    aerodynamics : {"small-angle", "exact", "linear"}

    Returns
    -------
    pandas.DataFrame
        Indexed by preset; columns ``frequency_hz``, ``multipliers`` (the four lateral ones, by
        descending modulus), ``mode_types`` (of the modes, e.g. ``"real, real, oscillatory"``),
        ``leading_multiplier``, ``leading_modulus``, ``leading_type``, ``leading_kind``,
        ``stable``, ``doubling_wingbeats``, ``doubling_ms`` (of the leading mode, when unstable;
        nan otherwise), ``floquet_exponents_per_s`` (ln(mu)/T of the modes),
        ``averaged_eigenvalues_per_s`` (the averaged lateral system's),
        ``averaged_leading_per_s``, ``coupling``, ``multiplier_error``, ``liouville_error``.
    """
    import pandas as pd

    rows = []
    for name in _names(names):
        a = analyse(name, aerodynamics)
        lead = a.leading
        unstable = not lead.stable
        rows.append({
            "preset": name, "frequency_hz": a.orbit.insect.frequency,
            "multipliers": tuple(complex(m) for m in a.stability.lateral.multipliers),
            "mode_types": ", ".join(m.type for m in a.modes),
            "leading_multiplier": lead.multiplier, "leading_modulus": abs(lead.multiplier),
            "leading_type": lead.type, "leading_kind": lead.kind, "stable": a.stable,
            "doubling_wingbeats": lead.time_wingbeats if unstable else math.nan,
            "doubling_ms": lead.time_ms if unstable else math.nan,
            "floquet_exponents_per_s": tuple(
                complex(np.log(m.multiplier)) / a.orbit.period for m in a.modes),
            "averaged_eigenvalues_per_s": tuple(complex(e) for e in a.averaged.eigenvalues),
            "averaged_leading_per_s": complex(a.averaged.eigenvalues[0]),
            "coupling": a.stability.coupling, "multiplier_error": a.stability.multiplier_error,
            "liouville_error": a.stability.liouville_error,
        })
    return pd.DataFrame(rows).set_index("preset")


def mode_table(names: Iterable[str] | None = None, aerodynamics: str = "small-angle") -> Any:
    """One row per lateral mode of each preset (Floquet), beside the averaged system's.

    The averaged eigenvalue beside a Floquet mode is the one of the same rank (both sorted by
    descending growth rate).

    Returns
    -------
    pandas.DataFrame
        Columns ``preset``, ``mode`` (1, 2, ... by descending modulus), ``multiplier``,
        ``modulus``, ``type``, ``kind``, ``stable``, ``time_wingbeats`` (doubling if unstable,
        halving if stable), ``time_ms``, ``period_ms`` (oscillatory modes), ``growth_rate_per_s``
        (ln of the modulus over T), ``averaged_eigenvalue_per_s``.
    """
    import pandas as pd

    rows = []
    for name in _names(names):
        a = analyse(name, aerodynamics)
        eig = list(a.averaged.eigenvalues)
        # One averaged eigenvalue per Floquet mode: of a pair, the one with positive imag.
        eig_modes = [e for e in eig if e.imag >= -REAL_TOL * abs(e)]
        for i, m in enumerate(a.modes):
            rows.append({
                "preset": name, "mode": i + 1, "multiplier": m.multiplier,
                "modulus": abs(m.multiplier), "type": m.type, "kind": m.kind,
                "stable": m.stable, "time_wingbeats": m.time_wingbeats, "time_ms": m.time_ms,
                "period_ms": m.period_ms, "growth_rate_per_s": m.growth_rate,
                "averaged_eigenvalue_per_s": complex(eig_modes[i]) if i < len(eig_modes)
                else math.nan,
            })
    return pd.DataFrame(rows)


def derivative_table(names: Iterable[str] | None = None, aerodynamics: str = "small-angle",
                     nondimensional: bool = True) -> Any:
    """The cycle-averaged lateral derivatives of each preset.

    Parameters
    ----------
    names : iterable of str, optional
    aerodynamics : {"small-angle", "exact", "linear"}
    nondimensional : bool
        Sun's group's form (:class:`~flapping.hover.sixdof.LateralDerivatives`) if True, SI
        otherwise.

    Returns
    -------
    pandas.DataFrame
        Indexed by preset, one column per derivative (``Yv`` ... ``Nr``).
    """
    import pandas as pd

    rows = {}
    for name in _names(names):
        a = analyse(name, aerodynamics)
        rows[name] = a.averaged.nondimensional if nondimensional else a.averaged.dimensional
    return pd.DataFrame.from_dict(rows, orient="index")[list(LATERAL_DERIVATIVE_NAMES)]


def _lateral_multipliers(orbit: SixDofHoverOrbit) -> np.ndarray:
    """The lateral block's multipliers from one variational integration (no error estimate)."""
    model = orbit.model
    result = monodromy(model.segment_functions(), orbit.x0, model.period,
                       breakpoints=model.breakpoints, rtol=ANALYSIS_RTOL, atol=ANALYSIS_ATOL,
                       args=(orbit.amplitude,))
    matrix = np.asarray(result.matrix)
    return floquet_multipliers(matrix[np.ix_(LATERAL, LATERAL)])


def inertia_sensitivity(name: str, factors: Sequence[float] = (0.5, 2.0),
                        aerodynamics: str = "small-angle",
                        scaled: Sequence[str] = ("I_x", "I_z", "both")) -> Any:
    """The leading lateral mode with the ESTIMATED roll and yaw inertia scaled.

    Each row scales I_x, I_z or both by a factor. The hover orbit does not depend on either
    (the lateral states are zero on it and I_xz = 0, so neither enters the planar motion): the
    preset's orbit is reused with the scaled insect, and the lateral multipliers come from one
    variational integration at the analysis's tolerances (the preset's own row, factor 1, is
    :func:`analyse`'s).

    Parameters
    ----------
    name : str
        A preset of :data:`LATERAL_PRESETS`.
    factors : sequence of float
        Positive scale factors.
    aerodynamics : {"small-angle", "exact", "linear"}
    scaled : sequence of {"I_x", "I_z", "both"}
        Which inertia each set of rows scales.

    Returns
    -------
    pandas.DataFrame
        Columns ``scaled`` (``"none"``, ``"I_x"``, ``"I_z"``, ``"both"``), ``factor``,
        ``roll_inertia``, ``yaw_inertia`` [kg m^2], ``leading_multiplier``, ``leading_modulus``,
        ``leading_type``, ``stable``, ``doubling_wingbeats`` (nan if stable).

    Raises
    ------
    ValueError
        For a bad preset or a non-positive factor; if the insect has I_xz != 0 (then the orbit
        could depend on I_x and I_z, and is not reused).
    """
    import pandas as pd

    factors = [check.positive(f"factors[{i}]", f) for i, f in enumerate(factors)]
    which = [check.choice(f"scaled[{i}]", w, ("I_x", "I_z", "both"))
             for i, w in enumerate(scaled)]
    base = analyse(name, aerodynamics)
    insect = base.orbit.insect
    if insect.roll_yaw_product != 0.0:
        raise ValueError("inertia_sensitivity reuses the orbit, which needs roll_yaw_product 0")
    assert insect.roll_inertia is not None and insect.yaw_inertia is not None

    def row(what: str, factor: float, mu: Any) -> dict[str, Any]:
        modes = classify_multipliers(mu, base.orbit.period)
        lead = modes[0]
        fx = factor if what in ("I_x", "both") else 1.0
        fz = factor if what in ("I_z", "both") else 1.0
        assert insect.roll_inertia is not None and insect.yaw_inertia is not None
        return {"scaled": what, "factor": factor, "roll_inertia": fx * insect.roll_inertia,
                "yaw_inertia": fz * insect.yaw_inertia, "leading_multiplier": lead.multiplier,
                "leading_modulus": abs(lead.multiplier), "leading_type": lead.type,
                "stable": all(m.stable for m in modes),
                "doubling_wingbeats": math.nan if lead.stable else lead.time_wingbeats}

    rows = [row("none", 1.0, base.stability.lateral.multipliers)]
    for what in which:
        for f in factors:
            changes = {}
            if what in ("I_x", "both"):
                changes["roll_inertia"] = f * insect.roll_inertia
            if what in ("I_z", "both"):
                changes["yaw_inertia"] = f * insect.yaw_inertia
            with warnings.catch_warnings():
                # one ESTIMATED moment scaled alone may break the triangle inequality (x2 of
                # I_z = I_y: 1.6 times the bound): the study's point, not the user's slip
                warnings.simplefilter("ignore", PlausibilityWarning)
                resized = insect.with_(**changes)
            orbit = replace(base.orbit, insect=resized)
            rows.append(row(what, f, _lateral_multipliers(orbit)))
    return pd.DataFrame(rows)


# --- The published lateral results ------------------------------------------------------------

@dataclass(frozen=True)
class PublishedLateral:
    """What one source says about the lateral modes of one hovering insect.

    Parameters
    ----------
    cite : str
        Key in ``book/references.bib``.
    species : str
        The source's insect.
    preset : str
        Our preset to compare with.
    method : str
    modes : tuple of (str, bool or None)
        The modes the source names, by descending growth rate: (type, stable), type one of
        ``"real"``, ``"oscillatory"`` or ``None`` (not stated), stable None when not stated.
    doubling_wingbeats : float or None
        The unstable mode's doubling time in wingbeats, when the source gives it.
    quote : str
        Where it was read and what it says.
    status : str
        ``"verified"`` (read in the source's abstract) or ``"second-hand"`` (read in a report of
        it: a press release, another paper's introduction).
    note : str
    """

    cite: str
    species: str
    preset: str
    method: str
    modes: tuple[tuple[str | None, bool | None], ...]
    doubling_wingbeats: float | None
    quote: str
    status: str
    note: str = ""

    def __post_init__(self) -> None:
        check.choice("preset", self.preset, LATERAL_PRESETS)
        check.choice("status", self.status, ("verified", "second-hand"))
        for i, (kind, stable) in enumerate(self.modes):
            check.choice(f"modes[{i}] type", kind, ("real", "oscillatory", None))
            check.choice(f"modes[{i}] stable", stable, (True, False, None))
        if self.doubling_wingbeats is not None:
            check.positive("doubling_wingbeats", self.doubling_wingbeats)

    @property
    def verdict(self) -> str:
        """``"unstable"`` if a mode is unstable, ``"stable"`` if all are, else ``"not stated"``."""
        if any(stable is False for _, stable in self.modes):
            return "unstable"
        if self.modes and all(stable is True for _, stable in self.modes):
            return "stable"
        return "not stated"


#: The published lateral results at hover (each read as its ``quote`` says).
PUBLISHED_LATERAL: tuple[PublishedLateral, ...] = (
    PublishedLateral(
        "zhang2010", "dronefly", "hoverfly", "CFD derivatives + averaging",
        (("real", False), ("oscillatory", True), ("real", True)), 9.0,
        "Zhang & Sun (2010), Acta Mech. Sin. 26:175, abstract: 'one unstable slow divergence "
        "mode (mode 1), one stable slow oscillatory mode (mode 2), and one stable fast "
        "subsidence mode (mode 3)'; 'Modes 1 and 2 mainly consist of a rotation about the "
        "horizontal longitudinal axis (x-axis) and a side translation'; 'td, the time for "
        "initial disturbances to double, is about 9 times the wingbeat period'",
        "verified",
        note="Sun's group's model dronefly (145 mg, R = 11.2 mm, Dudley's data) is our hoverfly "
             "preset's morphology."),
    PublishedLateral(
        "xu2013", "bumblebee", "bumblebee", "CFD derivatives + averaging",
        ((None, False),), None,
        "Elsevier press release (14 March 2013) on Xu & Sun (2013), J. Theor. Biol.: 'the "
        "bumblebee is unstable when it hovers and flies slowly'; 'The instability at hovering "
        "and low speed is mainly caused by a sideways wind made by the movement of the wings - "
        "a positive roll moment'",
        "second-hand",
        note="The paper's abstract was not read: the mode types and the doubling time are not "
             "recorded. Zhu, Meng & Sun (2020, introduction) report Xu & Sun's hover as "
             "having 'the same number of lateral modes' as longitudinal (three)."),
    PublishedLateral(
        "zhu2020", "dronefly", "hoverfly", "CFD derivatives + averaging",
        ((None, False),), None,
        "Zhu, Meng & Sun (2020), Sci. Rep., doi 10.1038/s41598-020-58762-5, abstract (PubMed "
        "32029787): 'At hovering flight, the motion of the dronefly is weakly unstable owing "
        "to two unstable natural modes of motion, a longitudinal one and a lateral one'; 'The "
        "longitudinal derivatives due to the lateral motion are approximately 3 orders of "
        "magnitude smaller'",
        "verified",
        note="One unstable lateral mode; its type and doubling time are not in the abstract."),
    PublishedLateral(
        "perl2022", "fruit fly", "fruit_fly",
        "CFD with measured wing kinematics and wing-wing interaction + linear analysis",
        (("oscillatory", False),), None,
        "Perl, Maya & Beatus (2022), APS DFD abstract A05.3: 'passive lateral dynamics are "
        "unstable, but with an oscillating-diverging mode that stems from a negative coupling "
        "between roll and sideways motion'; earlier CFD studies with sinusoidal kinematics "
        "found 'a non-oscillatory diverging mode, with positive coupling between roll and "
        "sideways motion'",
        "verified",
        note="Wing elevation (which our model does not have) and wing-wing interaction turn "
             "the divergence into an oscillation; a conference abstract, no numbers."),
    PublishedLateral(
        "xu2015", "dronefly", "hoverfly", "CFD derivatives + averaging",
        ((None, False),), None,
        "Xu & Sun (2015), J. Beijing Univ. Aeronaut. Astronaut. 41(1):133, English abstract "
        "(html.rhhz.net/BJHKHTDXXBZRB/20150121.htm): 'at hovering, the longitudinal and "
        "lateral disturbed motion both includes the unstable mode, therefore hovering is "
        "unstable'",
        "verified",
        note="The paper's method section (read) defines the non-dimensional derivatives and "
             "gives the model dronefly's data; its tables were not in the stored page."),
)

#: Published lateral derivatives that could be read: none (see the module docstring).
PUBLISHED_LATERAL_DERIVATIVES: dict[str, dict[str, float]] = {}


def published_rows() -> list[dict[str, Any]]:
    """:data:`PUBLISHED_LATERAL` as table rows (one per record)."""
    return [{"cite": r.cite, "species": r.species, "preset": r.preset, "method": r.method,
             "verdict": r.verdict,
             "modes": "; ".join(MODE_KINDS[(k, s)] if k is not None and s is not None
                                else ("unstable, type not stated" if s is False
                                      else "not stated") for k, s in r.modes),
             "doubling_wingbeats": r.doubling_wingbeats, "status": r.status, "quote": r.quote,
             "note": r.note} for r in PUBLISHED_LATERAL]


def _agree(ours: Any, theirs: Any) -> str:
    if theirs is None or ours is None:
        return "not stated"
    return "yes" if ours == theirs else "no"


def compare_published(aerodynamics: str = "small-angle",
                      records: Iterable[PublishedLateral] | None = None) -> Any:
    """Ours beside each published lateral result, mode by mode, mode type first.

    The published modes and ours are matched by rank, both by descending growth rate (our modes
    by descending multiplier modulus). Our lateral block has four multipliers, so four modes
    when all are real; a source with three modes (one a pair) leaves our last unmatched.

    Parameters
    ----------
    aerodynamics : {"small-angle", "exact", "linear"}
    records : iterable of PublishedLateral, optional
        Default :data:`PUBLISHED_LATERAL`.

    Returns
    -------
    pandas.DataFrame
        One row per published mode: ``cite``, ``species``, ``preset``, ``mode``, ``their_type``,
        ``our_type``, ``type_agrees``, ``their_stable``, ``our_stable``, ``stability_agrees``,
        ``their_doubling_wingbeats``, ``our_time_wingbeats`` (doubling if unstable, halving if
        stable), ``status``.
    """
    import pandas as pd

    rows = []
    for r in PUBLISHED_LATERAL if records is None else records:
        ours = analyse(r.preset, aerodynamics).modes
        for i, (kind, stable) in enumerate(r.modes):
            m = ours[i] if i < len(ours) else None
            rows.append({
                "cite": r.cite, "species": r.species, "preset": r.preset, "mode": i + 1,
                "their_type": kind, "our_type": None if m is None else m.type,
                "type_agrees": _agree(None if m is None else m.type, kind),
                "their_stable": stable, "our_stable": None if m is None else m.stable,
                "stability_agrees": _agree(None if m is None else m.stable, stable),
                "their_doubling_wingbeats": r.doubling_wingbeats if i == 0 else None,
                "our_time_wingbeats": None if m is None else m.time_wingbeats,
                "status": r.status,
            })
    return pd.DataFrame(rows)


# --- Sun's group's lateral system, the published reference quantities, ours beside theirs --------

#: The lateral states of Sun's group's system, in the order of :func:`lateral_system`.
LATERAL_STATES: tuple[str, ...] = ("v", "p", "r", "phi")
#: The non-dimensional mass, inertia and gravity ratios :func:`lateral_system` takes.
RATIO_NAMES: tuple[str, ...] = ("m", "Ix", "Iz", "Ixz", "g")


@dataclass(frozen=True)
class LateralScales:
    """Sun's group's reference quantities (module docstring), SI.

    Attributes
    ----------
    speed : float
        U = 2 Phi n r2 [m/s] (Phi peak to peak, r2 the radius of gyration in m).
    period : float
        T = 1/n [s].
    chord : float
        c, the mean chord [m].
    area : float
        S_t, both wings [m^2].
    density : float
        rho [kg/m^3].
    gravity : float
        g [m/s^2].
    """

    speed: float
    period: float
    chord: float
    area: float
    density: float
    gravity: float

    @classmethod
    def of_orbit(cls, orbit: SixDofHoverOrbit) -> LateralScales:
        """The scales of an orbit: its insect and its trimmed amplitude (Phi = 2 amplitude)."""
        ins = orbit.insect
        speed = 2.0 * (2.0 * orbit.amplitude) * ins.frequency * ins.r2 * ins.semi_span
        return cls(speed=speed, period=ins.period, chord=ins.mean_chord,
                   area=2.0 * ins.semi_span * ins.mean_chord, density=ins.air_density,
                   gravity=ins.gravity)

    @property
    def force(self) -> float:
        """0.5 rho U^2 S_t [N]."""
        return 0.5 * self.density * self.speed ** 2 * self.area

    def ratios(self, mass: float, roll_inertia: float, yaw_inertia: float,
               roll_yaw_product: float = 0.0) -> dict[str, float]:
        """m+, I_x+, I_z+, I_xz+ and g+ (keys :data:`RATIO_NAMES`) of a body [kg, kg m^2]."""
        inertia = self.force * self.chord * self.period ** 2  # 0.5 rho U^2 S c T^2
        mass_scale = 0.5 * self.density * self.speed * self.area * self.period
        return {"m": mass / mass_scale, "Ix": roll_inertia / inertia,
                "Iz": yaw_inertia / inertia, "Ixz": roll_yaw_product / inertia,
                "g": self.gravity * self.period / self.speed}


def orbit_ratios(orbit: SixDofHoverOrbit) -> dict[str, float]:
    """m+, I_x+, I_z+, I_xz+, g+ of an orbit's insect in its own scales (a six-dof orbit)."""
    ins = require_six_dof(orbit).insect
    assert ins.roll_inertia is not None and ins.yaw_inertia is not None
    return LateralScales.of_orbit(orbit).ratios(ins.mass, ins.roll_inertia, ins.yaw_inertia,
                                                ins.roll_yaw_product or 0.0)


def lateral_system(derivatives: dict[str, float] | Any, ratios: dict[str, float] | Any
                   ) -> np.ndarray:
    """Sun's group's non-dimensional lateral system matrix A+ (module docstring).

    Parameters
    ----------
    derivatives : mapping of str to float
        Y_v+ ... N_r+, keys :data:`~flapping.hover.sixdof.LATERAL_DERIVATIVE_NAMES`.
    ratios : mapping of str to float
        m+, I_x+, I_z+, I_xz+, g+, keys :data:`RATIO_NAMES` (m+, I_x+, I_z+ positive,
        I_x+ I_z+ > I_xz+^2).

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        In the states (v+, p+, r+, phi); its eigenvalues over T are the dimensional ones.

    Raises
    ------
    ValueError
        If a derivative or ratio is missing or not finite, or the inertia is not positive
        definite.
    """
    d = {n: check.real(n, derivatives[n]) if n in derivatives else math.nan
         for n in LATERAL_DERIVATIVE_NAMES}
    missing = [n for n, v in d.items() if not math.isfinite(v)]
    if missing:
        raise ValueError(f"`derivatives` must give every lateral derivative; missing {missing}")
    for n in RATIO_NAMES:
        if n not in ratios:
            raise ValueError(f"`ratios` must give {RATIO_NAMES}; missing {n!r}")
    mp = check.positive("ratios['m']", ratios["m"])
    ix = check.positive("ratios['Ix']", ratios["Ix"])
    iz = check.positive("ratios['Iz']", ratios["Iz"])
    ixz = check.real("ratios['Ixz']", ratios["Ixz"])
    gp = check.real("ratios['g']", ratios["g"])
    det = ix * iz - ixz * ixz
    if det <= 0.0:
        raise ValueError(f"`ratios` must have I_x+ I_z+ > I_xz+^2; got {ix}, {iz}, {ixz}")
    rows = []
    for s in ("v", "p", "r"):
        side, roll, yaw = d["Y" + s], d["L" + s], d["N" + s]
        rows.append((side / mp, (iz * roll + ixz * yaw) / det, (ixz * roll + ix * yaw) / det))
    a = np.zeros((4, 4))
    a[0, :3], a[1, :3], a[2, :3] = ([r[i] for r in rows] for i in range(3))
    a[0, 3] = gp
    a[3, 1] = 1.0
    return a


def eigenvalue_modes(eigenvalues: Sequence[complex] | np.ndarray,
                     period: float) -> tuple[Mode, ...]:
    """The modes of a linear system's eigenvalues [1/s], read as multipliers exp(lambda T).

    So that an averaged mode and a Floquet mode are named and timed the same way (doubling or
    halving time ln 2 / abs(Re lambda), in wingbeats of ``period``).
    """
    period = check.positive("period", period, unit="s")
    ev = np.asarray(eigenvalues, dtype=complex)
    # A real eigenvalue stays real (exp of a tiny imaginary part is rounding, not a mode).
    ev = np.where(np.abs(ev.imag) > REAL_TOL * np.abs(ev), ev, ev.real + 0j)
    return classify_multipliers(np.exp(ev * period), period)


@dataclass(frozen=True)
class LateralStudy:
    """A lateral CFD study: what of it could be read, as data.

    Attributes
    ----------
    key : str
        Its {cite} key (the :data:`PUBLISHED_LATERAL` record of the same key holds its modes).
    preset : str
        Our preset for its insect.
    reference : mapping of str to Number
        Reference quantities, SI: ``mass`` [kg], ``semi_span`` R [m], ``mean_chord`` c [m],
        ``r2`` (over R), ``wing_area`` (one wing) [m^2], ``wing_mass`` (one wing) [kg],
        ``body_length`` [m], ``root_spacing`` (between the two wing roots) [m],
        ``hinge_to_cg`` (wing-root axis to CG) [m], ``hanging_angle`` [rad],
        ``frequency`` [Hz], ``stroke_amplitude`` Phi [rad] (peak to peak); a quantity not read
        is absent.
    derivatives : mapping of str to Number
        The non-dimensional derivatives read (none so far).
    missing : str
        Why the derivatives that are absent are absent.
    """

    key: str
    preset: str
    reference: Any
    derivatives: Any
    missing: str

    @property
    def record(self) -> PublishedLateral:
        """The :data:`PUBLISHED_LATERAL` record of this study (its modes)."""
        return next(r for r in PUBLISHED_LATERAL if r.cite == self.key)


def _dronefly_reference() -> dict[str, Any]:
    src = "xu2015"
    where = ("method section, html.rhhz.net/BJHKHTDXXBZRB/20150121.htm and its copy at "
             "school.freekaoyan.com (read 2026-12-03)")
    note = ("Xu & Sun's model dronefly (data from R. Dudley); taken as Zhang & Sun's, whose "
            "table was not read (both are Sun's group's model dronefly)")
    r = 11.2e-3
    body = 1.29 * r

    def num(value: float, extra: str = "") -> Number:
        return Number(value, src, where, "read", note + extra)

    return {"mass": num(145e-6), "semi_span": num(r), "mean_chord": num(3.246e-3),
            "r2": num(0.534), "wing_area": num(36e-6), "wing_mass": num(0.326e-6),
            "body_length": num(body, " (1.29 R)"),
            "root_spacing": num(0.33 * body, " (0.33 body lengths)"),
            "hinge_to_cg": num(0.13 * body, " (l1 = 0.13 body lengths)"),
            "hanging_angle": num(math.radians(53.3), " (chi0 = 53.3 deg)")}


def _lateral_studies() -> dict[str, LateralStudy]:
    not_read = ("not read: the stored sources hold the abstract and first page only (no "
                "derivative table)")
    bee = sun_xiong_2005_reference()
    bee_ref = {k: bee[k] for k in ("mass", "semi_span", "mean_chord", "r2", "wing_mass",
                                   "frequency", "stroke_amplitude")}
    return {
        "zhang2010": LateralStudy("zhang2010", "hoverfly",
                                  MappingProxyType(_dronefly_reference()),
                                  MappingProxyType({}), not_read),
        "xu2013": LateralStudy(
            "xu2013", "bumblebee",
            MappingProxyType(bee_ref), MappingProxyType({}),
            "not read: only the publisher's press release was available; the reference "
            "quantities are Sun & Xiong's bumblebee (flapping.studies.cfd, each with its own "
            "status), Xu & Sun's own not read"),
        "xu2015": LateralStudy("xu2015", "hoverfly",
                               MappingProxyType(_dronefly_reference()),
                               MappingProxyType({}),
                               "not read: the stored page ends before the derivative tables"),
    }


#: The lateral studies whose reference quantities and modes were read, by {cite} key.
LATERAL_STUDIES: Any = MappingProxyType(_lateral_studies())


def lateral_study(key: str) -> LateralStudy:
    """The :class:`LateralStudy` of a {cite} key (``ValueError`` naming the keys if absent)."""
    return LATERAL_STUDIES[check.choice("study", key, tuple(LATERAL_STUDIES))]


def check_lateral_transcription(key: str) -> Any:
    """The published derivatives in the published lateral system, against the published modes.

    Parameters
    ----------
    key : str
        A key of ``LATERAL_STUDIES``.

    Returns
    -------
    tuple of Mode
        The modes of the published system (when every derivative and ratio has been read).

    Raises
    ------
    ValueError
        Naming the derivatives that were not read (today: all nine, for every study), so that
        no check is reported that was not made.
    """
    s = lateral_study(key)
    missing = [n for n in LATERAL_DERIVATIVE_NAMES if n not in s.derivatives]
    if missing:
        raise ValueError(f"{key}: the published lateral derivatives {missing} were not read "
                         f"({s.missing}); the transcription cannot be checked")
    raise ValueError(f"{key}: the published m+, I+ were not read")  # pragma: no cover


@dataclass(frozen=True)
class LateralComparison:
    """Ours beside one lateral study (:func:`compare_lateral`).

    Attributes
    ----------
    study : LateralStudy
    analysis : LateralAnalysis
        Our preset's.
    reference : pandas.DataFrame
        One row per reference quantity: ``quantity``, ``theirs``, ``ours``, ``unit``,
        ``status`` (theirs: ``"read"``, ``"estimated"`` or ``"not read"``).
    ratios : dict of str to float
        Our m+, I_x+, I_z+, I_xz+, g+ (:data:`RATIO_NAMES`) and ``U`` [m/s].
    derivatives : pandas.DataFrame
        Indexed by Y_v ... N_r: ``theirs`` (nan where not read), ``status``, ``ours``.
    system : numpy.ndarray
        Our derivatives in Sun's non-dimensional system (:func:`lateral_system`).
    system_eigenvalues : numpy.ndarray
        Its eigenvalues over T [1/s], by descending real part.
    system_error : float
        Their largest distance from our averaged lateral system's eigenvalues, over the
        largest modulus (the check that our non-dimensional form is Sun's system's).
    modes : pandas.DataFrame
        Mode by mode (rank by growth rate): ``mode``, ``their_kind``,
        ``their_doubling_wingbeats``, ``averaged_kind``, ``averaged_wingbeats``,
        ``averaged_per_s``, ``floquet_kind``, ``floquet_wingbeats``, ``multiplier``,
        ``type_agrees`` (theirs against Floquet's: yes, no, not stated).
    """

    study: LateralStudy
    analysis: LateralAnalysis
    reference: Any
    ratios: dict[str, float]
    derivatives: Any
    system: np.ndarray
    system_eigenvalues: np.ndarray
    system_error: float
    modes: Any


_REFERENCE_ROWS: tuple[tuple[str, str, float, str], ...] = (
    # (key, label, SI -> shown factor, unit shown)
    ("mass", "m", 1e6, "mg"), ("semi_span", "R", 1e3, "mm"), ("mean_chord", "c", 1e3, "mm"),
    ("r2", "r2/R", 1.0, "-"), ("wing_area", "S (one wing)", 1e6, "mm^2"),
    ("wing_mass", "wing mass", 1e6, "mg"), ("hinge_to_cg", "wing root above CG", 1e3, "mm"),
    ("root_spacing", "root spacing", 1e3, "mm"), ("frequency", "n", 1.0, "Hz"),
    ("stroke_amplitude", "Phi", 180.0 / math.pi, "deg"),
)


def _our_reference(a: LateralAnalysis) -> dict[str, float]:
    ins = a.orbit.insect
    return {"mass": ins.mass, "semi_span": ins.semi_span, "mean_chord": ins.mean_chord,
            "r2": ins.r2, "wing_area": ins.wing_area, "wing_mass": ins.wing_mass,
            "hinge_to_cg": ins.hinge_height, "root_spacing": 0.0,
            "frequency": ins.frequency, "stroke_amplitude": 2.0 * a.orbit.amplitude}


def compare_lateral(study: str = "zhang2010",
                    aerodynamics: str = "small-angle") -> LateralComparison:
    """Our preset beside a lateral study: reference quantities, derivatives, modes.

    Our derivatives are :func:`~flapping.hover.sixdof.averaged_lateral`'s, non-dimensional as
    Sun's group's; in Sun's system (:func:`lateral_system`, our m+ and I+) they give the averaged
    modes; our Floquet modes come from the lateral multipliers. The published modes are the
    abstract's (:data:`PUBLISHED_LATERAL`), matched by rank of growth rate.

    Parameters
    ----------
    study : str
        A key of ``LATERAL_STUDIES`` (``"zhang2010"``, ``"xu2013"``, ``"xu2015"``).
    aerodynamics : {"small-angle", "exact", "linear"}

    Returns
    -------
    LateralComparison
    """
    import pandas as pd

    s = lateral_study(study)
    a = analyse(s.preset, aerodynamics)
    ours = _our_reference(a)
    ref_rows = []
    for key, label, factor, unit in _REFERENCE_ROWS:
        num = s.reference.get(key)
        ref_rows.append({"quantity": label, "theirs": math.nan if num is None else
                         num.value * factor, "ours": ours[key] * factor, "unit": unit,
                         "status": "not read" if num is None else num.status})
    ratios = orbit_ratios(a.orbit)
    scales = LateralScales.of_orbit(a.orbit)
    d_ours = a.averaged.nondimensional
    derivs = pd.DataFrame({
        "theirs": [s.derivatives[n].value if n in s.derivatives else math.nan
                   for n in LATERAL_DERIVATIVE_NAMES],
        "status": [s.derivatives[n].status if n in s.derivatives else "not read"
                   for n in LATERAL_DERIVATIVE_NAMES],
        "ours": [d_ours[n] for n in LATERAL_DERIVATIVE_NAMES]},
        index=pd.Index(LATERAL_DERIVATIVE_NAMES, name="derivative"))
    system = lateral_system(d_ours, ratios)
    ev = np.linalg.eigvals(system).astype(complex) / scales.period
    ev = ev[np.argsort(-ev.real, kind="stable")]
    avg = np.asarray(a.averaged.eigenvalues)
    error = float(max(np.min(np.abs(avg - e)) for e in ev) / np.max(np.abs(avg)))
    averaged = eigenvalue_modes(ev, scales.period)
    rows = []
    published = s.record.modes
    for i in range(max(len(published), len(a.modes))):
        kind, stable = published[i] if i < len(published) else (None, None)
        fl = a.modes[i] if i < len(a.modes) else None
        av = averaged[i] if i < len(averaged) else None
        if i >= len(published):
            theirs = "-"
        elif kind is None or stable is None:
            theirs = "unstable, type not stated" if stable is False else "not stated"
        else:
            theirs = MODE_KINDS[(kind, stable)]
        rows.append({
            "mode": i + 1, "their_kind": theirs,
            "their_doubling_wingbeats": (s.record.doubling_wingbeats if i == 0 else None),
            "averaged_kind": None if av is None else av.kind,
            "averaged_wingbeats": None if av is None else av.time_wingbeats,
            "averaged_per_s": None if av is None else av.growth_rate,
            "floquet_kind": None if fl is None else fl.kind,
            "floquet_wingbeats": None if fl is None else fl.time_wingbeats,
            "multiplier": None if fl is None else fl.multiplier,
            "type_agrees": ("-" if i >= len(published) else
                            _agree(None if fl is None else fl.type, kind)),
        })
    return LateralComparison(s, a, pd.DataFrame(ref_rows), {**ratios, "U": scales.speed},
                             derivs, system, ev, error, pd.DataFrame(rows))


#: What :func:`term_table` does to each derivative.
TERM_CHANGES: tuple[str, ...] = ("negated", "zeroed", "x2", "x0.5")


def _leading_modes(system: np.ndarray, period: float) -> tuple[Mode, ...]:
    return eigenvalue_modes(np.linalg.eigvals(system) / period, period)


def term_table(comparison: LateralComparison, changes: Sequence[str] = TERM_CHANGES) -> Any:
    """Which derivative decides our lateral mode types: each term changed alone in Sun's system.

    Our derivatives and our m+, I+, g+ (:func:`lateral_system`); one derivative at a time
    negated, zeroed, doubled or halved. A term that changes the mode types (real modes
    becoming an oscillation) is one that decides them.

    Parameters
    ----------
    comparison : LateralComparison
    changes : sequence of str
        Of :data:`TERM_CHANGES`.

    Returns
    -------
    pandas.DataFrame
        One row per (derivative, change) after the row ``("none", "-")``: ``derivative``,
        ``change``, ``value`` (the derivative in the system), ``mode_types`` (of the four
        eigenvalues, by descending growth rate, e.g. ``"real, oscillatory, real"``),
        ``leading_kind``, ``leading_per_s``, ``types_change`` (bool), ``stable``.
    """
    import pandas as pd

    check.instance("comparison", comparison, LateralComparison)
    which = [check.choice(f"changes[{i}]", c, TERM_CHANGES) for i, c in enumerate(changes)]
    base = dict(comparison.analysis.averaged.nondimensional)
    ratios = {k: comparison.ratios[k] for k in RATIO_NAMES}
    period = comparison.analysis.orbit.period
    factor = {"negated": -1.0, "zeroed": 0.0, "x2": 2.0, "x0.5": 0.5}

    def row(name: str, change: str, d: dict[str, float]) -> dict[str, Any]:
        modes = _leading_modes(lateral_system(d, ratios), period)
        return {"derivative": name, "change": change,
                "value": d.get(name, math.nan), "mode_types": ", ".join(m.type for m in modes),
                "leading_kind": modes[0].kind, "leading_per_s": modes[0].growth_rate,
                "stable": all(m.stable for m in modes)}

    rows = [row("none", "-", base)]
    for name in LATERAL_DERIVATIVE_NAMES:
        for c in which:
            rows.append(row(name, c, {**base, name: factor[c] * base[name]}))
    table = pd.DataFrame(rows)
    table["types_change"] = table.mode_types != rows[0]["mode_types"]
    return table


def lv_threshold(comparison: LateralComparison, xtol: float = 1e-9) -> float:
    """The L_v+ (ours and our other terms) below which a lateral oscillation appears.

    Bisection between our L_v+ and -our L_v+ on whether a complex pair exists.

    Raises
    ------
    ValueError
        If the types do not differ at the two ends (no threshold between them).
    """
    check.instance("comparison", comparison, LateralComparison)
    tol = check.positive("xtol", xtol)
    base = dict(comparison.analysis.averaged.nondimensional)
    ratios = {k: comparison.ratios[k] for k in RATIO_NAMES}
    period = comparison.analysis.orbit.period

    def oscillates(lv: float) -> bool:
        modes = _leading_modes(lateral_system({**base, "Lv": lv}, ratios), period)
        return any(m.type == "oscillatory" for m in modes)

    hi, lo = base["Lv"], -base["Lv"]
    if oscillates(hi) == oscillates(lo):
        raise ValueError(f"an oscillation exists at both L_v+ = {hi:.4g} and {lo:.4g}, or at "
                         "neither: no threshold between them")
    while abs(hi - lo) > tol:
        mid = 0.5 * (hi + lo)
        if oscillates(mid) == oscillates(hi):
            hi = mid
        else:
            lo = mid
    return 0.5 * (hi + lo)


def inclined_body_inertia(insect: Any, body_angle: float) -> tuple[float, float, float]:
    """(I_x, I_z, I_xz) [kg m^2] of the insect's body with its long axis inclined nose-up.

    The presets' lateral inertia (:func:`~flapping.model.presets.lateral_inertia_estimate`)
    has the body's long axis along body x. Sun's group's model dronefly hangs with its long
    axis at chi0 = 53.3 deg to the horizontal x axis of their body frame (Xu & Sun 2015). The
    same axisymmetric body turned nose-up by ``body_angle`` about y: with I_a = the preset's
    I_x (about the long axis) and I_t = its I_z (transverse), e = (cos b, 0, -sin b) the long
    axis (z down), the tensor I_t 1 + (I_a - I_t) e e^T gives I_x = I_a cos^2 b + I_t sin^2 b,
    I_z = I_a sin^2 b + I_t cos^2 b and I_xz = (I_a - I_t) sin b cos b (the integral of x z
    dm, negative nose-up; the tensor's xz entry is -I_xz). I_y is unchanged.

    Parameters
    ----------
    insect : Insect
        With its roll and yaw inertia (long axis along x).
    body_angle : float
        Nose-up inclination of the long axis [rad], in [0, pi/2].

    Returns
    -------
    tuple of float
    """
    b = check.real("body_angle", body_angle, low=0.0, high=0.5 * math.pi)
    if insect.roll_inertia is None or insect.yaw_inertia is None:
        raise ValueError("`insect` must have a roll and a yaw inertia")
    ia, it = insect.roll_inertia, insect.yaw_inertia
    c, sn = math.cos(b), math.sin(b)
    return ia * c * c + it * sn * sn, ia * sn * sn + it * c * c, (ia - it) * sn * c


def _row(label: str, a: LateralAnalysis) -> dict[str, Any]:
    d = a.averaged.nondimensional
    averaged = eigenvalue_modes(a.averaged.eigenvalues, a.orbit.period)
    ins = a.orbit.insect
    return {
        "case": label, "hinge_height_mm": 1e3 * ins.hinge_height,
        "roll_yaw_product": ins.roll_yaw_product or 0.0,
        "Yv": d["Yv"], "Yp": d["Yp"], "Lv": d["Lv"], "Lp": d["Lp"],
        "averaged_kinds": ", ".join(m.kind for m in averaged),
        "averaged_leading_per_s": averaged[0].growth_rate,
        "floquet_kinds": ", ".join(m.kind for m in a.modes),
        "leading_multiplier": a.leading.multiplier,
        "doubling_wingbeats": math.nan if a.leading.stable else a.leading.time_wingbeats,
        "multiplier_error": a.stability.multiplier_error,
    }


@lru_cache(maxsize=16)
def _geometry_rows(name: str, cases: tuple[tuple[str, float, float], ...],
                   aerodynamics: str) -> tuple[dict[str, Any], ...]:
    base = analyse(name, aerodynamics)
    rows = []
    for label, height, angle in cases:
        if height == base.orbit.insect.hinge_height and angle == 0.0:
            rows.append(_row(label, base))
            continue
        ix, iz, ixz = inclined_body_inertia(base.orbit.insect, angle)
        insect = base.orbit.insect.with_(hinge_height=height, roll_inertia=ix, yaw_inertia=iz,
                                         roll_yaw_product=ixz)
        # With the roots above the CG the wings' drag pitches the body: the mean stroke angle
        # is a trim too (as flapping.studies.cfd trims it).
        trims = ("amplitude", "stroke_mean") if height != 0.0 else ("amplitude",)
        orbit = find_sixdof_hover_orbit(insect, aerodynamics=aerodynamics, trims=trims)
        stability = sixdof_stability(orbit)
        rows.append(_row(label, LateralAnalysis(
            name=name, orbit=orbit, stability=stability, averaged=averaged_lateral(orbit),
            modes=classify_multipliers(stability.lateral.multipliers, orbit.period))))
    return tuple(rows)


def geometry_table(name: str = "hoverfly",
                   cases: Sequence[tuple[str, float, float]] | None = None,
                   aerodynamics: str = "small-angle") -> Any:
    """The lateral derivatives and modes with Sun's group's body geometry, piece by piece.

    Sun's group's model dronefly (Xu & Sun 2015, :data:`LATERAL_STUDIES`) has its wing-root
    axis 0.13 body lengths (1.88 mm) above the centre of gravity and its body hanging at 53.3
    deg; our preset has the roots at the CG and the body's long axis along x. Raising the roots
    makes the side force act above the CG: L_v gains about h Y_v (Y_v < 0), the term that
    decides the mode type (:func:`term_table`). Inclining the body gives a product of inertia
    I_xz (:func:`inclined_body_inertia`) that couples roll and yaw. Each case is a new six-dof
    orbit (trimmed), its multipliers and its averaged system.

    Parameters
    ----------
    name : str
        A preset of :data:`LATERAL_PRESETS`.
    cases : sequence of (label, hinge height [m], body angle [rad]), optional
        Default: the preset; the dronefly's roots above the CG; its inclined body; both.
    aerodynamics : {"small-angle", "exact", "linear"}

    Returns
    -------
    pandas.DataFrame
        One row per case: ``case``, ``hinge_height_mm``, ``roll_yaw_product`` [kg m^2], ``Yv``,
        ``Yp``, ``Lv``, ``Lp`` (non-dimensional), ``averaged_kinds`` and ``floquet_kinds`` (the
        modes, by descending growth rate), ``averaged_leading_per_s``, ``leading_multiplier``
        (Floquet), ``doubling_wingbeats`` (nan if stable), ``multiplier_error``.
    """
    import pandas as pd

    name = _check_name(name)
    aerodynamics = check.choice("aerodynamics", aerodynamics, SIXDOF_AERODYNAMIC_MODELS)
    if cases is None:
        ref = LATERAL_STUDIES["zhang2010"].reference
        h, chi = ref["hinge_to_cg"].value, ref["hanging_angle"].value
        cases = (("preset", 0.0, 0.0), ("roots above the CG", h, 0.0),
                 ("body inclined", 0.0, chi), ("both", h, chi))
    span = presets.preset(name).semi_span
    checked = tuple((str(label), check.real(f"cases[{i}] height", h, low=0.0, high=span),
                     check.real(f"cases[{i}] angle", b, low=0.0, high=0.5 * math.pi))
                    for i, (label, h, b) in enumerate(cases))
    return pd.DataFrame(list(_geometry_rows(name, checked, aerodynamics)))

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

Published lateral derivatives (Y_v ... N_r of Zhang & Sun 2010 and Xu & Sun 2013) could not be
read: only the abstracts (and, for Xu & Sun, the publisher's press release) were available, and
they give no derivative values. :data:`PUBLISHED_LATERAL_DERIVATIVES` is therefore empty, and
says so.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any

import numpy as np

from flapping import _validation as check
from flapping.hover.sixdof import (
    ANALYSIS_ATOL,
    ANALYSIS_RTOL,
    LATERAL_DERIVATIVE_NAMES,
    LateralDerivatives,
    SixDofHoverOrbit,
    SixDofStability,
    averaged_lateral,
    find_sixdof_hover_orbit,
    sixdof_stability,
)
from flapping.model import presets
from flapping.model.sixdof import LATERAL
from flapping.periodic.floquet import floquet_multipliers, monodromy

__all__ = [
    "LATERAL_PRESETS", "NO_LATERAL_INERTIA", "Mode", "classify_multipliers", "LateralAnalysis",
    "analyse", "lateral_table", "mode_table", "derivative_table", "inertia_sensitivity",
    "PublishedLateral", "PUBLISHED_LATERAL", "PUBLISHED_LATERAL_DERIVATIVES",
    "compare_published", "published_rows", "MODE_KINDS",
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
    aerodynamics : {"small-angle", "exact"}

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
    aerodynamics = check.choice("aerodynamics", aerodynamics, ("small-angle", "exact"))
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
    aerodynamics : {"small-angle", "exact"}

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
    aerodynamics : {"small-angle", "exact"}
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
    aerodynamics : {"small-angle", "exact"}
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
            orbit = replace(base.orbit, insect=insect.with_(**changes))
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
    aerodynamics : {"small-angle", "exact"}
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

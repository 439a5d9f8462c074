"""Published results on the hover stability of insects, longitudinal and lateral, beside ours.

:data:`PUBLISHED` holds one :class:`PublishedResult` per (source, species, motion): what the
source says about the hover's stability, the mode that decides it (oscillatory or real), its
growth, its modes one by one (:class:`Mode`: the mode type first, real or oscillatory, then
stable or unstable), and how we know: ``status`` is ``"verified"`` when the record was read in
the source's abstract, data file or page in the session that wrote it, ``"second-hand"`` when it
was read in another source that reports it, ``"unverified"`` when it comes from our own notes
only; ``reading`` says the same in the table's words (:data:`READINGS`: read in the source,
abstract only, secondary, not read). A number that could not be read is ``None``: none is
inferred, none is converted from a figure.

Each record says which motion it is about (:data:`MOTIONS`: ``"longitudinal"``, ``"lateral"``,
or ``"both"`` when one result covers both) and which kind of method gave it (:data:`METHODS`:
CFD, quasi-steady, experiment, system identification), beside the method in the source's words.

:func:`published_for` selects the records of one species, :func:`published_motion` those about
one motion (the lateral chapter's and the atlas's filter); :func:`as_rows` flattens records into
table rows with the units in the keys (``doubling_time_ms``, ``doubling_time_wingbeats``, ...).

The species names are the presets' (:mod:`flapping.model.presets`: ``hawkmoth``, ``bumblebee``,
``fruit_fly``, ``honeybee``, ``hoverfly``, ``monarch``) where the source's insect is the preset's,
and the source's own name otherwise (``"cranefly"``, ``"dronefly"``). Where a source's insect
under its own name is close enough to a preset to compare with, :attr:`PublishedResult.preset`
names that preset and the record's note says how close (:attr:`PublishedResult.compared_with`).

Imports the standard library and the package's validation only: the table is data, and a reader of
the book can check each row against its quote without running a model.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from flapping import _validation as check

__all__ = [
    "PublishedResult", "Mode", "PUBLISHED", "published_for", "published_motion", "as_rows",
    "STATUSES", "MODE_TYPES", "VERDICTS", "ATTITUDES", "MOTIONS", "METHODS", "READINGS",
    "MODE_KINDS", "MODE_STABILITIES", "agreement",
]

#: How a record was checked (see the module docstring).
STATUSES = ("verified", "second-hand", "unverified")
#: The mode that decides stability: ``"oscillatory"`` (a complex pair), ``"real"`` (a real
#: eigenvalue or multiplier), ``"stable"`` (every mode decays); ``None``: not stated.
MODE_TYPES = ("oscillatory", "real", "stable", None)
#: The source's verdict on the hover; ``None``: the source (as read) gives none.
VERDICTS = ("unstable", "stable", None)
#: Body attitude free (pitch a degree of freedom) or prescribed (translation only).
ATTITUDES = ("free", "prescribed")
#: The motion a record is about: ``"both"`` when one result covers longitudinal and lateral.
MOTIONS = ("longitudinal", "lateral", "both")
#: Kinds of method: computational fluid dynamics, quasi-steady (blade-element) loads, experiment
#: on animals, system identification of a model's response; ``"not stated"`` when not read.
METHODS = ("CFD", "QS", "experiment", "system identification", "not stated")
#: How far the source was read: the source itself (paper, data file, code), its abstract only,
#: another text that reports it (secondary), or not at all (our notes).
READINGS = ("source", "abstract", "secondary", "not read")
#: A mode's type, stated first: a real eigenvalue (divergence or subsidence) or a complex pair.
MODE_KINDS = ("real", "oscillatory", "not stated")
#: A mode's stability.
MODE_STABILITIES = ("stable", "unstable")
#: ``reading`` by default, from ``status``.
_READING_OF_STATUS = {"verified": "abstract", "second-hand": "secondary", "unverified": "not read"}


def _optional_positive(name: str, value: Any, unit: str) -> float | None:
    return None if value is None else check.positive(name, value, unit=unit)


def _times(name: str, value: Any) -> tuple[float, ...]:
    if isinstance(value, (str, bytes)) or not isinstance(value, Iterable):
        raise ValueError(f"`{name}` must be a tuple of positive times in s; got {value!r}")
    return tuple(check.positive(f"{name}[{i}]", v, unit="s") for i, v in enumerate(value))


def _text(name: str, value: Any, *, empty: bool = True) -> str:
    if not isinstance(value, str) or (not empty and not value.strip()):
        what = "a string" if empty else "a non-empty string"
        raise ValueError(f"`{name}` must be {what}; got {value!r}")
    return value


@dataclass(frozen=True)
class Mode:
    """One natural mode as a source states it: its type first, then its stability.

    Parameters
    ----------
    kind : str
        ``"real"``, ``"oscillatory"`` or ``"not stated"`` (:data:`MODE_KINDS`).
    stability : str
        ``"stable"`` or ``"unstable"`` (:data:`MODE_STABILITIES`).
    name : str
        The source's name for it (e.g. ``"fast subsidence"``) and its numbers, in words.
    motion : str, optional
        ``"longitudinal"`` or ``"lateral"`` when the record covers both; None: the record's.

    Raises
    ------
    ValueError
        On a field out of its set, naming it.
    """

    kind: str
    stability: str
    name: str = ""
    motion: str | None = None

    def __post_init__(self) -> None:
        check.choice("kind", self.kind, MODE_KINDS)
        check.choice("stability", self.stability, MODE_STABILITIES)
        _text("name", self.name)
        if self.motion is not None:
            check.choice("motion", self.motion, ("longitudinal", "lateral"))

    @property
    def label(self) -> str:
        """``"<type>, <stability>"`` then the source's name: ``"real, stable: fast subsidence"``."""
        head = f"{self.kind}, {self.stability}"
        return f"{head}: {self.name}" if self.name else head


@dataclass(frozen=True)
class PublishedResult:
    """One published hover-stability result: a source, an insect, a configuration.

    Parameters
    ----------
    cite : str
        Key of the source in ``book/references.bib``.
    species : str
        The preset's name when the source's insect is the preset's, the source's name otherwise.
    method : str
        How the source gets its result (e.g. ``"CFD derivatives + averaging"``,
        ``"quasi-steady + Floquet"``).
    attitude : str
        ``"free"`` or ``"prescribed"`` body attitude (:data:`ATTITUDES`).
    verdict : str or None
        ``"unstable"``, ``"stable"`` or ``None`` when the source, as read, gives no verdict.
    mode_type : str or None
        The mode that decides stability (:data:`MODE_TYPES`).
    status : str
        How the record was checked (:data:`STATUSES`).
    quote : str
        Where the record comes from: a short quote or close paraphrase of the source, and which
        page or file; required (non-empty) for a verified record.
    doubling_time_s : float, optional
        Time for the unstable mode's amplitude to double [s].
    oscillation_period_s : float, optional
        Period of the unstable oscillatory mode [s].
    wingbeat_s : float, optional
        The wingbeat period of the source's insect [s], when the source gives it.
    halving_times_s : tuple of float
        Times to halve of the stable modes [s], when given.
    exponents_per_s : tuple of float
        Floquet (characteristic) exponents or eigenvalues' real parts [1/s], when given.
    note : str
        What else a reader needs (what the numbers do not say, how the insect relates to ours).
    preset : str, optional
        The preset to compare with when the source's insect goes by another name (Xu & Sun's
        model dronefly is our ``"hoverfly"``); None: the species itself, when it is a preset.
    motion : str
        ``"longitudinal"`` (default), ``"lateral"`` or ``"both"`` (:data:`MOTIONS`).
    methods : tuple of str
        The kinds of method (:data:`METHODS`), e.g. ``("CFD",)``; default ``("not stated",)``.
    modes : tuple of Mode
        The modes the source states, one by one (only those read; empty if none).
    reading : str, optional
        How far the source was read (:data:`READINGS`); None: from ``status`` (verified ->
        abstract, second-hand -> secondary, unverified -> not read).
    taxon : str
        The species' scientific name where the source gives it (or a preset documents it).

    Raises
    ------
    ValueError
        On any argument out of its set or range, naming the argument.
    """

    cite: str
    species: str
    method: str
    attitude: str
    verdict: str | None
    mode_type: str | None
    status: str
    quote: str
    doubling_time_s: float | None = None
    oscillation_period_s: float | None = None
    wingbeat_s: float | None = None
    halving_times_s: tuple[float, ...] = ()
    exponents_per_s: tuple[float, ...] = ()
    note: str = ""
    preset: str | None = None
    motion: str = "longitudinal"
    methods: tuple[str, ...] = ("not stated",)
    modes: tuple[Mode, ...] = ()
    reading: str | None = None
    taxon: str = ""

    def __post_init__(self) -> None:
        for name in ("cite", "species", "method"):
            _text(name, getattr(self, name), empty=False)
        check.choice("status", self.status, STATUSES)
        check.choice("motion", self.motion, MOTIONS)
        methods = self.methods
        if isinstance(methods, (str, bytes)) or not isinstance(methods, Iterable):
            raise ValueError(f"`methods` must be a tuple of labels from {METHODS}; got {methods!r}")
        methods = tuple(methods)
        if not methods:
            raise ValueError(f"`methods` must name at least one label from {METHODS}")
        for i, m in enumerate(methods):
            check.choice(f"methods[{i}]", m, METHODS)
        object.__setattr__(self, "methods", methods)
        modes = self.modes
        if isinstance(modes, (str, bytes)) or not isinstance(modes, Iterable):
            raise ValueError(f"`modes` must be a tuple of Mode; got {modes!r}")
        modes = tuple(modes)
        for i, mode in enumerate(modes):
            check.instance(f"modes[{i}]", mode, Mode)
            if self.motion == "both" and mode.motion is None:
                raise ValueError(f"`modes[{i}]` must say its motion: the record covers both")
            if self.motion != "both" and mode.motion not in (None, self.motion):
                raise ValueError(f"`modes[{i}].motion` is {mode.motion!r}, the record's motion "
                                 f"is {self.motion!r}")
        object.__setattr__(self, "modes", modes)
        reading = _READING_OF_STATUS[self.status] if self.reading is None else self.reading
        object.__setattr__(self, "reading", check.choice("reading", reading, READINGS))
        _text("taxon", self.taxon)
        check.choice("attitude", self.attitude, ATTITUDES)
        check.choice("verdict", self.verdict, VERDICTS)
        check.choice("mode_type", self.mode_type, MODE_TYPES)
        check.choice("status", self.status, STATUSES)
        _text("quote", self.quote, empty=self.status != "verified")
        _text("note", self.note)
        if self.preset is not None:
            _text("preset", self.preset, empty=False)
        for name in ("doubling_time_s", "oscillation_period_s", "wingbeat_s"):
            object.__setattr__(self, name, _optional_positive(name, getattr(self, name), "s"))
        object.__setattr__(self, "halving_times_s",
                           _times("halving_times_s", self.halving_times_s))
        exponents = self.exponents_per_s
        if isinstance(exponents, (str, bytes)) or not isinstance(exponents, Iterable):
            raise ValueError(f"`exponents_per_s` must be a tuple of real numbers in 1/s; "
                             f"got {exponents!r}")
        object.__setattr__(self, "exponents_per_s", tuple(
            check.real(f"exponents_per_s[{i}]", v, unit="1/s") for i, v in enumerate(exponents)))
        if self.doubling_time_s is not None and self.verdict == "stable":
            raise ValueError("`doubling_time_s` is given, so `verdict` cannot be 'stable'")

    @property
    def is_lateral(self) -> bool:
        """True when the record says something about lateral motion (``"lateral"`` or
        ``"both"``)."""
        return self.motion in ("lateral", "both")

    @property
    def mode_labels(self) -> tuple[str, ...]:
        """The modes as text, type first (:attr:`Mode.label`), with the motion where the record
        covers both."""
        return tuple(m.label if self.motion != "both" else f"{m.motion}: {m.label}"
                     for m in self.modes)

    @property
    def compared_with(self) -> str:
        """The name our result for this record is looked up by: :attr:`preset` if given, else
        :attr:`species`."""
        return self.species if self.preset is None else self.preset

    @property
    def growth_rate_per_s(self) -> float | None:
        """ln 2 / doubling time [1/s]: the growth rate the doubling time states (None if none)."""
        return None if self.doubling_time_s is None else math.log(2.0) / self.doubling_time_s

    @property
    def doubling_time_wingbeats(self) -> float | None:
        """The doubling time in wingbeats of the source's own insect (None if either is missing)."""
        if self.doubling_time_s is None or self.wingbeat_s is None:
            return None
        return self.doubling_time_s / self.wingbeat_s


_SUN2005 = ("Sun & Xiong (2005a), J. Exp. Biol. abstract: 'three natural modes were identified: "
            "one unstable oscillatory mode, one stable fast subsidence mode and one stable slow "
            "subsidence mode'; 'The period of the oscillations is 0.32 s'; 'The oscillations "
            "double in amplitude in 0.1 s'; fast subsidence 'decay[s] to half of the starting "
            "values in 0.024 s', slow 'in 0.37 s'; 'the wingbeat period (6.4 ms)'")
_SUNWANG = ("Sun & Wang (2007), J. Exp. Biol. 210:2714, summary: 'The model insect has the same "
            "three natural modes of motion as those reported recently for a hovering bumblebee: "
            "one unstable oscillatory mode, one stable fast subsidence mode and one stable slow "
            "subsidence mode'; 'morphological and certain kinematical data of hoverflies were "
            "used for the model insect'")
_ACTA = ("Second-hand, from the introduction of Sci. Rep. (2025) s41598-025-24175-5: Sun & Xiong "
         "'found ... one unstable oscillatory mode, one stable fast subsidence mode, and one "
         "stable slow subsidence mode. Follow-up research on hoverfly, cranefly, dronefly, and "
         "hawkmoth revealed the same conclusion'")
_WU = ("Wu & Sun (2012), abstract: 'The Floquet theory (cyclic-motion stability analysis) agreed "
       "well with the simulation for both the model dronefly and the model hawkmoth; but the "
       "averaged-model theory gave good results only for the dronefly'")
_FWUAV = ("FWUAV data file matlab/sim_data/other_insects/sim_QS_x_hover_conv_rate.mat at commit "
          "1a25d41, read with scipy.io.loadmat: conv_rate_{insect} rows 4-6 (rows 1-3, position, "
          "are 0); floquet_stability.m computes them as log|rho| * f [1/s]; "
          "fig_convergence_rate.m labels rows 4, 5, 6 'Longitudinal mode 1', 'Longitudinal mode "
          "2', 'Lateral mode'")
_FWUAV_NOTE = ("Attitude prescribed: perturbations of position and velocity only (eom_hover, 6 "
               "states), so no pitch mode; the third exponent is a lateral (sideways) mode. "
               "Magnitudes only (log|rho|): the file does not say which modes are complex.")
_FWUAV_METHOD = ("quasi-steady; its analytically linearised equations integrated over the "
                 "period (sim_pert), Floquet exponents from the monodromy")
_CHENG_DENG = ("Cheng & Deng (2011), IEEE T-RO abstract: damping 'linearly dependent on the body "
               "translational and angular velocities and increases with wing-stroke amplitude "
               "and frequency'; 'The model was then used to estimate the flight dynamics and "
               "stability of four different species of flying insects as case studies'")
_SCIREP2025 = ("the introduction of Sci. Rep. (2025) s41598-025-24175-5 (read on nature.com)")
_BEATUS_LIST = ("Beatus, Guckenheimer & Cohen, 'Roll control in fruit flies' (arXiv 1407.7993, "
                "read), and Whitehead et al. (2015, J. Exp. Biol., abstract page read) list it "
                "among the studies finding that flapping flight is 'aerodynamically unstable, "
                "on a time scale of a few wing-beats'")
_PERL2022 = ("Perl, Maya & Beatus (2022), APS DFD abstract A05.3 (archive.aps.org): 'passive "
             "lateral dynamics are unstable, but with an oscillating-diverging mode that stems "
             "from a negative coupling between roll and sideways motion'; 'Previous studies "
             "using computational fluid dynamics (CFD) simulations on several insects found "
             "that they are passively unstable due to a non-oscillatory diverging mode, with "
             "positive coupling between roll and sideways motion'")

#: The three longitudinal modes Sun's group reports at hover, type first.
_SUN_MODES = (Mode("oscillatory", "unstable", "pitch and horizontal motion"),
              Mode("real", "stable", "fast subsidence"),
              Mode("real", "stable", "slow subsidence"))


def _sun_group() -> list[PublishedResult]:
    """Sun's group: CFD stability derivatives, linearised and cycle-averaged, attitude free."""
    method = "CFD derivatives + averaging"
    cfd = ("CFD",)
    rows = [
        PublishedResult(
            "sun2005", "bumblebee", method, "free", "unstable", "oscillatory", "verified",
            _SUN2005, doubling_time_s=0.1, oscillation_period_s=0.32, wingbeat_s=6.4e-3,
            halving_times_s=(0.024, 0.37),
            note="Unstable mode: pitch and horizontal motion, 'negligible vertical motion'; "
                 "caused by nose-up pitch coupled with forward motion. Abstract on PubMed/JEB.",
            methods=cfd, modes=(
                Mode("oscillatory", "unstable",
                     "pitch and horizontal motion, period 0.32 s, doubles in 0.1 s"),
                Mode("real", "stable", "fast subsidence, halves in 0.024 s"),
                Mode("real", "stable", "slow subsidence (vertical), halves in 0.37 s"))),
        PublishedResult(
            "sun2005honeybee", "honeybee", method, "free", "unstable", "oscillatory",
            "verified",
            "Sun & Xiong (2005b), Acta Aeronaut. Astronaut. Sin. 26(4), abstract: 'The disturbed "
            "motion has three natural modes: an unstable oscillatory mode, a stable fast "
            "subsidence mode and a stable slow subsidence mode'; (Chinese abstract) the "
            "doubling time of the disturbance, 0.11 s, is 22 times the wingbeat period, 5.1 ms",
            doubling_time_s=0.11, wingbeat_s=5.1e-3,
            note="Period of the oscillation not in the abstract.", methods=cfd, modes=(
                Mode("oscillatory", "unstable", "doubles in 0.11 s"),
                Mode("real", "stable", "fast subsidence"),
                Mode("real", "stable", "slow subsidence"))),
        PublishedResult(
            "sun2007", "hoverfly", method, "free", "unstable", "oscillatory", "verified",
            _SUNWANG,
            note="Stabilised by feeding pitch attitude, pitch rate and horizontal velocity into "
                 "the mean stroke angle (or a differential down/upstroke angle of attack); the "
                 "slow subsidence needs vertical-speed feedback. No growth rate in the summary.",
            methods=cfd, modes=_SUN_MODES),
    ]
    for species, note in (("hoverfly", ""), ("cranefly", ""), ("dronefly", ""),
                          ("hawkmoth", "Sun's group's hawkmoth: CFD finds it unstable, Gao et "
                                       "al. (2009) with CFD too find it stable.")):
        rows.append(PublishedResult(
            "sun2007acta", species, method, "free", "unstable", "oscillatory", "second-hand",
            _ACTA, note=(note + " The paper itself not read: no numbers.").strip(),
            methods=cfd, modes=_SUN_MODES))
    rows += [
        PublishedResult(
            "xu2015", "dronefly", method, "free", "unstable", None, "verified",
            "Xu & Sun (2015), J. Beijing Univ. Aeronaut. Astronaut. 41(1), abstract: 'at "
            "hovering, the longitudinal and lateral disturbed motion both includes the "
            "unstable mode, therefore hovering is unstable'; in forward flight the longitudinal "
            "unstable mode's doubling time is shorter than at hover",
            note="The morphology of our hoverfly preset (145 mg, R = 11.2 mm, data from R. "
                 "Dudley) is this paper's model dronefly, so we compare with the hoverfly. Mode "
                 "types and doubling times not in the abstract.", preset="hoverfly",
            motion="both", methods=cfd, modes=(
                Mode("not stated", "unstable", "one longitudinal mode", motion="longitudinal"),
                Mode("not stated", "unstable", "one lateral mode", motion="lateral"))),
        PublishedResult(
            "wu2012", "dronefly", "CFD + Floquet vs averaging, checked by NS-coupled simulation",
            "free", None, None, "verified", _WU,
            note="The abstract gives no verdict and no numbers: averaging valid for the "
                 "dronefly (high wingbeat frequency, small wing-to-body mass ratio). Compared "
                 "with our hoverfly, which takes this dronefly's frequency (164 Hz, second-hand) "
                 "but Sun's group's hoverfly morphology: close, not the same data set.",
            preset="hoverfly", methods=cfd),
        PublishedResult(
            "wu2012", "hawkmoth", "CFD + Floquet vs averaging, checked by NS-coupled simulation",
            "free", None, None, "verified", _WU,
            note="The abstract gives no verdict and no numbers: averaging fails for the hawkmoth "
                 "(low frequency, large wing mass, large body oscillation).", methods=cfd),
    ]
    return rows + _sun_group_later()


def _sun_group_later() -> list[PublishedResult]:
    """Sun's group after 2012, the lateral studies among them (second-hand where not read)."""
    return [
        PublishedResult(
            "liang2013", "model insects", "CFD (as the citing papers describe it)", "free",
            "unstable", None, "second-hand", f"Liang & Sun (2013): {_BEATUS_LIST}",
            note="Not read: its insects, motion, modes and numbers are unknown here; recorded as "
                 "longitudinal by default. The bibliographic details are not verified "
                 "(references.bib).", methods=("CFD",), reading="secondary"),
        PublishedResult(
            "zhang2010", "dronefly", "CFD derivatives + averaging", "free", "unstable", "real",
            "verified",
            "Zhang & Sun (2010), Acta Mech. Sin. 26:175, abstract (as quoted in "
            "flapping.studies.lateral.PUBLISHED_LATERAL): 'one unstable slow divergence mode "
            "(mode 1), one stable slow oscillatory mode (mode 2), and one stable fast subsidence "
            "mode (mode 3)'; 'Modes 1 and 2 mainly consist of a rotation about the horizontal "
            "longitudinal axis (x-axis) and a side translation'; 'td, the time for initial "
            "disturbances to double, is about 9 times the wingbeat period'",
            note="Lateral. The abstract read by the lateral chapter's session, not re-read in "
                 "this one; second-hand agreement in the introduction of Sci. Rep. (2025) "
                 "s41598-025-24175-5 and in Perl et al. (2022). Sun's group's model dronefly is "
                 "our hoverfly preset's morphology.", preset="hoverfly", motion="lateral",
            methods=("CFD",), modes=(
                Mode("real", "unstable", "slow divergence, roll and side translation, doubles "
                     "in about 9 wingbeats"),
                Mode("oscillatory", "stable", "slow oscillation, roll and side translation"),
                Mode("real", "stable", "fast subsidence"))),
        PublishedResult(
            "xu2013", "bumblebee", "CFD derivatives + averaging", "free", "unstable", None,
            "second-hand",
            "Elsevier press release (14 March 2013) on Xu & Sun, J. Theor. Biol. (2013): the "
            "bumblebee 'is unstable when it hovers and flies slowly, and becomes neutral or "
            "weakly stable at medium and high flight speeds'; 'The instability at hovering and "
            "low speed is mainly caused by a sideways wind made by the movement of the wings - "
            "a positive roll moment'",
            note="Lateral. The mode type is not in the press release; Perl et al. (2022) report "
                 "that earlier CFD studies found a non-oscillatory lateral divergence.",
            motion="lateral", methods=("CFD",), taxon="",
            modes=(Mode("not stated", "unstable", "roll moment from the sideways wind"),)),
        PublishedResult(
            "zhu2020", "dronefly", "CFD derivatives + averaging, 0 to 8.6 m/s", "free",
            "unstable", None, "verified",
            "Zhu, Meng & Sun (2020), Sci. Rep., abstract (PubMed 32029787, as quoted in "
            "flapping.studies.lateral.PUBLISHED_LATERAL): 'At hovering flight, the motion of the "
            "dronefly is weakly unstable owing to two unstable natural modes of motion, a "
            "longitudinal one and a lateral one'; the paper's introduction read on nature.com",
            note="The abstract read by the lateral chapter's session, not re-read in this one. "
                 "Mode types and doubling times not in the abstract.", preset="hoverfly",
            motion="both", methods=("CFD",), modes=(
                Mode("not stated", "unstable", "one longitudinal mode, weak",
                     motion="longitudinal"),
                Mode("not stated", "unstable", "one lateral mode, weak", motion="lateral"))),
    ]


def _others() -> list[PublishedResult]:
    """Everyone else: Gao et al., Faruque & Humbert, Perl et al.; then :func:`_quasi_steady`."""
    fly = "Drosophila melanogaster"
    rows = [
        PublishedResult(
            "gao2009", "hawkmoth", "CFD derivatives + averaging", "free", "stable", "stable",
            "verified",
            "Gao, Aono & Liu (2009), J. Biomech. Sci. Eng. 4(1) abstract: 'three natural modes "
            "are identified of a stable oscillatory mode, a stable fast subsidence mode and a "
            "stable slow subsidence mode, which indicate that the hawkmoth hovering flight is "
            "stable'",
            note="Disagrees with Sun's group's CFD hawkmoth (sun2007acta).", methods=("CFD",),
            modes=(Mode("oscillatory", "stable"), Mode("real", "stable", "fast subsidence"),
                   Mode("real", "stable", "slow subsidence"))),
        PublishedResult(
            "gao2011", "fruit_fly", "CFD (as the citing papers describe it), 6 degrees of "
            "freedom", "free", "unstable", None, "second-hand",
            f"'Gao et al. (2011)': {_BEATUS_LIST}",
            note="Not read. The project's brief named it 'Gao, Lu & Sun 2011'; no such paper "
                 "was found, and the 2011 fruit-fly paper the citing texts list is taken to be "
                 "Gao, Aono & Liu's (details not verified, references.bib). Modes unknown.",
            motion="both", methods=("CFD",), taxon=fly),
        PublishedResult(
            "faruque2010a", "fruit_fly", "system identification of a quasi-steady flapping "
            "model about hover", "free", "unstable", None, "second-hand",
            f"Second-hand, from {_SCIREP2025}: 'Faruque and Sean Humbert7,8 and Cheng and Deng9 "
            "also studied the dynamic flight stability in several hovering insects. Their "
            "results all showed that hovering flight in the insects mentioned above was "
            "dynamically unstable due to the unstable modes of the longitudinal and lateral "
            "motions'",
            note="Part 1, longitudinal. Not read: modes and numbers unknown.",
            methods=("system identification", "QS"), taxon=fly,
            modes=(Mode("not stated", "unstable"),)),
        PublishedResult(
            "faruque2010b", "fruit_fly", "system identification of a quasi-steady flapping "
            "model about hover", "free", "unstable", None, "second-hand",
            f"Second-hand, from {_SCIREP2025} (the same sentence as Part 1)",
            note="Part 2, lateral-directional. Not read: modes and numbers unknown.",
            motion="lateral", methods=("system identification", "QS"), taxon=fly,
            modes=(Mode("not stated", "unstable"),)),
        PublishedResult(
            "perl2022", "fruit_fly", "CFD derivatives, measured wing kinematics, wing-wing "
            "interaction", "free", "unstable", "oscillatory", "verified", _PERL2022,
            note="Lateral. Oral presentation: the abstract is the only text.",
            motion="lateral", methods=("CFD",), taxon=fly,
            modes=(Mode("oscillatory", "unstable",
                        "oscillating divergence: sliding right, the fly rolls left"),)),
        PublishedResult(
            "perl2023", "fruit_fly", "CFD derivatives, measured wing kinematics, wing-wing "
            "interaction", "free", "unstable", "oscillatory", "verified",
            "Perl, Maya, Sabag & Beatus (2023), Phys. Fluids 35(4), abstract (ouci.dntb.gov.ua "
            "record, doi 10.1063/5.0138255): 'Lateral dynamics are unstable due to an "
            "oscillating-diverging mode with a doubling time of 17 wingbeats'",
            note="Lateral; the full paper of perl2022. Doubling time 17 wingbeats (their "
                 "wingbeat not in the abstract, so no time in s).",
            motion="lateral", methods=("CFD", "experiment"), taxon=fly,
            modes=(Mode("oscillatory", "unstable", "doubles in 17 wingbeats"),)),
    ]
    return rows + _quasi_steady()


def _quasi_steady() -> list[PublishedResult]:
    """Taha et al., the paper, Ristroph et al., FWUAV and the other quasi-steady models."""
    rows = [
        PublishedResult(
            "taha2020", "hawkmoth", "chronological calculus (beyond first-order averaging) + "
            "experiment", "free", "stable", None, "verified",
            "Taha, Kiani, Hedrick & Greeter (2020), Science Robotics abstract (NSF PAR record): "
            "'we reveal a passive stabilization mechanism that insects exploit through their "
            "natural wing oscillations: vibrational stabilization'; 'supported through "
            "experiments on a real hawkmoth subjected to pitch disturbance from hovering'",
            note="Pitch stabilised by the flapping itself, which direct averaging misses. "
                 "Second-hand (UC Irvine news, Oct. 2020): the effect grows as the flapping "
                 "frequency falls. No growth rates in the abstract.",
            methods=("QS", "experiment")),
        PublishedResult(
            "elsadek", "hawkmoth", "quasi-steady + Floquet", "free", "unstable", "real",
            "verified",
            "Elsadek, El-Bayoumi & Taha (manuscript), abstract: 'Floquet theorem is used to "
            "assess the stability of the captured periodic orbit corresponding to hovering "
            "equilibrium. The results showed that the system is indeed unstable.'; eq. (67): "
            "multipliers 0.5933, 1.0258, 0.9871 +- 0.0108i, 'the second value is greater than "
            "one which implies that the system is unstable'",
            note="The paper this project reproduces; its multipliers are in the book's "
                 "appendix of the paper's numbers.", methods=("QS",), taxon="Manduca sexta",
            reading="source", modes=(Mode("real", "unstable", "multiplier 1.0258, eq. (67)"),)),
        PublishedResult(
            "ristroph2013", "fruit_fly", "pitch model from flapping-wing aerodynamics + "
            "magnetic perturbation experiments", "free", "unstable", None, "verified",
            "Ristroph et al. (2013), abstract: 'a theory that predicts the instability growth "
            "rate in body pitch from flapping-wing aerodynamics'; flies 'employ active control "
            "that is indeed fast relative to the instability'; with sensors disabled they stay "
            "upright only with 'high-drag fibres' attached",
            note="Growth rate not in the abstract. Passive stability by body drag, not by the "
                 "wing hinge.", methods=("QS", "experiment"),
            modes=(Mode("not stated", "unstable", "body pitch"),)),
    ]
    for species, exponents in (("hawkmoth", (-1.77552044, -4.6284423, -1.48133668)),
                               ("bumblebee", (-1.52894323, -2.89196594, -2.01187695)),
                               ("fruit_fly", (-3.9368558, -7.03588389, -4.6478547)),
                               ("monarch", (-8.43546036, -12.84492058, -2.73144541))):
        lon1, lon2, lat = exponents
        rows.append(PublishedResult(
            "fwuav", species, _FWUAV_METHOD, "prescribed", "stable", "stable", "verified",
            _FWUAV, exponents_per_s=exponents, note=_FWUAV_NOTE, motion="both",
            methods=("QS",), reading="source", modes=(
                Mode("not stated", "stable", f"exponent {lon1:.3f} 1/s", motion="longitudinal"),
                Mode("not stated", "stable", f"exponent {lon2:.3f} 1/s", motion="longitudinal"),
                Mode("not stated", "stable", f"exponent {lat:.3f} 1/s", motion="lateral"))))
    return rows + _other_models()


def _other_models() -> list[PublishedResult]:
    """The other quasi-steady and Floquet models (abstracts, or the reading list)."""
    return [
        PublishedResult(
            "chengdeng2011", "four species", "quasi-steady damping derivatives + linear 6-DOF "
            "model", "free", None, None, "verified", _CHENG_DENG,
            note="Which four species, their derivatives and their modes are not in the "
                 "abstract: not read, not recorded. Second-hand ({_SCIREP2025}): hover "
                 "unstable through unstable longitudinal and lateral modes.".replace(
                     "{_SCIREP2025}", _SCIREP2025),
            motion="both", methods=("QS",)),
        PublishedResult(
            "bluman2017", "insect-scale wing", "Floquet, with wing-wake interaction", "free",
            "unstable", None, "unverified",
            "Project reading list (READING.md): 'Floquet hover stability, wing-wake interaction "
            "destabilises'; the paper's abstract has not been read",
            note="Species, numbers and mode type unknown."),
        PublishedResult(
            "tahmasian2023", "five species", "averaging with wing inertia and mean stroke angle",
            "free", None, None, "verified",
            "Tahmasian & Kotulak-Smith (2023), abstract: 'the wing inertial forces have a "
            "considerable effect on pitch dynamics'; 'the body of hovering insects can not be "
            "vibrationally stabilized in a non-vertical orientation'; the body angle balances "
            "the weight's moment against the moment of flapping 'with a nonzero mean stroke "
            "angle'",
            note="Predicts the body angle of five species; the abstract names neither the "
                 "species nor a stability verdict.", methods=("QS",)),
    ]


#: Every published result recorded, Sun's group first.
PUBLISHED: tuple[PublishedResult, ...] = tuple(_sun_group() + _others())


def published_for(species: str) -> tuple[PublishedResult, ...]:
    """The records of one species.

    Parameters
    ----------
    species : str
        A species name as it appears in :data:`PUBLISHED` (the presets' names, or the source's).

    Returns
    -------
    tuple of PublishedResult
        The records of that species, in :data:`PUBLISHED`'s order.

    Raises
    ------
    ValueError
        If ``species`` is not a string or no record has it (the message lists the names).
    """
    names = sorted({r.species for r in PUBLISHED})
    check.choice("species", species, names)
    return tuple(r for r in PUBLISHED if r.species == species)


def published_motion(motion: str) -> tuple[PublishedResult, ...]:
    """The records about one motion: those of that motion and those that cover both.

    Parameters
    ----------
    motion : {"longitudinal", "lateral"}

    Returns
    -------
    tuple of PublishedResult
        In :data:`PUBLISHED`'s order; a ``"both"`` record appears for either motion.

    Raises
    ------
    ValueError
        If ``motion`` is not one of the two.
    """
    motion = check.choice("motion", motion, ("longitudinal", "lateral"))
    return tuple(r for r in PUBLISHED if r.motion in (motion, "both"))


def _ms(value: float | None) -> float | None:
    return None if value is None else 1e3 * value


def _row(r: PublishedResult) -> dict[str, Any]:
    ms = _ms
    return {
        "cite": r.cite, "species": r.species, "method": r.method, "attitude": r.attitude,
        "verdict": r.verdict, "mode_type": r.mode_type,
        "doubling_time_ms": ms(r.doubling_time_s),
        "doubling_time_wingbeats": r.doubling_time_wingbeats,
        "oscillation_period_ms": ms(r.oscillation_period_s),
        "wingbeat_ms": ms(r.wingbeat_s),
        "halving_times_ms": tuple(1e3 * t for t in r.halving_times_s),
        "exponents_per_s": r.exponents_per_s,
        "status": r.status, "quote": r.quote, "note": r.note, "preset": r.preset,
        "motion": r.motion, "methods": r.methods, "modes": r.mode_labels,
        "reading": r.reading, "taxon": r.taxon,
    }


def as_rows(records: Iterable[PublishedResult] | None = None) -> list[dict[str, Any]]:
    """Records as table rows (dicts), times in ms and the doubling time also in wingbeats.

    Parameters
    ----------
    records : iterable of PublishedResult, optional
        The records to flatten (default: all of :data:`PUBLISHED`).

    Returns
    -------
    list of dict
        One dict per record, with keys ``cite``, ``species``, ``method``, ``attitude``,
        ``verdict``, ``mode_type``, ``doubling_time_ms``, ``doubling_time_wingbeats`` (None
        unless the source gives the wingbeat), ``oscillation_period_ms``, ``wingbeat_ms``,
        ``halving_times_ms``, ``exponents_per_s``, ``status``, ``quote``, ``note``, ``preset``,
        ``motion``, ``methods`` (tuple of :data:`METHODS` labels), ``modes`` (one text per
        mode, type first: :attr:`PublishedResult.mode_labels`), ``reading``, ``taxon``.

    Raises
    ------
    ValueError
        If ``records`` is not an iterable of :class:`PublishedResult`.
    """
    if records is None:
        records = PUBLISHED
    if isinstance(records, (str, bytes)) or not isinstance(records, Iterable):
        raise ValueError(f"`records` must be an iterable of PublishedResult; got {records!r}")
    items = list(records)
    for i, r in enumerate(items):
        check.instance(f"records[{i}]", r, PublishedResult)
    return [_row(r) for r in items]


def agreement(record: PublishedResult, mode_type: str, verdict: str) -> str:
    """Whether our result agrees with a published one: ``"yes"``, ``"no"`` or ``"not stated"``.

    Where either side is stable the verdicts are compared; otherwise the type of the unstable
    mode (``"oscillatory"``, ``"real"``): a real divergence and an oscillation are different
    instabilities even at similar growth rates.

    Parameters
    ----------
    record : PublishedResult
    mode_type : str
        Our leading mode's type (``"oscillatory"``, ``"real"`` or ``"flip"``).
    verdict : {"unstable", "stable"}
        Ours.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If ``verdict`` is not one of the two.
    """
    verdict = check.choice("verdict", verdict, ("unstable", "stable"))
    if record.verdict is None:
        return "not stated"
    if record.verdict == "stable" or verdict == "stable":
        return "yes" if record.verdict == verdict else "no"
    if record.mode_type in (None, "stable"):
        return "not stated"
    return "yes" if record.mode_type == mode_type else "no"

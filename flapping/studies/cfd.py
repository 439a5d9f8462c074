"""Sun's group's CFD stability derivatives as data, and our model on their insect (issue 28).

Three parts, in the order of the issue:

1. **The published derivatives as data** (:data:`STUDIES`, :class:`CFDStudy`): each number with
   its source, the table it is printed in and a status, ``"read"`` (read in the source during
   this work) or ``"estimated"`` (not read: from memory of a cited source, or computed by a stated
   method). The transcription is checked by feeding the derivatives into the published linear
   system (:meth:`CFDStudy.matrix`) and comparing its modes with the published ones
   (:func:`check_transcription`).
2. **Our model on their insect** (:func:`compare`): their morphology and kinematics as an
   :class:`~flapping.model.morphology.Insect`, trimmed by our hover solve, our cycle-averaged
   derivatives in their non-dimensional form beside theirs, term by term, with both sets of
   averaged modes and our Floquet multipliers.
3. **Which term decides the mode type** (:func:`swap_table`: one term or a group of ours
   replaced by theirs; :func:`physics_table`: the candidate physics the model has today, each
   with its effect on M_u+ and on the mode type).

The published non-dimensional system (Sun & Xiong 2005, attitude free, hover, body axes with x
horizontal at the equilibrium, z down, theta nose up). Reference velocity U = 2 Phi n r2 (Phi
the peak-to-peak stroke amplitude, r2 its radius of gyration times R), length c (mean chord),
time T = 1/n (the wingbeat period), area S = 2 R c (both wings). With u+ = u/U, w+ = w/U,
q+ = q T, t+ = t/T, forces over 0.5 rho U^2 S and the moment over 0.5 rho U^2 S c, the equations
m du/dt = X_u u + X_w w + X_q q - m g theta (and likewise w, q) become::

    d/dt+ [u+, w+, q+, theta] = A+ [u+, w+, q+, theta]

    A+ = [[X_u+/m+, X_w+/m+, X_q+/m+, -g+],
          [Z_u+/m+, Z_w+/m+, Z_q+/m+,  0 ],
          [M_u+/I+, M_w+/I+, M_q+/I+,  0 ],
          [   0   ,    0   ,    1   ,  0 ]]

with m+ = m / (0.5 rho U S T), I+ = I_y / (0.5 rho U^2 S c T^2), g+ = g T / U, and
X_u+ = X_u / (0.5 rho U S), X_q+ = X_q / (0.5 rho U^2 S T), M_u+ = M_u / (0.5 rho U S c),
M_q+ = M_q / (0.5 rho U^2 S c T) (derivatives of the dimensional loads). In matrix form: with
D = diag(U, U, 1/T, 1), the dimensional system matrix is A = D A+ D^-1 / T (eigenvalues
lambda = lambda+ / T) and a dimensional Jacobian J per unit mass and inertia maps back as
A+ = T D^-1 J D. The time scale T, not c/U, is the one with which the table below reproduces the
published modes (with c/U the pitch-rate terms come out 7 times too small and no choice of m+
and I+ fits; checked by hand, not kept).

What the sources give and what they do not (2026-12-03):

- The derivative table: a journal "view-large" table page of J. Exp. Biol. (cob.silverchair.com
  /view-large/6176870, "Table 1. Non-dimensional aerodynamic derivatives"), which does not name
  its paper. Attributed to Sun & Xiong (2005) by its modes: with the bumblebee's g+ it fits all
  four of their abstract's numbers to rounding with m+ and I+ the only free numbers
  (:func:`check_transcription`). A second page (journals.biologists.com/view-large/6218122,
  "Non-dimensional stability derivatives": -1.28 -0.04 2.32 0.01 -1.26 0.05 -0.28 -0.03, one value
  missing) is kept out (:data:`UNATTRIBUTED`): its paper and insect are not established and it
  lacks a term.
- m+ and I+: Sun & Xiong's own values were not read. They are identified from the published modes
  (:func:`identify_mass_and_inertia`), and the identified m+ is compared with the one the
  morphology gives (6 % apart at rho = 1.225: their density and wing area were not read).
- Sun, Wang & Xiong (2007, hoverfly, cranefly, dronefly, hawkmoth), Taha, Hajj & Nayfeh (2014,
  the hawkmoth QS-versus-CFD comparison) and Gao et al. (2009): their tables were not found in the
  stored sources; they are not in :data:`STUDIES`. A second, wider search (2026-12-03, branch
  cfdmore; :data:`SEARCHED` lists each study, what its stored pages show and why it is left out)
  found no further table: the stored full-text pages of these papers are excerpted from their
  beginning (title, abstract, introduction), so only their abstracts and the two J. Exp. Biol.
  table pages above could be read.

What the evidence supports (Sun & Xiong's bumblebee; tests/test_cfd.py checks each statement):
the term that decides the mode type is M_u+, the pitch moment per forward speed. Swapped alone
into our averaged system it turns our real mode into an oscillation; ours swapped into theirs
turns their oscillation real; no other single term changes the type. Ours has the opposite sign
(forward speed pitches our insect nose down) and is an order of magnitude smaller. Of the
physics the model has, the hinge height above the CG adds -h X_u+/c to M_u+ (the wings' drag
acting above the CG), a centre of pressure nearer the leading edge raises M_u+ too, and wing mass
and a hinge offset (with the mean stroke angle trimmed) move it little; :func:`physics_table`
gives the numbers, and :func:`mu_law` the straight lines they lie on. With M_u+ varied alone
(:func:`mu_sweep`), the type changes where M_u+ changes sign, in our system and in theirs
(:func:`mode_type_threshold`). Why CFD's M_u+ is large and positive is not settled here.

A centre of pressure that moves with the angle of attack (issue 28's candidate) is not an
option here: in these loads forward speed enters a section's speed U, not its induced angle
w_eff/U (w_eff does not contain u), so on the hover orbit, where w_eff is small, it would move
M_u+ only through its mean position, which :func:`physics_table` varies. Testing it needs an
induced flow (a downwash or wake model) in the aerodynamic model first.

The trim's angle of attack (:func:`angle_of_attack_table`, :func:`type_change_angle`): our hover
solve keeps the paper's eq. (40) mean angle of attack and trims the amplitude; on this bumblebee
eq. (40) gives a small angle. Held higher (``alpha_m``), with the amplitude trimmed instead, the
wings' drag grows (X_u+), the hinge above the CG turns it into a nose-up M_u+, and the mode turns
oscillatory where M_u+ changes sign; CFD's magnitude of M_u+ is not reached.

Conventions: SI inside; the derivative names are ``"Xu", "Xw", "Xq", "Zu", ..., "Mq"`` and
stand for the non-dimensional X_u+ ... M_q+.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import brentq, least_squares

from flapping import _validation
from flapping.hover import HoverOrbit, find_hover_orbit
from flapping.hover.stability import HoverStability, hover_stability
from flapping.model.morphology import Insect
from flapping.model.presets import ellington_r1
from flapping.studies import _published
from flapping.studies._modes import DERIVATIVES, REAL_TOL, SWAP_GROUPS, mode_summary
from flapping.studies._published import Number, sun_xiong_2005_reference

if TYPE_CHECKING:  # pandas is the optional ``sweep`` extra, imported when a table is built
    import pandas

__all__ = [
    "DERIVATIVES",
    "MU_RANGE",
    "STATUSES",
    "Number",
    "PublishedModes",
    "CFDStudy",
    "STUDIES",
    "UNATTRIBUTED",
    "SEARCHED",
    "study",
    "mode_summary",
    "identify_mass_and_inertia",
    "TranscriptionCheck",
    "check_transcription",
    "CFDComparison",
    "compare",
    "study_insect",
    "our_derivatives",
    "SWAP_GROUPS",
    "swap_table",
    "physics_table",
    "hinge_height_for",
    "BASES",
    "mu_sweep",
    "mode_type_threshold",
    "MuLaw",
    "mu_law",
    "ANGLES_DEG",
    "angle_of_attack_table",
    "TypeChangeAngle",
    "type_change_angle",
]

#: Statuses of a :class:`Number`: read in the source during this work, or not (shared with the
#: lateral study, :mod:`flapping.studies._published`).
STATUSES: tuple[str, ...] = _published.STATUSES


@dataclass(frozen=True)
class PublishedModes:
    """The modes a study publishes, as times [s] (as printed: rounded).

    Attributes
    ----------
    oscillation_period : float
        Period of the unstable oscillatory mode [s].
    doubling_time : float
        Its time to double in amplitude [s].
    halving_times : tuple of float
        Halving times of the stable subsidence modes [s], fastest first.
    wingbeat : float
        The wingbeat period T [s].
    source : str
        Where they are printed.
    """

    oscillation_period: float
    doubling_time: float
    halving_times: tuple[float, ...]
    wingbeat: float
    source: str

    def targets(self) -> np.ndarray:
        """(growth rate, angular frequency, subsidence rates...) [1/s] the times stand for."""
        return np.array([math.log(2.0) / self.doubling_time,
                         2.0 * math.pi / self.oscillation_period,
                         *(-math.log(2.0) / h for h in self.halving_times)])


@dataclass(frozen=True)
class CFDStudy:
    """A CFD study's published derivatives, reference quantities and modes.

    Attributes
    ----------
    key : str
        The study's {cite} key.
    insect : str
        Which insect.
    derivatives : mapping of str to Number
        X_u+ ... M_q+ (:data:`DERIVATIVES`), non-dimensional as in the module docstring.
    reference : mapping of str to Number
        ``mass`` [kg], ``semi_span`` R [m], ``mean_chord`` c [m], ``r2`` (over R),
        ``stroke_amplitude`` Phi [rad] (peak to peak, the sources' convention), ``frequency`` n
        [Hz], ``air_density`` [kg/m^3], ``gravity`` [m/s^2], ``hinge_height`` (the wing root
        above the centre of gravity at hover, [m]), ``hinge_offset`` (the wing root ahead of it,
        [m]), ``wing_mass`` (one wing, [kg]), ``body_length`` [m] (the unit in which the
        hinge height is estimated).
    modes : PublishedModes
    notes : tuple of str
        What the comparison with our model does not model, and other caveats.
    """

    key: str
    insect: str
    derivatives: Mapping[str, Number]
    reference: Mapping[str, Number]
    modes: PublishedModes
    notes: tuple[str, ...] = ()

    def value(self, name: str) -> float:
        """The SI value of a reference quantity (a ValueError naming the quantities if absent)."""
        return self.reference[_validation.choice("name", name, tuple(self.reference))].value

    @property
    def speed(self) -> float:
        """U = 2 Phi n r2 [m/s] (Phi peak to peak, r2 times R)."""
        return (2.0 * self.value("stroke_amplitude") * self.value("frequency")
                * self.value("r2") * self.value("semi_span"))

    @property
    def period(self) -> float:
        """T = 1/n [s], the reference time."""
        return 1.0 / self.value("frequency")

    @property
    def area(self) -> float:
        """S = 2 R c [m^2], both wings."""
        return 2.0 * self.value("semi_span") * self.value("mean_chord")

    @property
    def gravity_ratio(self) -> float:
        """g+ = g T / U."""
        return self.value("gravity") * self.period / self.speed

    def mass_ratio(self, mass: float | None = None) -> float:
        """m+ = m / (0.5 rho U S T), of ``mass`` [kg] (default the study's)."""
        m = self.value("mass") if mass is None else _validation.positive("mass", mass, unit="kg")
        return m / (0.5 * self.value("air_density") * self.speed * self.area * self.period)

    def inertia_scale(self) -> float:
        """0.5 rho U^2 S c T^2 [kg m^2]: I+ = I_y / this."""
        return (0.5 * self.value("air_density") * self.speed ** 2 * self.area
                * self.value("mean_chord") * self.period ** 2)

    def derivative_vector(self) -> np.ndarray:
        """The nine derivatives in the order of :data:`DERIVATIVES`."""
        return np.array([self.derivatives[n].value for n in DERIVATIVES])

    def matrix(self, mass_ratio: float, inertia_ratio: float,
               derivatives: Sequence[float] | None = None) -> np.ndarray:
        """The non-dimensional system matrix A+ of the module docstring.

        Parameters
        ----------
        mass_ratio, inertia_ratio : float
            m+ and I+ (> 0).
        derivatives : sequence of 9 floats, optional
            In the order of :data:`DERIVATIVES`; default the study's.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
        """
        mp = _validation.positive("mass_ratio", mass_ratio)
        ip = _validation.positive("inertia_ratio", inertia_ratio)
        d = self.derivative_vector() if derivatives is None else _validation.vector(
            "derivatives", derivatives, size=9)
        return _system(d, mp, ip, self.gravity_ratio)

    def scaling(self) -> np.ndarray:
        """D = diag(U, U, 1/T, 1): the dimensional state is D times the non-dimensional one."""
        return np.diag([self.speed, self.speed, 1.0 / self.period, 1.0])


def _system(d: np.ndarray, mp: float, ip: float, gp: float) -> np.ndarray:
    xu, xw, xq, zu, zw, zq, mu, mw, mq = d
    return np.array([[xu / mp, xw / mp, xq / mp, -gp],
                     [zu / mp, zw / mp, zq / mp, 0.0],
                     [mu / ip, mw / ip, mq / ip, 0.0],
                     [0.0, 0.0, 1.0, 0.0]])


def _derivatives_of(a_plus: np.ndarray, mp: float, ip: float) -> np.ndarray:
    """X_u+ ... M_q+ of a non-dimensional system matrix (the inverse of :func:`_system`)."""
    block = np.array(a_plus[:3, :3], dtype=float)
    block[:2] *= mp
    block[2] *= ip
    return block.reshape(-1)


# =========================================================================== the data
_SX = "sun2005"
_SX_TABLE = ("J. Exp. Biol. table page cob.silverchair.com/view-large/6176870, 'Table 1. "
             "Non-dimensional aerodynamic derivatives' (the page does not name its paper; "
             "attributed by its modes, see check_transcription)")
def _sun_xiong_2005() -> CFDStudy:
    values = (-0.785, 0.050, -0.090, -0.031, -1.033, -0.031, 2.389, -0.190, -0.883)
    derivs = {n: Number(v, _SX, _SX_TABLE, "read") for n, v in zip(DERIVATIVES, values,
                                                                     strict=True)}
    ref = sun_xiong_2005_reference()
    modes = PublishedModes(0.32, 0.1, (0.024, 0.37), 6.4e-3, _SX + ", abstract (verified)")
    notes = ("body drag: not modelled (Sun & Xiong compute the body's loads too; the body's "
             "contribution to the derivatives is not separated in the table)",
             "stroke plane: horizontal at hover in both; our body x axis is the stroke plane's "
             "(the body angle only places the CG relative to the wing root)",
             "wing-wake interaction, unsteady circulation, wing rotation timing: not modelled "
             "(quasi-steady blade elements)",
             "trim: theirs sets the mid-stroke angles of attack and the mean stroke angle by "
             "force and moment balance; ours keeps alpha_m at eq. (40) and trims Phi (and "
             "phi_bar when the hinge is off the CG's vertical)")
    return CFDStudy(_SX, "bumblebee", MappingProxyType(derivs), MappingProxyType(ref), modes,
                    notes)


#: The studies whose table is read and reproduces its published modes, by {cite} key.
STUDIES: Mapping[str, CFDStudy] = MappingProxyType({_SX: _sun_xiong_2005()})

#: Tables found but kept out: where, what they read, and why they are not used.
UNATTRIBUTED: tuple[Mapping[str, Any], ...] = (
    MappingProxyType({
        "where": "journals.biologists.com/view-large/6218122, J. Exp. Biol. 'Table 1. "
                 "Non-dimensional stability derivatives'",
        "reads": "X_u+ ... M_q+ in the order Xu Zu Mu Xw Zw Mw Xq Zq Mq: -1.28 -0.04 2.32 0.01 "
                 "-1.26 0.05 -0.28 -0.03 (the ninth value missing from the stored page)",
        "why": "paper and insect not established; one term missing, so its modes cannot be "
               "checked. A guess, not used: Sun & Wang (2007, J. Exp. Biol. 210:2714, model "
               "hoverfly), whose summary speaks of 'stability and control derivatives' where Sun "
               "& Xiong's speaks of 'aerodynamic derivatives' (the two tables' titles). Searched "
               "again (branch cfdmore): no stored page repeats these numbers or names the "
               "table's paper, and no stored source gives that paper's modes as times (Sun & "
               "Wang's summary gives mode types only). The one number found that could bear on "
               "a hoverfly-like model insect, zhang2010's abstract (the model dronefly's "
               "longitudinal unstable mode doubles in about 14 wingbeats), leaves three unknowns "
               "(the missing term, m+, I+) against one datum, so it cannot attribute the table",
    }),
)

#: Studies searched for a longitudinal derivative table and left out of :data:`STUDIES`, by
#: {cite} key: what the stored sources show of them (read during this work) and why they are
#: not used. None gives both a table and its modes.
SEARCHED: Mapping[str, Mapping[str, str]] = MappingProxyType({
    "sun2007": MappingProxyType({
        "insect": "model insect with hoverfly data",
        "found": "summary and introduction (jeb.biologists.org/cgi/content/full/210/15/2714, "
                 "cob.silverchair.com article-split page): the same three modes as the "
                 "bumblebee, one unstable oscillatory, one fast and one slow subsidence; CFD "
                 "stability and control derivatives",
        "why": "the derivative table is not in the stored excerpts (possibly the unattributed "
               "table, see UNATTRIBUTED) and the summary gives mode types, not times",
    }),
    "sun2007acta": MappingProxyType({
        "insect": "hoverfly, cranefly, dronefly, hawkmoth",
        "found": "nothing of the paper itself; its result second-hand (Sci. Rep. 2025 "
                 "introduction: the same modes as the bumblebee)",
        "why": "no table and no modes in the stored sources",
    }),
    "taha2014": MappingProxyType({
        "insect": "hawkmoth (Sun et al.'s kinematics and trim)",
        "found": "first page (m.moam.info copy, JGCD 37(3), doi 10.2514/1.62323): QS "
                 "derivatives by complex-step differences, for the hawkmoth with the "
                 "kinematics and trim data of Sun et al.'s CFD, to compare with it",
        "why": "the comparison table is not in the stored excerpt",
    }),
    "gao2009": MappingProxyType({
        "insect": "hawkmoth",
        "found": "abstract (fdocuments.net and scribd copies, J. Biomech. Sci. Eng. 4(1):105): "
                 "CFD derivatives; a stable oscillatory, a stable fast and a stable slow "
                 "subsidence mode, hover stable",
        "why": "the derivative table and the modes' times are not in the stored excerpts",
    }),
    "wu2012": MappingProxyType({
        "insect": "dronefly and hawkmoth",
        "found": "abstract: Floquet against averaging; averaging valid for the dronefly only",
        "why": "no derivative table or modes' times in the stored sources",
    }),
    "zhang2010": MappingProxyType({
        "insect": "dronefly (lateral)",
        "found": "abstract (m.moam.info copy): the longitudinal unstable mode doubles in about "
                 "14 wingbeat periods",
        "why": "lateral derivatives only; one longitudinal number, no table",
    }),
    "sun2005honeybee": MappingProxyType({
        "insect": "honeybee",
        "found": "abstract (from an earlier reading, see book/references.bib): the unstable "
                 "oscillatory mode doubles in 0.11 s, 22 wingbeats of 5.1 ms",
        "why": "no derivative table in the stored sources",
    }),
    "chengdeng2011": MappingProxyType({
        "insect": "four species (quasi-steady, not CFD)",
        "found": "abstract and first page: analytic QS damping derivatives at hover",
        "why": "not a CFD table; no numbers in the stored excerpt",
    }),
})


def study(key: str) -> CFDStudy:
    """The study of a {cite} key in :data:`STUDIES` (``ValueError`` naming the keys if absent)."""
    return STUDIES[_validation.choice("study", key, tuple(STUDIES))]


_lookup = study  # compare's argument is named ``study``


# =========================================================================== modes
def _mode_numbers(eigenvalues: np.ndarray) -> np.ndarray | None:
    """(growth rate, angular frequency, real rates ascending) of one complex pair and two real
    eigenvalues [1/s]; None for another pattern."""
    cpx = eigenvalues[np.abs(eigenvalues.imag) > REAL_TOL * np.abs(eigenvalues)]
    real = np.sort(eigenvalues[np.abs(eigenvalues.imag) <= REAL_TOL
                               * np.abs(eigenvalues)].real)
    if cpx.size != 2 or real.size != 2:
        return None
    return np.array([cpx[0].real, abs(cpx[0].imag), *real])


def identify_mass_and_inertia(study_: CFDStudy) -> tuple[float, float]:
    """m+ and I+ with which the study's derivatives give its published modes (least squares).

    The published numbers (doubling time, period, two halving times) are four; m+ and I+ two;
    g+ comes from the reference quantities. Relative residuals, each rate weighted by itself.

    Parameters
    ----------
    study\\_ : CFDStudy

    Returns
    -------
    mass_ratio, inertia_ratio : float
        m+ and I+.

    Raises
    ------
    ValueError
        If the fit leaves the pattern of one complex pair and two real modes.
    """
    _validation.instance("study_", study_, CFDStudy)
    target = study_.modes.targets()
    period = study_.period

    def residual(log_x: np.ndarray) -> np.ndarray:
        ev = np.linalg.eigvals(study_.matrix(*np.exp(log_x))) / period
        numbers = _mode_numbers(ev)
        return np.full(4, 1e3) if numbers is None else (numbers - target) / np.abs(target)

    start = np.log([study_.mass_ratio(), 10.0])
    fit = least_squares(residual, start, x_scale=1.0)
    if not np.all(np.abs(fit.fun) < 1e3):
        raise ValueError(f"{study_.key}: no m+, I+ give one oscillatory and two real modes")
    mp, ip = np.exp(fit.x)
    return float(mp), float(ip)


@dataclass(frozen=True)
class TranscriptionCheck:
    """The published derivatives in the published system, against the published modes.

    Attributes
    ----------
    study : CFDStudy
    mass_ratio, inertia_ratio : float
        m+ and I+ identified from the modes (:func:`identify_mass_and_inertia`).
    mass_ratio_morphology : float
        m+ from the reference quantities (mass, rho, U, S, T).
    pitch_inertia : float
        The identified I+ in SI [kg m^2].
    eigenvalues : ndarray
        Of the published system at the identified m+, I+ [1/s] (by real part, descending).
    reproduced, published : dict of str to float
        ``oscillation_period``, ``doubling_time``, ``fast_halving``, ``slow_halving`` [s].
    """

    study: CFDStudy
    mass_ratio: float
    inertia_ratio: float
    mass_ratio_morphology: float
    pitch_inertia: float
    eigenvalues: np.ndarray
    reproduced: Mapping[str, float]
    published: Mapping[str, float]

    def relative_errors(self) -> dict[str, float]:
        """(reproduced - published) / published, per number."""
        return {k: (self.reproduced[k] - v) / v for k, v in self.published.items()}


def check_transcription(key: str) -> TranscriptionCheck:
    """Feed a study's derivatives into the published linear system and read off its modes.

    Parameters
    ----------
    key : str
        A key of :data:`STUDIES`.

    Returns
    -------
    TranscriptionCheck
    """
    s = study(key)
    mp, ip = identify_mass_and_inertia(s)
    ev = np.linalg.eigvals(s.matrix(mp, ip)) / s.period
    ev = ev[np.argsort(-ev.real)]
    numbers = _mode_numbers(ev)
    assert numbers is not None  # identify_mass_and_inertia checked the pattern
    names = ("oscillation_period", "doubling_time", "fast_halving", "slow_halving")
    reproduced = (2.0 * math.pi / numbers[1], math.log(2.0) / numbers[0],
                  -math.log(2.0) / numbers[2], -math.log(2.0) / numbers[3])
    published = (s.modes.oscillation_period, s.modes.doubling_time, *s.modes.halving_times)
    return TranscriptionCheck(s, mp, ip, s.mass_ratio(), ip * s.inertia_scale(), ev,
                              MappingProxyType(dict(zip(names, reproduced, strict=True))),
                              MappingProxyType(dict(zip(names, published, strict=True))))


# =========================================================================== our model
def study_insect(study_: CFDStudy, **changes: Any) -> Insect:
    """The study's insect as our :class:`~flapping.model.morphology.Insect`.

    R, S = R c (one wing), r2 and r1 = :func:`~flapping.model.presets.ellington_r1` of r2
    (Ellington's fit: the sources' r1 was not read), n, Phi/2 (our amplitude is the half
    peak-to-peak), m, rho, g, the hinge (height above and offset ahead of the CG, in the stroke
    plane's axes, which are our body axes when the stroke plane is horizontal at hover), massless
    wings (the CFD derivatives are aerodynamic), and I_y from the published modes
    (:func:`identify_mass_and_inertia`: Sun & Xiong's own I_y was not read).

    Parameters
    ----------
    study\\_ : CFDStudy
    **changes
        Insect fields to change (SI), e.g. ``hinge_height=0.0``.

    Returns
    -------
    Insect
    """
    _validation.instance("study_", study_, CFDStudy)
    _, ip = identify_mass_and_inertia(study_)
    v = study_.value
    insect = Insect(
        name=f"{study_.insect} ({study_.key})", semi_span=v("semi_span"),
        wing_area=v("semi_span") * v("mean_chord"), r1=ellington_r1(v("r2")), r2=v("r2"),
        frequency=v("frequency"), stroke_amplitude=v("stroke_amplitude") / 2.0, mass=v("mass"),
        pitch_inertia=ip * study_.inertia_scale(), air_density=v("air_density"),
        gravity=v("gravity"), hinge_height=v("hinge_height"), hinge_offset=v("hinge_offset"))
    return insect.with_(**changes) if changes else insect


def _trims(insect: Insect) -> tuple[str, ...]:
    """One trim with the hinge at the CG; the mean stroke angle too when it is off it."""
    off = insect.hinge_offset != 0.0 or insect.hinge_height != 0.0
    return ("amplitude", "stroke_mean") if off else ("amplitude",)


def our_derivatives(study_: CFDStudy, stability: HoverStability) -> np.ndarray:
    """Our cycle-averaged derivatives in the study's non-dimensional form (:data:`DERIVATIVES`).

    A+ = T D^-1 J D of the averaged Jacobian J (per unit mass and pitch inertia, SI), then
    X+ = m+ A+ and M+ = I+ A+ row by row, m+ and I+ of our insect's own m and I_y.

    Parameters
    ----------
    study\\_ : CFDStudy
    stability : HoverStability
        Of our insect's hover orbit.

    Returns
    -------
    numpy.ndarray, shape (9,)
    """
    problem = stability.orbit.problem
    if problem is None:
        raise ValueError("`stability` must be of a hover orbit (its problem knows the insect)")
    insect = problem.insect
    d = study_.scaling()
    a_plus = study_.period * np.linalg.solve(d, stability.averaged_jacobian) @ d
    return _derivatives_of(a_plus, study_.mass_ratio(insect.mass),
                           insect.pitch_inertia / study_.inertia_scale())


@dataclass(frozen=True)
class CFDComparison:
    """Our model on a CFD study's insect (:func:`compare`).

    Attributes
    ----------
    study : CFDStudy
    insect : Insect
        Ours: their morphology and kinematics.
    orbit : HoverOrbit
        Our hover orbit (trimmed as :func:`compare` says).
    stability : HoverStability
        Its Floquet analysis and averaged system.
    table : pandas.DataFrame
        Index :data:`DERIVATIVES`; columns ``theirs``, ``ours`` (non-dimensional) and
        ``ratio`` (ours / theirs).
    their_eigenvalues, our_eigenvalues : ndarray
        Of the averaged systems [1/s] (by real part, descending): theirs at the m+ and I+ of
        :func:`identify_mass_and_inertia`, ours of our averaged Jacobian.
    our_multipliers : ndarray
        Our Floquet multipliers (by modulus, descending).
    their_mode, our_mode, our_floquet_mode : dict
        :func:`mode_summary` of each (the Floquet one from the exponents).
    trim : dict of str to float
        ``their_stroke_amplitude_deg`` (peak to peak), ``our_stroke_amplitude_deg`` (peak to
        peak, trimmed), ``our_stroke_mean_deg`` (trimmed if the hinge is off the CG).
    not_modelled : tuple of str
    """

    study: CFDStudy
    insect: Insect
    orbit: HoverOrbit
    stability: HoverStability
    table: pandas.DataFrame
    their_eigenvalues: np.ndarray
    our_eigenvalues: np.ndarray
    our_multipliers: np.ndarray
    their_mode: Mapping[str, Any]
    our_mode: Mapping[str, Any]
    our_floquet_mode: Mapping[str, Any]
    trim: Mapping[str, float]
    not_modelled: tuple[str, ...] = field(default=())


def _solve(insect: Insect, guess: HoverOrbit | None = None,
           **hover_options: Any) -> tuple[HoverOrbit, HoverStability]:
    options: dict[str, Any] = {"trims": _trims(insect), **hover_options}
    if guess is not None:
        options.setdefault("x0_guess", np.asarray(guess.x0).tolist())
        options.setdefault("amplitude_guess", guess.amplitude)
        if "stroke_mean" in options["trims"]:
            insect = insect.with_(stroke_mean=guess.stroke_mean)
    orbit = find_hover_orbit(insect, **options)
    return orbit, hover_stability(orbit)


def compare(study: str | CFDStudy = "sun2005", **hover_options: Any) -> CFDComparison:
    """Our model on a CFD study's insect: derivatives term by term and both sets of modes.

    Our insect is :func:`study_insect` (their morphology, kinematics and hinge, massless wings);
    our hover solve trims the stroke amplitude (and the mean stroke angle when the hinge is off
    the CG) at our mean angle of attack, where theirs trims the mid-stroke angles of attack and
    the mean stroke angle in the CFD: both amplitudes are reported.

    Parameters
    ----------
    study : str or CFDStudy
        A key of :data:`STUDIES` or a study.
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit` (e.g. ``backend``).

    Returns
    -------
    CFDComparison

    Raises
    ------
    ValueError
        For an unknown study.
    ConvergenceError
        If our hover orbit cannot be found.
    """
    import pandas

    s = study if isinstance(study, CFDStudy) else _lookup(study)
    insect = study_insect(s)
    orbit, stab = _solve(insect, **hover_options)
    theirs = s.derivative_vector()
    ours = our_derivatives(s, stab)
    table = pandas.DataFrame({"theirs": theirs, "ours": ours, "ratio": ours / theirs},
                             index=pandas.Index(DERIVATIVES, name="derivative"))
    mp, ip = identify_mass_and_inertia(s)
    their_ev = np.linalg.eigvals(s.matrix(mp, ip)) / s.period
    their_ev = their_ev[np.argsort(-their_ev.real)]
    our_ev = np.asarray(stab.averaged_eigenvalues, dtype=complex)
    trim = {"their_stroke_amplitude_deg": math.degrees(s.value("stroke_amplitude")),
            "our_stroke_amplitude_deg": 2.0 * math.degrees(orbit.amplitude),
            "our_stroke_mean_deg": math.degrees(orbit.stroke_mean)}
    return CFDComparison(s, insect, orbit, stab, table, their_ev, our_ev,
                         np.asarray(stab.multipliers), MappingProxyType(mode_summary(their_ev)),
                         MappingProxyType(mode_summary(our_ev)),
                         MappingProxyType(mode_summary(np.asarray(stab.exponents))),
                         MappingProxyType(trim), s.notes)


# =========================================================================== which term


def swap_table(study: str | CFDComparison = "sun2005", **hover_options: Any
               ) -> pandas.DataFrame:
    """Our derivatives with theirs swapped in, one at a time and in groups, and the reverse.

    Every system is the published one (module docstring) at the m+ and I+ identified from the
    published modes and their g+, so the row "none" of direction "ours <- theirs" is our
    averaged system at their mass and inertia ratios, and "all" is theirs (their modes).

    Parameters
    ----------
    study : str or CFDComparison
        A key of :data:`STUDIES` (then :func:`compare` runs) or a comparison already made.
    **hover_options
        Passed to :func:`compare` with a key.

    Returns
    -------
    pandas.DataFrame
        One row per swap: ``direction`` ("ours <- theirs": our system with their terms;
        "theirs <- ours": theirs with ours), ``swapped`` (the terms, "+"-joined, "none" or
        "all"), ``Mu`` (the M_u+ in the system), ``type`` (of the leading mode), ``rate``
        [1/s], ``period`` [s], ``doubling_time`` [s].
    """
    import pandas

    comp = study if isinstance(study, CFDComparison) else compare(study, **hover_options)
    s = comp.study
    mp, ip = identify_mass_and_inertia(s)
    theirs, ours = s.derivative_vector(), comp.table["ours"].to_numpy()
    groups: list[tuple[str, ...]] = [(), *((n,) for n in DERIVATIVES), *SWAP_GROUPS]
    rows = []
    for direction, base, other in (("ours <- theirs", ours, theirs),
                                   ("theirs <- ours", theirs, ours)):
        for group in groups:
            d = base.copy()
            idx = [DERIVATIVES.index(n) for n in group]
            d[idx] = other[idx]
            ev = np.linalg.eigvals(_system(d, mp, ip, s.gravity_ratio)) / s.period
            label = "all" if group == DERIVATIVES else "+".join(group) or "none"
            rows.append({"direction": direction, "swapped": label,
                         "Mu": d[DERIVATIVES.index("Mu")], **mode_summary(ev)})
    return pandas.DataFrame(rows)


def _physics_cases(s: CFDStudy, insect: Insect) -> list[tuple[str, dict[str, float]]]:
    """(label, Insect changes) of :func:`physics_table`."""
    h = s.value("hinge_height")
    chord = s.value("mean_chord")
    return [
        ("as compared", {}),
        ("hinge at the CG", {"hinge_height": 0.0, "hinge_offset": 0.0}),
        *((f"hinge height x{k:g}", {"hinge_height": k * h}) for k in (0.5, 2.0, 3.0, 4.0)),
        ("hinge 1 chord ahead", {"hinge_offset": chord}),
        ("hinge 1 chord behind", {"hinge_offset": -chord}),
        ("wing mass", {"wing_mass": s.value("wing_mass")}),
        ("centre of pressure x_hat 0.1", {"center_of_pressure": 0.1}),
        ("centre of pressure x_hat 0.4", {"center_of_pressure": 0.4}),
    ]


def physics_table(study: str | CFDComparison = "sun2005", **hover_options: Any
                  ) -> pandas.DataFrame:
    """Candidate physics the model has today, each with its effect on M_u+ and the mode type.

    Each case changes our insect of :func:`compare` (the hinge's height above and offset from
    the CG, the wings' mass, the centre of pressure x_hat) and is trimmed as there: the mean
    stroke angle is a trim whenever the hinge is off the CG, so the "mean stroke angle" is the
    trim's answer to the hinge offset (column ``stroke_mean_deg``). What the model lacks today
    (a stroke plane inclined to the body axis, a centre of pressure moving with the angle of
    attack, body drag) is not in the table.

    Parameters
    ----------
    study : str or CFDComparison
        A key of :data:`STUDIES` (then :func:`compare` runs) or a comparison already made.
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    pandas.DataFrame
        One row per case: ``case``, the changed ``field`` values, ``Mu`` (our M_u+),
        ``Mq`` (our M_q+), ``averaged_type``, ``averaged_rate`` [1/s], ``averaged_period`` [s],
        ``floquet_type``, ``leading_multiplier`` (complex), ``stroke_mean_deg``,
        ``stroke_amplitude_deg`` (peak to peak), ``message`` (empty, or why no orbit was found).
    """
    import pandas

    comp = study if isinstance(study, CFDComparison) else compare(study, **hover_options)
    s = comp.study
    rows = []
    for label, changes in _physics_cases(s, comp.insect):
        row: dict[str, Any] = {"case": label, "changes": dict(changes)}
        try:
            orbit, stab = ((comp.orbit, comp.stability) if not changes else
                           _solve(comp.insect.with_(**changes), comp.orbit, **hover_options))
        except (ArithmeticError, ValueError, RuntimeError) as exc:  # ConvergenceError included
            rows.append({**row, "message": f"{type(exc).__name__}: {exc}"})
            continue
        d = our_derivatives(s, stab)
        avg = mode_summary(stab.averaged_eigenvalues)
        row.update(Mu=d[DERIVATIVES.index("Mu")], Mq=d[DERIVATIVES.index("Mq")],
                   averaged_type=avg["type"], averaged_rate=avg["rate"],
                   averaged_period=avg["period"],
                   floquet_type=mode_summary(stab.exponents)["type"],
                   leading_multiplier=complex(stab.multipliers[0]),
                   stroke_mean_deg=math.degrees(orbit.stroke_mean),
                   stroke_amplitude_deg=2.0 * math.degrees(orbit.amplitude), message="")
        rows.append(row)
    return pandas.DataFrame(rows)


#: The M_u+ values the functions of this section accept. The studies print ``|M_u+|`` up to ~2.4
#: (Sun & Xiong's 2.389); by the linear law of :func:`hinge_height_for` (h moves M_u+ by
#: -h X_u+ / c) M_u+ = +-10 puts the bumblebee's hinge ~5 cm (three body lengths) from its
#: centre of gravity, beyond which no insect lies, and the law, linear in small heights,
#: is no longer evidence (1e6 gave a 13 km hinge).
MU_RANGE: tuple[float, float] = (-10.0, 10.0)


def _mu(name: str, value: Any) -> float:
    """A target M_u+ in :data:`MU_RANGE`."""
    return _validation.real(name, value, low=MU_RANGE[0], high=MU_RANGE[1])


def hinge_height_for(comparison: CFDComparison, mu: float | None = None) -> float:
    """The hinge height [m] above the CG at which our M_u+ would equal ``mu``.

    From the law the hinge height obeys (tests/test_cfd.py checks it on solved orbits): the
    wings' force X_u u acting h above the centre of gravity adds -h X_u+ / c to M_u+, with X_u+
    independent of h. Extrapolated from the comparison's own M_u+ and X_u+; the CG straight
    below the hinge as in the comparison.

    Parameters
    ----------
    comparison : CFDComparison
    mu : float, optional
        The target M_u+ in :data:`MU_RANGE`; default theirs. ``0.0`` gives the neutral height
        where our real mode gives way to an oscillation.

    Returns
    -------
    float
        The height [m] (it may lie far outside any insect: compare with the body length).

    Raises
    ------
    ValueError
        If ``mu`` is outside :data:`MU_RANGE`.
    """
    _validation.instance("comparison", comparison, CFDComparison)
    target = (comparison.study.derivatives["Mu"].value if mu is None
              else _mu("mu", mu))
    ours = comparison.table["ours"]
    chord = comparison.study.value("mean_chord")
    return float(comparison.insect.hinge_height - (target - ours["Mu"]) * chord / ours["Xu"])


# =========================================================================== M_u+ alone
#: The systems :func:`mu_sweep` and :func:`mode_type_threshold` vary M_u+ in: ours (our other
#: eight derivatives) or theirs, both at the m+, I+ and g+ of the published system.
BASES: tuple[str, ...] = ("ours", "theirs")


def _base(comparison: CFDComparison, base: str) -> tuple[np.ndarray, float, float, CFDStudy]:
    _validation.instance("comparison", comparison, CFDComparison)
    _validation.choice("base", base, BASES)
    s = comparison.study
    d = (comparison.table["ours"] if base == "ours" else comparison.table["theirs"]).to_numpy()
    mp, ip = identify_mass_and_inertia(s)
    return np.array(d, dtype=float), mp, ip, s


def _leading(d: np.ndarray, mu: float, mp: float, ip: float, s: CFDStudy) -> dict[str, Any]:
    d = d.copy()
    d[DERIVATIVES.index("Mu")] = mu
    return mode_summary(np.linalg.eigvals(_system(d, mp, ip, s.gravity_ratio)) / s.period)


def mu_sweep(comparison: CFDComparison, values: ArrayLike, base: str = "ours"
             ) -> pandas.DataFrame:
    """The leading mode of the published system as M_u+ alone varies.

    Parameters
    ----------
    comparison : CFDComparison
    values : array_like of float
        The M_u+ values, each in :data:`MU_RANGE`.
    base : {"ours", "theirs"}
        Whose other eight derivatives the system keeps (at the published m+, I+, g+).

    Returns
    -------
    pandas.DataFrame
        One row per value: ``Mu``, ``type``, ``rate`` [1/s], ``frequency`` (the angular
        frequency of the leading mode, 0 if real, [rad/s]), ``period`` [s], ``doubling_time``
        [s].
    """
    import pandas

    mus = np.atleast_1d(_validation.array("values", values)).ravel()  # NaN: a LinAlgError
    for mu in mus.tolist():
        _mu("values", mu)
    d, mp, ip, s = _base(comparison, base)
    rows = []
    for mu in mus.tolist():
        lead = _leading(d, float(mu), mp, ip, s)
        freq = 0.0 if lead["type"] == "real" else 2.0 * math.pi / lead["period"]
        rows.append({"Mu": float(mu), **lead, "frequency": freq})
    return pandas.DataFrame(rows)


def mode_type_threshold(comparison: CFDComparison, base: str = "ours",
                        xtol: float = 1e-10) -> float:
    """The M_u+ at which the leading mode changes type, between ours and theirs (bisection).

    Parameters
    ----------
    comparison : CFDComparison
    base : {"ours", "theirs"}
        Whose other eight derivatives the system keeps (:func:`mu_sweep`).
    xtol : float
        Width of the final bracket (> 0).

    Returns
    -------
    float
        The threshold M_u+: one type below it, the other above (within ``xtol``).

    Raises
    ------
    ValueError
        If the leading mode has the same type at our M_u+ and at theirs (no bracket).
    """
    d, mp, ip, s = _base(comparison, base)
    tol = _validation.positive("xtol", xtol)
    lo = float(comparison.table.loc["Mu", "ours"])
    hi = float(comparison.table.loc["Mu", "theirs"])
    kind_lo = _leading(d, lo, mp, ip, s)["type"]
    if kind_lo == _leading(d, hi, mp, ip, s)["type"]:
        raise ValueError(f"the leading mode is {kind_lo} at both our M_u+ ({lo:.4g}) and theirs "
                         f"({hi:.4g}) in the {base!r} system: no threshold between them")
    while abs(hi - lo) > tol:
        mid = 0.5 * (lo + hi)
        if _leading(d, mid, mp, ip, s)["type"] == kind_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class MuLaw:
    """A straight-line fit of our M_u+ against one insect field over solved orbits (:func:`mu_law`).

    Attributes
    ----------
    field : str
        The :class:`~flapping.model.morphology.Insect` field (SI, or a chord fraction).
    values, mu : ndarray
        The field's values and our M_u+ on the orbits fitted (sorted by value).
    slope, intercept : float
        M_u+ = intercept + slope * value.
    max_residual : float
        Largest deviation of a fitted point from the line (the line's evidence).
    """

    field: str
    values: np.ndarray
    mu: np.ndarray
    slope: float
    intercept: float
    max_residual: float

    def value_for(self, mu: float) -> float:
        """The field's value at which the line reaches ``mu`` (an extrapolation if outside)."""
        return (_mu("mu", mu) - self.intercept) / self.slope


def _check_physics(physics: Any) -> None:
    """A table of :func:`physics_table` (its columns), or a ValueError (not a KeyError later)."""
    import pandas

    needed = ("changes", "Mu", "message")
    if not isinstance(physics, pandas.DataFrame) or not set(needed) <= set(physics.columns):
        got = (list(physics.columns) if isinstance(physics, pandas.DataFrame)
               else type(physics).__name__)
        raise ValueError(f"`physics` must be a table of physics_table() (columns {needed}); "
                         f"got {got}")


def mu_law(physics: pandas.DataFrame, comparison: CFDComparison, field: str) -> MuLaw:
    """Fit our M_u+ against one field over the cases of :func:`physics_table` that vary only it.

    A case is used if it found its orbit and every other field it changes keeps the compared
    insect's value (so "hinge at the CG", which also sets the already-zero offset, counts for the
    hinge height); the case "as compared" enters at the insect's own value.

    Parameters
    ----------
    physics : pandas.DataFrame
        From :func:`physics_table`.
    comparison : CFDComparison
        The comparison the table was made from.
    field : str
        An insect field, e.g. ``"hinge_height"`` or ``"center_of_pressure"``.

    Returns
    -------
    MuLaw

    Raises
    ------
    ValueError
        If fewer than three cases vary the field (a line through two points is no evidence).
    """
    _validation.instance("comparison", comparison, CFDComparison)
    _check_physics(physics)
    insect = comparison.insect
    if not isinstance(field, str) or not hasattr(insect, field):
        raise ValueError(f"field must be an Insect field; got {field!r}")
    xs, ys = [], []
    for _, row in physics.iterrows():
        if row.get("message") or not math.isfinite(row.get("Mu", math.nan)):
            continue
        changes = dict(row["changes"])
        others = {k: v for k, v in changes.items() if k != field}
        if any(getattr(insect, k) != v for k, v in others.items()):
            continue
        xs.append(float(changes.get(field, getattr(insect, field))))
        ys.append(float(row["Mu"]))
    if len(set(xs)) < 3:
        raise ValueError(f"field {field!r} is varied by {len(set(xs))} distinct case(s) of the "
                         "physics table; a law needs at least 3")
    order = np.argsort(xs)
    x, y = np.asarray(xs)[order], np.asarray(ys)[order]
    slope, intercept = np.polyfit(x, y, 1)
    resid = float(np.max(np.abs(y - (intercept + slope * x))))
    return MuLaw(field, x, y, float(slope), float(intercept), resid)


# =========================================================================== angle of attack
#: The mean angles of attack [deg] :func:`angle_of_attack_table` holds by default.
ANGLES_DEG: tuple[float, ...] = (15.0, 20.0, 25.0, 27.5, 30.0, 35.0, 40.0, 45.0, 50.0)


def _angles_rad(alphas_deg: ArrayLike) -> np.ndarray:
    """Validated angles [deg] in (0, 90), converted to radians (edge of the API: degrees)."""
    values = np.atleast_1d(np.asarray(alphas_deg, dtype=object)).ravel()
    if values.size == 0:
        raise ValueError("`alphas_deg` must hold at least one angle in (0, 90) deg; got none")
    return np.radians([_validation.real("alphas_deg", a, low=0.0, high=90.0, low_open=True,
                                        high_open=True, unit="deg") for a in values])


def _angle_row(comp: CFDComparison) -> dict[str, Any]:
    """One row of :func:`angle_of_attack_table` from a comparison."""
    ours = comp.table["ours"]
    lead = complex(comp.our_eigenvalues[0])
    return {"alpha_m_deg": math.degrees(comp.orbit.alpha_m),
            "stroke_amplitude_deg": comp.trim["our_stroke_amplitude_deg"],
            **{n: float(ours[n]) for n in ("Xu", "Zw", "Mu", "Mq")},
            "averaged_eigenvalue": lead, "averaged_type": comp.our_mode["type"],
            "leading_multiplier": complex(comp.our_multipliers[0]),
            "floquet_type": comp.our_floquet_mode["type"]}


def angle_of_attack_table(study: str | CFDStudy = "sun2005",
                          alphas_deg: ArrayLike = ANGLES_DEG,
                          **hover_options: Any) -> pandas.DataFrame:
    """Our model on a CFD study's insect with the mean angle of attack held, the amplitude trimmed.

    :func:`compare` keeps the paper's eq. (40) angle of attack alpha_m; here alpha_m is held at
    each given value and the hover solve trims the stroke amplitude (and the mean stroke angle
    when the hinge is off the CG) to carry the weight.

    Parameters
    ----------
    study : str or CFDStudy
        A key of :data:`STUDIES` or a study.
    alphas_deg : array_like of float
        Mean (mid-stroke) angles of attack alpha_m [deg], each in (0, 90).
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit` (not ``alpha_m``).

    Returns
    -------
    pandas.DataFrame
        One row per angle, in the order given: ``alpha_m_deg``, ``stroke_amplitude_deg`` (peak
        to peak, trimmed), our non-dimensional ``Xu``, ``Zw``, ``Mu``, ``Mq`` (X_u+, Z_w+,
        M_u+, M_q+), ``averaged_eigenvalue`` (the leading eigenvalue of our averaged system
        [1/s], complex), ``averaged_type``, ``leading_multiplier`` (our Floquet multiplier of
        largest modulus, complex) and ``floquet_type`` ("real" or "oscillatory").

    Raises
    ------
    ValueError
        For an angle outside (0, 90) deg, an unknown study, or ``alpha_m`` in the options.
    ConvergenceError
        If a hover orbit cannot be found.
    """
    import pandas

    _no_alpha_option(hover_options)
    s = study if isinstance(study, CFDStudy) else _lookup(study)
    rows = [_angle_row(compare(s, alpha_m=float(a), **hover_options))
            for a in _angles_rad(alphas_deg)]
    return pandas.DataFrame(rows)


def _no_alpha_option(hover_options: Mapping[str, Any]) -> None:
    if "alpha_m" in hover_options:
        raise ValueError("`alpha_m` is what these functions vary: give the angles as "
                         "`alphas_deg` (or `bracket_deg`), not as a hover option")


@dataclass(frozen=True)
class TypeChangeAngle:
    """The mean angle of attack at which our mode type changes, by two routes.

    Attributes
    ----------
    mu_zero : float
        alpha_m [rad] at which our averaged M_u+ crosses zero (Brent's method): with our other
        terms the averaged system's leading mode turns oscillatory there (within the small
        positive threshold of :func:`mode_type_threshold`).
    floquet : float
        alpha_m [rad] at which our leading Floquet multiplier turns complex (bisection on the
        type, to ``xtol``).
    xtol : float
        The width [rad] of the Floquet bracket at the end.
    averaged_bracket, floquet_bracket : tuple of float
        The alpha_m [rad] brackets the two searches started from (neighbouring angles of the
        table).
    nfev : int
        Number of hover solves (comparisons) made by the two searches.
    """

    mu_zero: float
    floquet: float
    xtol: float
    averaged_bracket: tuple[float, float]
    floquet_bracket: tuple[float, float]
    nfev: int

    @property
    def mu_zero_deg(self) -> float:
        """:attr:`mu_zero` in degrees."""
        return math.degrees(self.mu_zero)

    @property
    def floquet_deg(self) -> float:
        """:attr:`floquet` in degrees."""
        return math.degrees(self.floquet)

    @property
    def gap_deg(self) -> float:
        """floquet - mu_zero [deg] (what first-order averaging misses, plus the searches'
        tolerances)."""
        return self.floquet_deg - self.mu_zero_deg


def _bracket_from(table: pandas.DataFrame, column: str) -> tuple[float, float]:
    """The first neighbouring angles [rad] of a table (sorted by angle) between which
    ``column`` changes: the sign of ``"Mu"``, or the value of ``"floquet_type"``."""
    t = table.sort_values("alpha_m_deg")
    a, v = t["alpha_m_deg"].to_numpy(), t[column].to_numpy()
    if column == "Mu":
        v = np.sign(v.astype(float))
    change = np.flatnonzero(v[:-1] != v[1:])
    if change.size == 0:
        raise ValueError(f"our {column} does not change over the table's angles ({a.min():.4g} "
                         f"to {a.max():.4g} deg): no bracket for the type change")
    k = int(change[0])
    return math.radians(a[k]), math.radians(a[k + 1])


def type_change_angle(study: str | CFDStudy = "sun2005",
                      table: pandas.DataFrame | None = None, xtol_deg: float = 0.1,
                      **hover_options: Any) -> TypeChangeAngle:
    """The alpha_m at which our mode type changes: by averaging (M_u+ = 0) and by Floquet.

    Route 1: Brent's method on our averaged M_u+ as a function of alpha_m (:func:`compare` at
    each angle), the sign change bracketed by ``table``. Route 2: bisection on the type of our
    leading Floquet multiplier (one type at each end of its bracket, checked), from the
    neighbouring angles of ``table`` where ``floquet_type`` changes, to ``xtol_deg``. The two
    need not coincide: averaging is a first-order approximation of the periodic system, and
    the averaged type changes just above M_u+ = 0, not at it (:func:`mode_type_threshold`).

    Parameters
    ----------
    study : str or CFDStudy
        A key of :data:`STUDIES` or a study.
    table : pandas.DataFrame, optional
        From :func:`angle_of_attack_table` of the same study; default that of
        :data:`ANGLES_DEG`.
    xtol_deg : float
        Width of the final brackets [deg], in (0, 5].
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit` (not ``alpha_m``).

    Returns
    -------
    TypeChangeAngle

    Raises
    ------
    ValueError
        If M_u+ keeps its sign or the Floquet type does not change over the table, or for a
        bad ``xtol_deg``.
    """
    _no_alpha_option(hover_options)
    tol = math.radians(_validation.real("xtol_deg", xtol_deg, low=0.0, high=5.0,
                                        low_open=True, unit="deg"))
    s = study if isinstance(study, CFDStudy) else _lookup(study)
    if table is None:
        table = angle_of_attack_table(s, **hover_options)
    avg_bracket = _bracket_from(table, "Mu")
    flo_bracket = _bracket_from(table, "floquet_type")
    calls = [0]

    def at(alpha: float) -> CFDComparison:
        calls[0] += 1
        return compare(s, alpha_m=alpha, **hover_options)

    def mu(alpha: float) -> float:
        return float(at(alpha).table.loc["Mu", "ours"])

    mu_zero = float(brentq(mu, *avg_bracket, xtol=0.01 * tol))
    floquet = _bisect_type(at, *flo_bracket, tol)
    return TypeChangeAngle(mu_zero, floquet, tol, avg_bracket, flo_bracket, calls[0])


def _bisect_type(at: Any, lo: float, hi: float, tol: float) -> float:
    """Bisection on the Floquet type between ``lo`` (one type) and ``hi`` (the other)."""
    kind_lo = at(lo).our_floquet_mode["type"]
    if at(hi).our_floquet_mode["type"] == kind_lo:
        raise ValueError(f"our leading Floquet multiplier is {kind_lo} at both ends of the "
                         f"bracket ({math.degrees(lo):.4g}, {math.degrees(hi):.4g}) deg")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        if at(mid).our_floquet_mode["type"] == kind_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)

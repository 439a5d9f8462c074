"""Morphology of a flapping insect: geometry, mass properties and model constants.

All quantities are SI (metres, kilograms, seconds, radians). Degrees and millimetres appear only in
the :func:`hawkmoth` preset's documentation and in printed tables.

The wing planform is Ellington's beta distribution of chord (Ellington 1984, "The aerodynamics of
hovering insect flight. II. Morphological parameters"), fixed by the non-dimensional radii of the
first and second moments of area, ``r1`` and ``r2``. Span integrals of powers of radius and chord,

    I_mn = 2 * int_0^R r**m c(r)**n dr          (both wings; paper, after eq. 29)

have closed forms in beta functions (:meth:`Insect.span_integral`).
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Collection
from dataclasses import dataclass, field, fields
from typing import Any, Literal

import numpy as np
from scipy import special

import flapping._validation as _validation
from flapping.errors import PlausibilityWarning
from flapping.model.kinematics import check_amplitude

__all__ = ["Insect", "hawkmoth", "beta_shape_parameters", "lev_lift_slope", "MAGNITUDE_LIMIT",
           "PLAUSIBLE_RANGES", "PHYSICAL_RANGES", "ASPECT_RATIO_RANGE", "r2_range",
           "support_amplitude", "implausible_fields", "explain_blowup"]

AspectRatioConvention = Literal["pair", "single"]

#: The accepted aspect-ratio conventions of eq. (4) (see :class:`Insect`).
ASPECT_RATIO_CONVENTIONS: tuple[AspectRatioConvention, ...] = ("pair", "single")

#: Largest magnitude [SI] of any numeric :class:`Insect` field, and the inverse of the smallest
#: magnitude of a positive one: beyond it the model's products leave float64's range. Every
#: field's hard range (:data:`PHYSICAL_RANGES`) lies far inside [1/LIMIT, LIMIT].
MAGNITUDE_LIMIT = 1e30

#: Magnitudes of real insects and flapping vehicles, generously bounded: (low, high, unit). A
#: field outside its range is accepted (the model is still defined) with a
#: :class:`~flapping.errors.PlausibilityWarning`. Lower ends: fairyflies (Mymaridae, ~0.2 mm
#: wings, ~1e-10 kg); upper ends: large flapping MAVs and birds (~1 m half span, 2 kg, 1 Hz).
#: Frequencies reach ~1000 Hz in midges (Forcipomyia); air from Mars' surface (~0.02 kg/m^3) to
#: dense cold air; gravity from the Moon (1.62 m/s^2) to a few g; a0 around thin-aerofoil 2 pi.
#: ``"aspect_ratio_1"`` is the derived one-wing aspect ratio R^2/S (presets 2.8-3.5, damselflies
#: ~10). Fields whose hard range (:data:`_FIELDS`) is already physical (r1, r2, pitch_axis,
#: center_of_pressure) are not listed.
PLAUSIBLE_RANGES: dict[str, tuple[float, float, str]] = {
    "semi_span": (1e-4, 1.0, "m"),
    "wing_area": (1e-9, 1.0, "m^2"),
    "aspect_ratio_1": (0.5, 20.0, "(R^2/S of one wing)"),
    "frequency": (0.5, 2000.0, "Hz"),
    "stroke_amplitude": (math.radians(5.0), math.pi / 2, "rad"),
    "mass": (1e-10, 2.0, "kg"),
    "pitch_inertia": (1e-20, 1.0, "kg m^2"),
    "air_density": (0.01, 5.0, "kg/m^3"),
    "gravity": (1.0, 30.0, "m/s^2"),
    "a0": (1.0, 10.0, "1/rad"),
    "mu1": (0.0, 10.0, ""),
    "mu2": (0.0, 10.0, ""),
    "hinge_offset": (-1.0, 1.0, "m"),
    "hinge_height": (-1.0, 1.0, "m"),
    "stroke_mean": (-math.pi / 3, math.pi / 3, "rad"),
    "wing_mass_ratio": (0.0, 0.25, "(2 wing_mass / mass)"),
}

#: Hard ranges of the numeric :class:`Insect` fields [SI]: (low, high, unit). A value outside
#: is refused at construction (ValueError naming the field and this range); inside it but outside
#: :data:`PLAUSIBLE_RANGES` it is accepted with a warning. Each range is the literature's span
#: from the smallest insect to the largest flapping vehicle, widened about tenfold at each end
#: (so that no real animal or MAV, measured in any unit-correct way, is refused), and narrow
#: enough that a unit slip of 1000 (mm for m, g for kg) or an absurd magnitude (a 1e12 Hz wing
#: beat that "hovers" at 4406 m/s, a 1e-12 kg moth whose loads overflow) is an error:
#:
#: - ``semi_span``: fairyflies (Mymaridae) have ~0.15 mm wings, Festo's SmartBird a 1 m half
#:   span: [1e-5, 3] m (10 um to 3 m).
#: - ``wing_area`` (one wing): ~4e-9 m^2 (a fairyfly's fringed wing) to ~0.3 m^2 (SmartBird):
#:   [1e-11, 5] m^2. The chord is bounded through R^2/S, see :data:`ASPECT_RATIO_RANGE`.
#: - ``frequency``: 1-2 Hz (large ornithopters, birds) to ~1000 Hz (Forcipomyia midges); the
#:   book's species atlas follows a bumblebee to 1500 Hz on purpose: [0.1, 1e4] Hz.
#: - ``stroke_amplitude``: (0, 90 deg] by eq. (39) (:func:`~.kinematics.check_amplitude`), and
#:   at least 1 deg: insects beat 30-90 deg, the atlas's fast family reaches 2.6 deg; below
#:   1 deg the nominal amplitude (which fixes alpha_m by eq. 40) is no wing beat.
#: - ``mass``: ~1e-10 kg (fairyflies; a 1 mg thrips is 1e-6 kg) to ~0.1-0.5 kg flapping MAVs
#:   (and 2 kg birds): [1e-11, 20] kg.
#: - ``pitch_inertia``: m L^2 / 12 of a fairyfly (~2e-19) to a 20 kg, 1 m body (~2 kg m^2):
#:   [1e-24, 10] kg m^2.
#: - ``air_density``: Mars' surface (~0.015 kg/m^3) to Titan (5.4) and Venus (65): [1e-3, 100].
#: - ``gravity``: > 0 (no weight, no hover: alpha_m of eq. 40 is zero); Ceres (0.28) to a few g:
#:   [0.1, 100] m/s^2.
#: - ``a0``: 2 pi for a thin aerofoil, 3-6 per rad measured on insect wings at low Reynolds
#:   number: [0.1, 30] 1/rad.
#: - ``mu1``, ``mu2``: Berman & Wang's fitted rotational damping coefficients (0.2); the fit has
#:   no physical upper end, so the bound only keeps the loads in float64 range: [0, 1e6]
#:   (issue 7's reproducers of a non-finite result use 7.5e4 and 1e6).
#: - ``hinge_offset``, ``hinge_height``: millimetres in insects, centimetres in MAVs: [-5, 5] m.
#: - ``wing_mass`` (one wing): [0, 10] kg, and below half of ``mass`` (the wings are part of
#:   the insect).
#: - ``r1``, ``r2``: Ellington's beta distribution (see :func:`beta_shape_parameters`): r1 in
#:   (0, 1), and r2 in the open interval from r1 to the largest r2 whose squared chord is
#:   integrable (insects: r1 = 0.4-0.6, r2 = 0.45-0.65).
PHYSICAL_RANGES: dict[str, tuple[float, float, str]] = {
    "semi_span": (1e-5, 3.0, "m"),
    "wing_area": (1e-11, 5.0, "m^2"),
    "frequency": (0.1, 1e4, "Hz"),
    "stroke_amplitude": (math.radians(1.0), math.pi / 2, "rad"),
    "mass": (1e-11, 20.0, "kg"),
    "pitch_inertia": (1e-24, 10.0, "kg m^2"),
    "air_density": (1e-3, 100.0, "kg/m^3"),
    "gravity": (0.1, 100.0, "m/s^2"),
    "a0": (0.1, 30.0, "1/rad"),
    "mu1": (0.0, 1e6, ""),
    "mu2": (0.0, 1e6, ""),
    "hinge_offset": (-5.0, 5.0, "m"),
    "hinge_height": (-5.0, 5.0, "m"),
    "wing_mass": (0.0, 10.0, "kg"),
    "roll_inertia": (1e-24, 10.0, "kg m^2"),
    "yaw_inertia": (1e-24, 10.0, "kg m^2"),
    "roll_yaw_product": (-10.0, 10.0, "kg m^2"),
}

#: Hard range of one wing's aspect ratio R^2/S = R/c_bar (the mean chord over the wing length):
#: insects 2.5-5 (damselflies ~10), the model's needle and sail tests 27 and 0.27; a chord 20
#: times the wing length or a 200th of it is no wing (the blade-element strip theory of eq. 29
#: needs the chord small beside R; this only refuses what no planform has).
ASPECT_RATIO_RANGE: tuple[float, float] = (0.05, 200.0)

#: Numeric fields of :class:`Insect`: (accepted range, unit). Ranges: "physical" (the closed
#: range of :data:`PHYSICAL_RANGES`), "fraction" (of the chord, [0, 1]), "amplitude"
#: (:func:`~.kinematics.check_amplitude` and at least :data:`PHYSICAL_RANGES`'s 1 deg),
#: "stroke_mean" (real in (-pi/2, pi/2)), "r1" (in (0, 1)), "r2" (in (0, 1), then in the range
#: r1 allows, :func:`beta_shape_parameters`), "radius" ((0, 1] or None), "optional" (the
#: physical range or None).
_FIELDS: dict[str, tuple[str, str]] = {
    "semi_span": ("physical", "m"), "wing_area": ("physical", "m^2"),
    "frequency": ("physical", "Hz"), "mass": ("physical", "kg"),
    "pitch_inertia": ("physical", "kg m^2"), "air_density": ("physical", "kg/m^3"),
    "a0": ("physical", "1/rad"), "gravity": ("physical", "m/s^2"),
    "mu1": ("physical", ""), "mu2": ("physical", ""),
    "pitch_axis": ("fraction", ""), "center_of_pressure": ("fraction", ""),
    "hinge_offset": ("physical", "m"), "stroke_amplitude": ("amplitude", "rad"),
    "hinge_height": ("physical", "m"), "stroke_mean": ("stroke_mean", "rad"),
    "r1": ("r1", ""), "r2": ("r2", ""),
    "wing_mass": ("physical", "kg"),
    "wing_mass_r1": ("radius", ""), "wing_mass_r2": ("radius", ""),
    "roll_inertia": ("optional", "kg m^2"), "yaw_inertia": ("optional", "kg m^2"),
    "roll_yaw_product": ("optional", "kg m^2"),
}


def r2_range(r1: float) -> tuple[float, float]:
    """The open interval of r2 that Ellington's beta chord distribution admits with this r1.

    r2 > r1 (a positive variance of the area about its centroid) and the beta shape parameters
    p, q > 1/2 (the squared chord, which the blade-element loads integrate, is integrable):
    r2^2 < r1^2 + r1 (1 - r1) / (1 + 1 / (2 min(r1, 1 - r1))).

    Parameters
    ----------
    r1 : float
        Non-dimensional radius of the first moment of wing area, in (0, 1).

    Returns
    -------
    (float, float)
        The bounds (low, high) of r2, both excluded.

    Raises
    ------
    ValueError
        If ``r1`` is not a real number in (0, 1).
    """
    r1 = _validation.real("r1", r1, low=0.0, high=1.0, low_open=True, high_open=True)
    return r1, _r2_high(r1)


def _r2_high(r1: float) -> float:
    """The upper end of :func:`r2_range` (p or q = 1/2 there, k = 1 / (2 min(r1, 1 - r1)))."""
    k = 1.0 / (2.0 * min(r1, 1.0 - r1))
    return math.sqrt(r1**2 + r1 * (1.0 - r1) / (k + 1.0))


def beta_shape_parameters(r1: float, r2: float) -> tuple[float, float]:
    """Shape parameters (p, q) of the beta chord distribution with moments r1, r2.

    Ellington's method of moments (paper, appendix A): the non-dimensional chord
    c(r)/c_bar = r**(p-1) (1-r)**(q-1) / B(p, q) has first moment r1 and second moment r2**2.

    Parameters
    ----------
    r1 : float
        Non-dimensional radius of the first moment of wing area, in (0, 1).
    r2 : float
        Non-dimensional radius of the second moment of wing area, in :func:`r2_range` (r1's):
        above r1, and close enough to it that the squared chord is integrable (p, q > 1/2).

    Returns
    -------
    p, q : float
        Positive shape parameters of the beta distribution.

    Raises
    ------
    ValueError
        If r1 or r2 is outside the range for which a beta distribution exists (the message names
        the argument and the range).
    """
    r1 = _validation.real("r1", r1, low=0.0, high=1.0, low_open=True, high_open=True)
    # r1 < r2: positive variance; r2 below r2_range's end: p, q > 1/2 (an integrable c^2).
    r2 = _validation.real("r2", r2, low=r1, high=_r2_high(r1), low_open=True, high_open=True,
                          unit=f"(Ellington's beta distribution: r1 < r2 < {_r2_high(r1):.6g} "
                               f"with r1 = {r1:.6g})")
    variance = r2**2 - r1**2
    k = r1 * (1.0 - r1) / variance - 1.0
    p, q = r1 * k, (1.0 - r1) * k
    if min(p, q) <= 0.5:
        # The blade-element loads integrate c(r)^2 over the span (I_02, I_12, I_22): they diverge
        # at the root for p <= 1/2 and at the tip for q <= 1/2.
        raise ValueError(
            f"`r1` = {r1:.6g} and `r2` = {r2:.6g} give a chord distribution whose square is not "
            f"integrable (beta shape p = {p:.4g}, q = {q:.4g}; both must exceed 1/2): r2 must lie "
            "closer to r1")
    return p, q


def lev_lift_slope(aspect_ratio: float, a0: float = 2.0 * math.pi) -> float:
    """Coefficient A of the leading-edge-vortex lift law C_L = A sin(2 alpha), eq. (4).

    A = pi AR / (2 (1 + sqrt(1 + (pi AR / a0)**2))), the extended lifting-line fit quoted by
    Taha and Hajj.

    Parameters
    ----------
    aspect_ratio : float
        Aspect ratio AR > 0.
    a0 : float
        Two-dimensional lift-curve slope [1/rad], > 0. Default 2 pi.

    Returns
    -------
    float
        A (dimensionless), in (0, a0/2).

    Raises
    ------
    ValueError
        If aspect_ratio or a0 is not a positive real number.
    """
    aspect_ratio = _validation.positive("aspect_ratio", aspect_ratio)
    a0 = _validation.positive("a0", a0, unit="1/rad")
    return _lift_slope(aspect_ratio, a0)


def _lift_slope(aspect_ratio: float, a0: float) -> float:
    """:func:`lev_lift_slope` of trusted floats (an :class:`Insect`'s own fields)."""
    x = math.pi * aspect_ratio
    return x / (2.0 * (1.0 + math.sqrt(1.0 + (x / a0) ** 2)))


@dataclass(frozen=True)
class Insect:
    """An insect (or flapping MAV) in hover: wing geometry, body, and aerodynamic constants.

    Parameters
    ----------
    name : str
        Label used in tables and plots.
    semi_span : float
        Wing length R from the wing hinge to the tip [m].
    wing_area : float
        Area S of one wing [m^2].
    r1, r2 : float
        Non-dimensional radii of the first and second moments of wing area (Ellington).
    frequency : float
        Flapping frequency f [Hz].
    stroke_amplitude : float
        Flapping amplitude Phi [rad] of phi(t) = Phi cos(2 pi f t), in (0, pi/2].
    mass : float
        Mass m of the insect [kg] (body and both wings: the weight is m g).
    pitch_inertia : float
        Moment of inertia I_y of the body (without the wings) about the pitch axis through its
        centre of gravity [kg m^2].
    air_density : float
        rho [kg/m^3]. Not given in the paper; 1.225 (sea-level standard air).
    gravity : float
        g [m/s^2], > 0 (no weight, no hover). Not given in the paper; 9.81.
    a0 : float
        Two-dimensional lift-curve slope in eq. (4) [1/rad]; the paper uses 2 pi.
    aspect_ratio_convention : {"pair", "single"}
        Which aspect ratio enters eq. (4), which the paper does not state: ``"pair"`` is
        Ellington's AR = (2R)^2 / (2S) = 2 R^2 / S of the wing pair, ``"single"`` is R^2 / S of
        one wing.
    pitch_axis : float
        x0_hat, position of the wing's pitch axis behind the leading edge over the chord, in
        [0, 1]; enters the rotational circulation (eq. 5) through (3/4 - x0_hat). Default 0.
    center_of_pressure : float
        x_hat, chordwise distance from the pitch (hinge) line back to the centre of pressure over
        the chord, in [0, 1]; eqs. (21)-(23). Default 1/4 ("c/4" in the text).
    hinge_offset : float
        x_h, distance of the wing hinge ahead of the centre of gravity [m]. Default 0 (the CG
        under the hinge line).
    mu1, mu2 : float
        Berman and Wang's rotational damping coefficients (dimensionless), >= 0. Default 0.2.
    hinge_height : float
        h_w, height of the wing hinge above the centre of gravity [m] (the stroke plane's height;
        z is down in body axes, so the hinge sits at z = -h_w). Default 0 (the paper's model).
    stroke_mean : float
        phi_bar, mean stroke angle [rad] of phi(t) = phi_bar + Phi cos(2 pi f t), positive
        forward, in (-pi/2, pi/2). Default 0 (the paper's eq. 39).
    wing_mass : float
        m_w, mass of one wing [kg], >= 0, included in ``mass`` (the body alone weighs
        ``mass - 2 wing_mass``), below half of it. Default 0: massless wings, the paper's model.
        With wings of mass the equations of motion carry their inertial loads
        (:mod:`flapping.model.inertia`).
    wing_mass_r1, wing_mass_r2 : float or None
        Radii of the first moment and of gyration of one wing's mass about the hinge, over R, in
        (0, 1] with wing_mass_r1 <= wing_mass_r2. Default None: those of the wing area,
        :attr:`r1` and :attr:`r2` (a membrane of uniform areal density).
    roll_inertia, yaw_inertia, roll_yaw_product : float or None
        I_x, I_z and I_xz of the body (without the wings) about its centre of gravity in body
        axes [kg m^2]: the inertia tensor [[I_x, 0, -I_xz], [0, I_y, 0], [-I_xz, 0, I_z]] of the
        six-degree-of-freedom model (:mod:`flapping.model.sixdof`; the planar model does not use
        them). Default None: not given (a six-degree-of-freedom solve then refuses the insect).
        The tensor must be positive definite.

    Raises
    ------
    ValueError
        If a field is outside its range; the message names the field and the range. Numbers of
        any real type (``int``, ``np.float32``, ``np.int64``, ...) are stored as Python floats;
        bools and strings are refused. A value outside its field's physical range
        (:data:`PHYSICAL_RANGES`: e.g. a wing beat of 1e12 Hz, a 1e-12 kg body, a 10 m wing),
        an r2 outside :func:`r2_range` of r1, and a wing aspect ratio R^2/S outside
        :data:`ASPECT_RATIO_RANGE` are refused, as are integers too large for float64.

    Warns
    -----
    PlausibilityWarning
        For each value inside its physical range but outside :data:`PLAUSIBLE_RANGES` (e.g. a
        wing beat of 5 kHz), naming the field, its value and the range.
    """

    name: str
    semi_span: float
    wing_area: float
    r1: float
    r2: float
    frequency: float
    stroke_amplitude: float
    mass: float
    pitch_inertia: float
    air_density: float = 1.225
    gravity: float = 9.81
    a0: float = 2.0 * math.pi
    aspect_ratio_convention: AspectRatioConvention = "pair"
    pitch_axis: float = 0.0
    center_of_pressure: float = 0.25
    hinge_offset: float = 0.0
    mu1: float = 0.2
    mu2: float = 0.2
    hinge_height: float = 0.0
    stroke_mean: float = 0.0
    wing_mass: float = 0.0
    wing_mass_r1: float | None = None
    wing_mass_r2: float | None = None
    roll_inertia: float | None = None
    yaw_inertia: float | None = None
    roll_yaw_product: float | None = None
    _shape: tuple[float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self._check(None, stacklevel=5)

    def _check(self, changed: Collection[str] | None, stacklevel: int) -> None:
        """Validate and convert every field (``changed`` None) or the ``changed`` ones, in the
        same order either way (so that the first bad field named is the same); warn once per
        implausible value of the result (:data:`PLAUSIBLE_RANGES`)."""
        if changed is None or "name" in changed:
            _validation.instance("name", self.name, str)
        for name, (kind, unit) in _FIELDS.items():
            if changed is None or name in changed:
                object.__setattr__(self, name, _check_field(name, getattr(self, name), kind,
                                                            unit))
        if changed is None or "aspect_ratio_convention" in changed:
            _validation.choice("aspect_ratio_convention", self.aspect_ratio_convention,
                               ASPECT_RATIO_CONVENTIONS)
        if changed is None or "r1" in changed or "r2" in changed:
            object.__setattr__(self, "_shape", beta_shape_parameters(self.r1, self.r2))
        if changed is None or not _WING_MASS_FIELDS.isdisjoint(changed) or "mass" in changed:
            _check_wing_mass(self)
        if changed is None or "semi_span" in changed or "wing_area" in changed:
            _check_aspect_ratio(self)
        if changed is None or not _INERTIA_FIELDS.isdisjoint(changed):
            _check_inertia_tensor(self, lateral=changed is not None
                                  and not _LATERAL_INERTIA_FIELDS.isdisjoint(changed),
                                  stacklevel=stacklevel + 1)
        for message in _implausible(self):
            warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel)

    def implausible_fields(self) -> dict[str, str]:
        """The fields likely to blame if this insect's hover solve blows up, each with why.

        Every field is in its hard range (:data:`PHYSICAL_RANGES`), but a combination of
        plausible magnitudes can still be no insect: a hawkmoth's wings on a 1 mg body lift a
        million times its weight, and the integration of eq. (2) overflows. Named here: each
        field outside :data:`PLAUSIBLE_RANGES` (a derived ratio names the fields it is made
        of), a body radius of gyration sqrt(I_y / m_body) outside [0.01, 5] R, a hinge more than
        3 R from the centre of gravity, and, if nothing else is named, a weight that the wings at
        rest would carry with a stroke below 2 deg or not even at 90 deg (eq. 40 at
        alpha_m = 45 deg, its best angle: :func:`support_amplitude`), blamed on ``mass``.

        Returns
        -------
        dict of str to str
            Field name -> a sentence with its value and the range it leaves (empty if the
            insect looks like one). The hover layer appends these to a blow-up's message
            (:func:`explain_blowup`).
        """
        return implausible_fields(self)

    # ----------------------------------------------------------------- geometry
    @property
    def mean_chord(self) -> float:
        """Mean chord c_bar = S / R [m] (consistent with the chord distribution's area)."""
        return self.wing_area / self.semi_span

    @property
    def beta_p(self) -> float:
        """Shape parameter p of the beta chord distribution (exponent p - 1 at the root)."""
        return self._shape[0]

    @property
    def beta_q(self) -> float:
        """Shape parameter q of the beta chord distribution (exponent q - 1 at the tip)."""
        return self._shape[1]

    @property
    def aspect_ratio(self) -> float:
        """Aspect ratio entering eq. (4), by :attr:`aspect_ratio_convention`."""
        single = self.semi_span**2 / self.wing_area
        return 2.0 * single if self.aspect_ratio_convention == "pair" else single

    @property
    def lift_slope(self) -> float:
        """A of C_L = A sin(2 alpha), eq. (4)."""
        return _lift_slope(self.aspect_ratio, self.a0)  # both fields checked on construction

    @property
    def period(self) -> float:
        """Flapping period T = 1/f [s]."""
        return 1.0 / self.frequency

    @property
    def wing_mass_radii(self) -> tuple[float, float]:
        """(wing_mass_r1, wing_mass_r2), the area's (r1, r2) where not given."""
        r1 = self.r1 if self.wing_mass_r1 is None else self.wing_mass_r1
        r2 = self.r2 if self.wing_mass_r2 is None else self.wing_mass_r2
        return r1, r2

    @property
    def wing_mass_moments(self) -> tuple[float, float]:
        """(A1, A2): first and second spanwise mass moments of the wing pair about the hinge,
        2 m_w r1 R [kg m] and 2 m_w (r2 R)^2 [kg m^2]."""
        r1, r2 = self.wing_mass_radii
        return (2.0 * self.wing_mass * r1 * self.semi_span,
                2.0 * self.wing_mass * (r2 * self.semi_span) ** 2)

    @property
    def weight(self) -> float:
        """Weight m g [N] (body and wings)."""
        return self.mass * self.gravity

    def chord(self, r: np.ndarray | float) -> np.ndarray:
        """Chord c(r) [m] at radius r [m] from the hinge, Ellington's beta distribution.

        c(r) = c_bar / B(p, q) * (r/R)**(p-1) * (1 - r/R)**(q-1). Singular (integrably) at the root
        when p < 1; returned as zero outside the open interval (0, R), including at the root
        and tip themselves where the true value may be infinite.

        Raises
        ------
        ValueError
            If ``r`` is not a finite real number or array of them.
        """
        r_hat = _validation.array("r", r) / self.semi_span
        p, q = self._shape
        inside = (r_hat > 0.0) & (r_hat < 1.0)
        safe = np.where(inside, r_hat, 0.5)
        value = self.mean_chord / special.beta(p, q) * safe ** (p - 1.0) * (1.0 - safe) ** (q - 1.0)
        return np.where(inside, value, 0.0)

    def span_integral(self, m: float, n: float) -> float:
        """I_mn = 2 int_0^R r**m c(r)**n dr for both wings, in closed form [m^(m+n+1)].

        I_mn = 2 R^(m+1) (c_bar/B(p,q))^n B(m + n(p-1) + 1, n(q-1) + 1).

        Raises
        ------
        ValueError
            If the integral diverges for this planform (m + n(p-1) + 1 <= 0 or n(q-1) + 1 <= 0).
        """
        # Integer orders (the model's own) are exact as floats: no validation needed.
        m = float(m) if type(m) is int else _validation.real("m", m)
        n = float(n) if type(n) is int else _validation.real("n", n)
        p, q = self._shape
        return _span_integral(self.semi_span, self.mean_chord, p, q, m, n)

    def with_(self, **changes: Any) -> Insect:
        """A copy with some fields changed (validated again).

        E.g. ``hawkmoth().with_(hinge_offset=1e-3)``.

        Only the changed fields are validated again (the others were checked when ``self`` was
        built): a sweep makes one insect per point.

        Raises
        ------
        ValueError
            If a changed field is outside its range.
        TypeError
            If a name is not a field of :class:`Insect`.

        Warns
        -----
        PlausibilityWarning
            For each value of the copy outside :data:`PLAUSIBLE_RANGES`, as the constructor.
        """
        for name in changes:
            if name not in _INIT_FIELDS:
                raise TypeError(f"Insect.with_() got an unexpected keyword argument {name!r}")
        new = object.__new__(type(self))
        new.__dict__.update(self.__dict__)
        for name, value in changes.items():
            object.__setattr__(new, name, value)
        new._check(changes, stacklevel=3)
        return new

    def as_table(self) -> list[tuple[str, str, float, str]]:
        """Rows (symbol, description, value, unit) for printing, in display units (mm, deg, g)."""
        return [
            ("R", "semi-span", self.semi_span * 1e3, "mm"),
            ("S", "area of one wing", self.wing_area * 1e6, "mm^2"),
            ("c_bar", "mean chord S/R", self.mean_chord * 1e3, "mm"),
            ("r1", "radius of 1st moment of area / R", self.r1, "-"),
            ("r2", "radius of 2nd moment of area / R", self.r2, "-"),
            ("f", "flapping frequency", self.frequency, "Hz"),
            ("Phi", "stroke amplitude", math.degrees(self.stroke_amplitude), "deg"),
            ("m", "body mass", self.mass * 1e3, "g"),
            ("I_y", "pitch moment of inertia", self.pitch_inertia * 1e10, "mg cm^2"),
            ("rho", "air density", self.air_density, "kg/m^3"),
            ("g", "gravity", self.gravity, "m/s^2"),
            ("AR", f"aspect ratio ({self.aspect_ratio_convention})", self.aspect_ratio, "-"),
            ("x0_hat", "pitch axis behind leading edge / chord", self.pitch_axis, "-"),
            ("x_hat", "centre of pressure behind pitch axis / chord", self.center_of_pressure, "-"),
            ("x_h", "hinge ahead of centre of gravity", self.hinge_offset * 1e3, "mm"),
            ("mu1", "rotational damping coefficient (frequency term)", self.mu1, "-"),
            ("mu2", "rotational damping coefficient (rate term)", self.mu2, "-"),
        ] + [row for row, value in (
            (("h_w", "hinge above centre of gravity", self.hinge_height * 1e3, "mm"),
             self.hinge_height),
            (("phi_bar", "mean stroke angle", math.degrees(self.stroke_mean), "deg"),
             self.stroke_mean),
            (("m_w", "mass of one wing", self.wing_mass * 1e6, "mg"), self.wing_mass),
            (("r1_m", "radius of 1st moment of wing mass / R", self.wing_mass_radii[0], "-"),
             self.wing_mass),
            (("r2_m", "radius of gyration of wing mass / R", self.wing_mass_radii[1], "-"),
             self.wing_mass)) if value != 0.0]  # rows only when used: tables stay as they were


def hawkmoth(**overrides: Any) -> Insect:
    """The hawkmoth *Manduca sexta* of the paper's appendix A.

    R = 51.9 mm, S = 947.8 mm^2 (one wing), r1 = 0.44, r2 = 0.525, f = 26.3 Hz, Phi = 60.5 deg,
    m = 1.648 g, I_y = 2080 mg cm^2, after Ellington (1984) and Willmott & Ellington (1997) as
    cited by the paper; the body's roll and yaw inertia (six degrees of freedom only) are
    ESTIMATES (:func:`~flapping.model.presets.lateral_inertia_estimate`, d = 10 mm). The paper
    also prints c_bar = 18.3 mm; we use c_bar = S/R = 18.26 mm so
    that the chord distribution has the stated area. The paper writes f = 26.5 Hz once, but its
    period T = 0.0380 s is 1/26.3 Hz. Choices the paper leaves open take the :class:`Insect`
    defaults and can be changed with keyword ``overrides``.

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units (e.g. ``mass=2e-3``).

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        If an override is outside its field's range (see :class:`Insect`).
    TypeError
        If an override is not a field of :class:`Insect`.
    """
    values: dict[str, Any] = dict(
        name="hawkmoth",
        semi_span=51.9e-3,
        wing_area=947.8e-6,
        r1=0.44,
        r2=0.525,
        frequency=26.3,
        stroke_amplitude=math.radians(60.5),
        mass=1.648e-3,
        pitch_inertia=2080.0 * 1e-6 * 1e-4,  # 2080 mg cm^2 = 2080 * (1e-6 kg)(1e-4 m^2)
        # ESTIMATES (presets.lateral_inertia_estimate: a prolate ellipsoid 10 mm across; only
        # six degrees of freedom use them)
        roll_inertia=1.648e-3 * 10e-3**2 / 10.0,
        yaw_inertia=2080.0 * 1e-6 * 1e-4,
        roll_yaw_product=0.0,
    )
    values.update(overrides)
    return Insect(**values)


#: The fields :meth:`Insect.with_` may change (those of the constructor).
_INIT_FIELDS = frozenset(f.name for f in fields(Insect) if f.init)


@functools.lru_cache(maxsize=1024)
def _span_integral(semi_span: float, mean_chord: float, p: float, q: float, m: float,
                   n: float) -> float:
    """:meth:`Insect.span_integral` of a planform (cached: a sweep over other fields asks the
    same planform's integrals at every point)."""
    a = m + n * (p - 1.0) + 1.0
    b = n * (q - 1.0) + 1.0
    if a <= 0.0 or b <= 0.0:
        raise ValueError(
            f"I_mn diverges for m={m!r}, n={n!r} with beta shape p={p:.4g}, q={q:.4g}: "
            "needs m + n(p-1) + 1 > 0 and n(q-1) + 1 > 0"
        )
    log_value = (
        (m + 1.0) * math.log(semi_span)
        + n * (math.log(mean_chord) - special.betaln(p, q))
        + special.betaln(a, b)
    )
    return 2.0 * math.exp(log_value)


def _implausible(insect: Insect) -> list[str]:
    """One message per value outside :data:`PLAUSIBLE_RANGES` (field, value, range)."""
    return [message for message in _implausible_each(insect) if message]


def _implausible_each(insect: Insect) -> list[str]:
    """For each entry of :data:`PLAUSIBLE_RANGES` in order, its message, or ``""`` if inside."""
    messages = []
    for name, (low, high, unit) in PLAUSIBLE_RANGES.items():
        if name == "aspect_ratio_1":
            value, what = insect.semi_span**2 / insect.wing_area, "semi_span**2 / wing_area"
        elif name == "wing_mass_ratio":
            value, what = 2.0 * insect.wing_mass / insect.mass, "2 wing_mass / mass"
        else:
            value, what = getattr(insect, name), f"`{name}`"
        messages.append(
            "" if low <= value <= high else
            f"{what} = {value:.6g} {unit} of {insect.name!r} is outside the range of insects "
            f"and flapping vehicles [{low:.6g}, {high:.6g}] {unit}; the model accepts it, but "
            "check the units (SI: m, kg, s, rad)")
    return messages


def _check_aspect_ratio(insect: Insect) -> None:
    """One wing's R^2/S (R over the mean chord) in :data:`ASPECT_RATIO_RANGE`."""
    low, high = ASPECT_RATIO_RANGE
    ratio = insect.semi_span**2 / insect.wing_area
    if not low <= ratio <= high:
        raise ValueError(
            f"`semi_span`**2 / `wing_area` (one wing's aspect ratio R / c_bar) must be in "
            f"[{low:g}, {high:g}]; got {ratio:.6g} (`semi_span` = {insect.semi_span:.6g} m, "
            f"`wing_area` = {insect.wing_area:.6g} m^2: a mean chord of "
            f"{insect.mean_chord:.6g} m); check the units (SI: m, m^2)")


#: Plausible range of the body's radius of gyration about its pitch axis over the wing length,
#: sqrt(I_y / m_body) / R: the presets lie at 0.1-0.4 (an insect body about as long as a wing).
GYRATION_RANGE: tuple[float, float] = (0.01, 5.0)
#: Largest plausible distance of the hinge from the centre of gravity, over R.
HINGE_RANGE = 3.0
#: Plausible range [rad] of the stroke amplitude the wings need to carry the weight at rest with
#: alpha_m = 45 deg (eq. 40): below 2 deg the wings lift far more than the weight (a body far too
#: light for its wings: eq. 2 is then stiff enough to overflow), above 90 deg no hover exists.
SUPPORT_AMPLITUDE_RANGE: tuple[float, float] = (math.radians(2.0), math.pi / 2)

#: Which fields a derived quantity of :data:`PLAUSIBLE_RANGES` is made of.
_DERIVED_FIELDS = {"aspect_ratio_1": ("semi_span", "wing_area"),
                   "wing_mass_ratio": ("wing_mass", "mass")}


def support_amplitude(insect: Insect) -> float:
    """The stroke amplitude [rad] that carries the weight of a body at rest at alpha_m = 45 deg.

    Eq. (40) solved for Phi: m g = 2 pi^2 f^2 Phi^2 (rho A I_21 / 2) sin(2 alpha_m), at the
    angle that lifts most. Above pi/2 the insect cannot hover; far below its nominal amplitude
    the wings are far too strong for the body.

    Parameters
    ----------
    insect : Insect

    Returns
    -------
    float
        Phi [rad] (may exceed pi/2).

    Raises
    ------
    ValueError
        If ``insect`` is not an :class:`Insect`.
    """
    _validation.instance("insect", insect, Insect)
    k21 = 0.5 * insect.air_density * insect.lift_slope * insect.span_integral(2, 1)
    return math.sqrt(insect.weight / (2.0 * math.pi**2 * insect.frequency**2 * k21))


def implausible_fields(insect: Insect) -> dict[str, str]:
    """:meth:`Insect.implausible_fields` (the fields likely to blame for a blow-up, with why).

    Raises
    ------
    ValueError
        If ``insect`` is not an :class:`Insect`.
    """
    _validation.instance("insect", insect, Insect)
    found: dict[str, str] = {}

    def blame(names: tuple[str, ...], why: str) -> None:
        for name in names:
            found[name] = f"{found[name]}; {why}" if name in found else why

    for key, message in zip(PLAUSIBLE_RANGES, _implausible_each(insect), strict=True):
        if message:
            blame(_DERIVED_FIELDS.get(key, (key,)), message)
    body = insect.mass - 2.0 * insect.wing_mass
    gyration = math.sqrt(insect.pitch_inertia / body) / insect.semi_span
    low, high = GYRATION_RANGE
    if not low <= gyration <= high:
        blame(("pitch_inertia", "mass"),
              f"the body's radius of gyration sqrt(pitch_inertia / body mass) is {gyration:.3g} "
              f"wing lengths, outside [{low:g}, {high:g}]")
    for name in ("hinge_offset", "hinge_height"):
        ratio = abs(getattr(insect, name)) / insect.semi_span
        if ratio > HINGE_RANGE:
            blame((name,), f"`{name}` is {ratio:.3g} wing lengths from the centre of gravity "
                           f"(more than {HINGE_RANGE:g})")
    amplitude = support_amplitude(insect)
    low, high = SUPPORT_AMPLITUDE_RANGE
    # A weight the wings cannot match follows from any implausible size above; alone, it blames
    # the mass (the field most often given in the wrong unit).
    if not found and not low <= amplitude <= high:
        why = "lift far more than" if amplitude < low else "cannot lift"
        blame(("mass",), f"the wings {why} the weight m g = {insect.weight:.3g} N: at rest "
                         f"and alpha_m = 45 deg they carry it with a stroke of "
                         f"{math.degrees(amplitude):.3g} deg, outside [2, 90] deg (eq. 40; "
                         "check mass, semi_span, wing_area, frequency, air_density)")
    return found


def explain_blowup(insect: Insect) -> str:
    """A sentence naming the likely culprit fields of a failed or overflowing hover solve.

    For the hover layer to append to a "non-finite value" or divergence message, so that the
    user reads which field to check, not only that the integration failed.

    Parameters
    ----------
    insect : Insect

    Returns
    -------
    str
        ``""`` if no field looks implausible (:meth:`Insect.implausible_fields`), else
        ``"likely cause: `mass` (...); `semi_span` (...)"``.

    Raises
    ------
    ValueError
        If ``insect`` is not an :class:`Insect`.
    """
    found = implausible_fields(insect)
    if not found:
        return ""
    return "likely cause: " + "; ".join(f"`{name}` ({why})" for name, why in found.items())


_INERTIA_FIELDS = frozenset({"roll_inertia", "pitch_inertia", "yaw_inertia",
                             "roll_yaw_product"})


_LATERAL_INERTIA_FIELDS = frozenset({"roll_inertia", "yaw_inertia", "roll_yaw_product"})


#: How far a lateral principal moment (roll or yaw) may exceed the sum of the other two (the
#: triangle inequality, which every rigid body obeys) before the Insect is refused; between 1
#: and this factor, a PlausibilityWarning when ``with_`` changes a lateral moment. The presets'
#: lateral moments are ESTIMATES tied to their own I_y (I_z = I_y, a slender body at the
#: bound): the book scales one at a time (x0.5, x2: up to 1.6 times the bound), and a preset
#: built with a smaller I_y keeps them (at most 12.6 times the bound, the hawkmoth's I_z / I_x).
#: A unit slip is far larger: a lateral moment in g cm^2 typed as kg m^2 is 1e7 times too large,
#: 10 kg m^2 of roll on a 1.6 g moth 2e7 times the bound.
TRIANGLE_SLACK = 1000.0

_INERTIA_NAMES = "`roll_inertia`, `pitch_inertia`, `yaw_inertia`, `roll_yaw_product`"


def _check_inertia_tensor(insect: Insect, lateral: bool = True, stacklevel: int = 2) -> None:
    """Refuse a body inertia tensor that is not positive definite (I_x I_z > I_xz^2), or whose
    principal moments break the triangle inequality by more than :data:`TRIANGLE_SLACK` (no
    rigid body has them); warn if they break it by less and ``with_`` changes a lateral one."""
    i_x, i_z, i_xz = insect.roll_inertia, insect.yaw_inertia, insect.roll_yaw_product
    if i_x is not None and i_z is not None and i_xz is not None and i_x * i_z <= i_xz * i_xz:
        raise ValueError(
            f"`roll_yaw_product` = {i_xz:.6g} kg m^2 must satisfy I_xz^2 < I_x I_z "
            f"(roll_inertia {i_x:.6g}, yaw_inertia {i_z:.6g}): the body's inertia tensor must "
            "be positive definite")
    if i_x is None or i_z is None:
        return
    # principal moments: the two of the x-z block (roll and yaw, coupled by I_xz), and I_y
    moments = [*np.linalg.eigvalsh([[i_x, -(i_xz or 0.0)], [-(i_xz or 0.0), i_z]]),
               insect.pitch_inertia]
    # A roll inertia of 10 kg m^2 on a 1.6 g moth, or a lateral moment in g cm^2, is refused.
    # Only a lateral moment too large: a preset built with another I_y keeps the lateral
    # ESTIMATES made for its own, which no I_y in range breaks by the slack from below.
    _validation.triangle_inequality(_INERTIA_NAMES, moments, max_ratio=TRIANGLE_SLACK,
                                    check=(0, 1))
    # The warning only when with_() changes a lateral moment (a full construction cannot tell
    # the presets' estimates from moments the user gave)
    if not lateral:
        return
    try:
        _validation.triangle_inequality(_INERTIA_NAMES, moments)
    except ValueError as exc:
        warnings.warn(f"{exc}; kept, as it is within {TRIANGLE_SLACK:g} times the bound",
                      PlausibilityWarning, stacklevel=stacklevel)


_WING_MASS_FIELDS = frozenset({"wing_mass", "wing_mass_r1", "wing_mass_r2", "r1", "r2"})


def _check_wing_mass(insect: Insect) -> None:
    """The wings lighter than the insect, and the mass radii ordered (Cauchy-Schwarz)."""
    if not 2.0 * insect.wing_mass < insect.mass:
        raise ValueError(f"`wing_mass` must be below half of `mass` = {insect.mass:.6g} kg (the "
                         f"wings are part of the insect); got {insect.wing_mass:.6g} kg")
    r1, r2 = insect.wing_mass_radii
    if not r1 <= r2:
        raise ValueError(f"`wing_mass_r1` = {r1:.6g} must not exceed `wing_mass_r2` = {r2:.6g} "
                         "(the radius of gyration bounds the mean radius)")


def _check_field(name: str, value: object, kind: str, unit: str) -> float | None:
    """One numeric field of :class:`Insect` as a float in its range (see :data:`_FIELDS`)."""
    if kind == "physical":
        low, high, _ = PHYSICAL_RANGES[name]
        return _validation.real(name, value, low=low, high=high, unit=unit)
    if kind == "optional":
        if value is None:
            return None
        low, high, _ = PHYSICAL_RANGES[name]
        return _validation.real(name, value, low=low, high=high, unit=unit)
    if kind == "radius":
        if value is None:
            return None
        return _validation.real(name, value, low=0.0, high=1.0, low_open=True,
                                unit="(fraction of the wing length)")
    if kind == "fraction":
        return _validation.real(name, value, low=0.0, high=1.0, unit="(fraction of the chord)")
    if kind == "amplitude":
        amplitude = check_amplitude(value, name)  # the kinematics' range, (0, pi/2], first
        return _validation.real(name, amplitude, low=PHYSICAL_RANGES[name][0],
                                high=math.pi / 2, unit="rad (1 to 90 deg)")
    if kind == "stroke_mean":
        return _validation.real(name, value, low=-math.pi / 2, high=math.pi / 2, low_open=True,
                                high_open=True, unit=unit)
    # r1 and r2: fractions of the wing length; r2's range given r1 is checked afterwards.
    return _validation.real(name, value, low=0.0, high=1.0, low_open=True, high_open=True,
                            unit="(fraction of the wing length)")

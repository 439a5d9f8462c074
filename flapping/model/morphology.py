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
           "PLAUSIBLE_RANGES"]

AspectRatioConvention = Literal["pair", "single"]

#: The accepted aspect-ratio conventions of eq. (4) (see :class:`Insect`).
ASPECT_RATIO_CONVENTIONS: tuple[AspectRatioConvention, ...] = ("pair", "single")

#: Largest magnitude [SI] of any numeric :class:`Insect` field, and the inverse of the smallest
#: magnitude of a positive one. Beyond it the model's products leave float64's range (span
#: integrals reach R^-3 S^4, i.e. LIMIT^7; loads multiply these by rho f^2), so a value outside
#: [1/LIMIT, LIMIT] is an error, not a warning. Plausible values lie far inside: see
#: :data:`PLAUSIBLE_RANGES`.
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

#: Numeric fields of :class:`Insect`: (accepted range, unit). Ranges: "positive" (magnitude in
#: [1/MAGNITUDE_LIMIT, MAGNITUDE_LIMIT]), "nonnegative" (0 or up to MAGNITUDE_LIMIT),
#: "fraction" (of the chord, [0, 1]), "real" (magnitude up to MAGNITUDE_LIMIT), "amplitude"
#: (:func:`~.kinematics.check_amplitude`), "stroke_mean" (real in (-pi/2, pi/2));
#: r1 and r2 are checked together by :func:`beta_shape_parameters`. Gravity is positive: with
#: g = 0 there is no weight to carry, so no hover (the angle alpha_m of eq. 40 is zero).
_FIELDS: dict[str, tuple[str, str]] = {
    "semi_span": ("positive", "m"), "wing_area": ("positive", "m^2"),
    "frequency": ("positive", "Hz"), "mass": ("positive", "kg"),
    "pitch_inertia": ("positive", "kg m^2"), "air_density": ("positive", "kg/m^3"),
    "a0": ("positive", "1/rad"), "gravity": ("positive", "m/s^2"),
    "mu1": ("nonnegative", ""), "mu2": ("nonnegative", ""),
    "pitch_axis": ("fraction", ""), "center_of_pressure": ("fraction", ""),
    "hinge_offset": ("real", "m"), "stroke_amplitude": ("amplitude", "rad"),
    "hinge_height": ("real", "m"), "stroke_mean": ("stroke_mean", "rad"),
    "r1": ("real", ""), "r2": ("real", ""),
    "wing_mass": ("nonnegative", "kg"),
    "wing_mass_r1": ("radius", ""), "wing_mass_r2": ("radius", ""),
}


def beta_shape_parameters(r1: float, r2: float) -> tuple[float, float]:
    """Shape parameters (p, q) of the beta chord distribution with moments r1, r2.

    Ellington's method of moments (paper, appendix A): the non-dimensional chord
    c(r)/c_bar = r**(p-1) (1-r)**(q-1) / B(p, q) has first moment r1 and second moment r2**2.

    Parameters
    ----------
    r1 : float
        Non-dimensional radius of the first moment of wing area, in (0, 1).
    r2 : float
        Non-dimensional radius of the second moment of wing area, in (r1, sqrt(r1)), close
        enough to r1 that the squared chord is integrable (p, q > 1/2).

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
    # r1 < r2: positive variance; r2 < sqrt(r1): a mean square below the mean (p, q > 0).
    r2 = _validation.real("r2", r2, low=r1, high=math.sqrt(r1), low_open=True, high_open=True)
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

    Raises
    ------
    ValueError
        If a field is outside its range; the message names the field and the range. Numbers of
        any real type (``int``, ``np.float32``, ``np.int64``, ...) are stored as Python floats;
        bools and strings are refused. Magnitudes beyond :data:`MAGNITUDE_LIMIT` (positive
        ones also below its inverse) are refused, including integers too large for float64.

    Warns
    -----
    PlausibilityWarning
        For each value outside :data:`PLAUSIBLE_RANGES` (magnitudes no insect or flapping
        vehicle has, e.g. a wing beat of 1e12 Hz), naming the field, its value and the range.
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
        for message in _implausible(self):
            warnings.warn(message, PlausibilityWarning, stacklevel=stacklevel)

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
        """
        r_hat = np.asarray(r, dtype=float) / self.semi_span
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
    cited by the paper. The paper also prints c_bar = 18.3 mm; we use c_bar = S/R = 18.26 mm so
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
    messages = []
    for name, (low, high, unit) in PLAUSIBLE_RANGES.items():
        if name == "aspect_ratio_1":
            value, what = insect.semi_span**2 / insect.wing_area, "semi_span**2 / wing_area"
        elif name == "wing_mass_ratio":
            value, what = 2.0 * insect.wing_mass / insect.mass, "2 wing_mass / mass"
        else:
            value, what = getattr(insect, name), f"`{name}`"
        if not low <= value <= high:
            messages.append(
                f"{what} = {value:.6g} {unit} of {insect.name!r} is outside the range of insects "
                f"and flapping vehicles [{low:.6g}, {high:.6g}] {unit}; the model accepts it, but "
                "check the units (SI: m, kg, s, rad)")
    return messages


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
    if kind == "radius":
        if value is None:
            return None
        return _validation.real(name, value, low=0.0, high=1.0, low_open=True,
                                unit="(fraction of the wing length)")
    if kind == "positive":
        return _validation.real(name, value, low=1.0 / MAGNITUDE_LIMIT, high=MAGNITUDE_LIMIT,
                                unit=unit)
    if kind == "nonnegative":
        return _validation.real(name, value, low=0.0, high=MAGNITUDE_LIMIT, unit=unit)
    if kind == "fraction":
        return _validation.real(name, value, low=0.0, high=1.0, unit="(fraction of the chord)")
    if kind == "amplitude":
        return check_amplitude(value, name)
    if kind == "stroke_mean":
        return _validation.real(name, value, low=-math.pi / 2, high=math.pi / 2, low_open=True,
                                high_open=True, unit=unit)
    return _validation.real(name, value, low=-MAGNITUDE_LIMIT, high=MAGNITUDE_LIMIT, unit=unit)

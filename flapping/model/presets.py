"""Species presets: hovering insects from the literature as :class:`~.morphology.Insect` objects.

Six species, each number with its source and how far that source was checked:

=============  ======================  =========  ========  ===============================
name           species                 mass [mg]  R [mm]    frequency [Hz]
=============  ======================  =========  ========  ===============================
hawkmoth       *Manduca sexta*         1648       51.9      26.3 (the paper's preset)
bumblebee      *Bombus*                175        13.2      156.25 (1 / 6.4 ms; 116 in another
                                                            source, see :func:`bumblebee`)
fruit_fly      *Drosophila*            0.72       2.02      254
honeybee       *Apis mellifera*        ~100       ~9.7      230
hoverfly       Sun's model hoverfly    145        11.2      ~164
monarch        *Danaus plexippus*      307.9      61.0      11.72
=============  ======================  =========  ========  ===============================

Every number of a preset is a :class:`Sourced` value: SI value, source, and a **status**:

- ``"verified"``: read in the source's data file or abstract (FWUAV's ``.mat``/``.m`` files at the
  commits named, the abstracts of Sun & Xiong 2005a and Altshuler et al. 2005);
- ``"paper"``: as printed in the seed paper's appendix A (the hawkmoth; :func:`hawkmoth` unchanged);
- ``"second-hand"``: quoted from a source by an earlier reading note, not re-read here;
- ``"unverified"``: from memory of the cited paper; check it before relying on it;
- ``"estimate"``: computed by a stated method (:func:`ellipsoid_pitch_inertia`,
  :func:`ellington_r1`), not taken from any source.

Unverified and estimated numbers carry a plausible range (:attr:`Sourced.low`,
:attr:`Sourced.high`), used by the book's uncertainty study (``book/atlas.md``).

Modelling choices shared by all presets (the model's, stated once):

- Two geometries. ``geometry="paper"`` (the default): the wing hinge at the centre of gravity
  and massless wings, as the paper models its hawkmoth, so every earlier number is unchanged.
  ``geometry="source"`` (:attr:`Preset.measured`; ``"measured"``, its former name, still works
  with a ``DeprecationWarning``: most of these numbers are estimated, not measured): the hinge
  position relative to the body's
  centre of gravity (:func:`hinge_geometry` of the sources' hinge-to-CG distance and its angle to
  the stroke plane) and the wing mass, spread as the wing area (uniform areal density: FWUAV's
  monarch wing has radius of gyration 0.543 R, its area's r2 is 0.543). With the hinge off the
  CG the hover orbit needs the mean stroke angle as a second trim
  (``trims=("amplitude", "stroke_mean")``). Only the hoverfly's hinge position is a measurement
  (second-hand); the hawkmoth's, bumblebee's and fruit fly's come from FWUAV's monarch body
  scaled to their mass, the monarch's from FWUAV's measured body, the honeybee's by analogy:
  estimates, each with a range.
- The stroke plane is horizontal in body axes, as in the paper.
- ``stroke_amplitude`` is the *nominal* amplitude: it fixes the mean angle of attack alpha_m by the
  trim of eq. (40) and is the first guess of the hover solve, which then finds the hover amplitude.

Module order: imports only :mod:`flapping.model.morphology` (and, through it, kinematics).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Literal

from flapping import _validation
from flapping.model.morphology import Insect, hawkmoth

__all__ = [
    "GEOMETRIES",
    "DEPRECATED_GEOMETRIES",
    "STATUSES",
    "hinge_geometry",
    "Sourced",
    "Preset",
    "PRESETS",
    "preset",
    "preset_names",
    "species_table",
    "ellipsoid_pitch_inertia",
    "BODY_SIZES",
    "ellington_r1",
    "hawkmoth",
    "bumblebee",
    "fruit_fly",
    "honeybee",
    "hoverfly",
    "monarch",
]

Status = Literal["verified", "paper", "second-hand", "unverified", "estimate"]

#: The geometries a preset comes in: the paper's (hinge at the CG, massless wings) and the
#: sources' (their hinge position and wing mass: estimated for the most part, see each number's
#: status).
GEOMETRIES: tuple[str, ...] = ("paper", "source")

#: Former names of the geometries, accepted with a DeprecationWarning: "measured" was the
#: sources' geometry, whose hinge positions are estimates but for the hoverfly's.
DEPRECATED_GEOMETRIES: Mapping[str, str] = MappingProxyType({"measured": "source"})

#: The accepted statuses of a :class:`Sourced` number, from best to worst checked.
STATUSES: tuple[Status, ...] = ("verified", "paper", "second-hand", "unverified", "estimate")

#: FWUAV (fdcl-gwu/FWUAV, MATLAB): commits of the data files read.
_FWUAV_PARAMS = "FWUAV morp_params.mat (Berman & Wang's values; commit d23b81b)"
_FWUAV_MONARCH = "FWUAV morp_MONARCH.m / sim_data/morp_MONARCH.mat (HEAD 04953d4)"
_FWUAV_HOVER = ("FWUAV sim_data/other_insects/sim_QS_x_hover_mona.mat, the hover of its Floquet "
                "comparison (commit 1a25d41)")


@dataclass(frozen=True)
class Sourced:
    """One number of a preset with where it comes from.

    Attributes
    ----------
    value : float
        The number, in SI units (as the :class:`Insect` field it sets).
    source : str
        Where it comes from, in words (a citation and, for data files, the file and commit).
    status : {"verified", "paper", "second-hand", "unverified", "estimate"}
        How far the source was checked (module docstring).
    cite : tuple of str
        Keys of ``book/references.bib`` for the source.
    low, high : float, optional
        Plausible range [SI] of an unverified or estimated number (both or neither).
    note : str
        The method of an estimate, or why this value was chosen over another.
    """

    value: float
    source: str
    status: Status
    cite: tuple[str, ...] = ()
    low: float | None = None
    high: float | None = None
    note: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "value", _validation.real("value", self.value))
        _validation.choice("status", self.status, STATUSES)
        if (self.low is None) != (self.high is None):
            raise ValueError("`low` and `high` must be given together")
        if self.low is not None and self.high is not None:
            low = _validation.real("low", self.low, high=self.value)
            high = _validation.real("high", self.high, low=self.value)
            object.__setattr__(self, "low", low)
            object.__setattr__(self, "high", high)

    @property
    def has_range(self) -> bool:
        """True if a plausible range is given."""
        return self.low is not None


@dataclass(frozen=True)
class Preset:
    """A species preset: its :class:`Insect` fields with their sources, and what the model lacks.

    Attributes
    ----------
    name : str
        The preset's name (``--insect NAME`` on the command line), also the insect's ``name``.
    species : str
        Latin name (or the model insect it reproduces).
    summary : str
        One line: which data set, and the preset's main choice.
    source : str
        The main source, in words (the ``species`` command lists it).
    values : mapping of str to Sourced
        The :class:`Insect` fields the preset sets (the others keep the class defaults).
    extras : mapping of str to Sourced
        Numbers used by an estimate (body length, body diameter, the hinge-to-CG distance) or
        given by the sources but absent from the model: documented, not used.
    measured : mapping of str to Sourced
        The :class:`Insect` fields of the sources' geometry (``geometry="source"``; the
        attribute keeps its former name): the wing hinge's position relative to the body's
        centre of gravity (``hinge_offset``, ``hinge_height``) and the wing mass
        (``wing_mass``), each with its source or estimate and its status.
    """

    name: str
    species: str
    summary: str
    source: str
    values: Mapping[str, Sourced]
    extras: Mapping[str, Sourced] = field(default_factory=dict)
    measured: Mapping[str, Sourced] = field(default_factory=dict)

    def insect(self, geometry: str = "paper", **overrides: Any) -> Insect:
        """The preset as an :class:`Insect`, with some fields changed.

        Parameters
        ----------
        geometry : {"paper", "source"}
            ``"paper"``: the wing hinge at the centre of gravity and massless wings, as the paper
            models its hawkmoth (every earlier number unchanged). ``"source"``: the hinge
            position and wing mass of :attr:`measured` (the hinge off the centre of gravity: hover
            then needs the mean stroke angle as a second trim). ``"measured"``: the former name
            of ``"source"``, deprecated.
        **overrides
            Any :class:`Insect` field, in SI units (applied last).

        Returns
        -------
        Insect

        Raises
        ------
        ValueError
            If an override is outside its field's range.
        TypeError
            If an override is not a field of :class:`Insect`.

        Warns
        -----
        DeprecationWarning
            For ``geometry="measured"``, naming ``"source"``.
        """
        geometry = _geometry(geometry)
        values: dict[str, Any] = {k: v.value for k, v in self.values.items()}
        values["name"] = self.name
        if geometry == "source":
            values.update({k: v.value for k, v in self.measured.items()})
        if self.name in BODY_SIZES:  # estimates (six degrees of freedom only)
            values.update(zip(("roll_inertia", "yaw_inertia", "roll_yaw_product"),
                              lateral_inertia_estimate(values["mass"], values["pitch_inertia"],
                                                       BODY_SIZES[self.name][1]), strict=True))
        values.update(overrides)
        return Insect(**values)

    @property
    def mass(self) -> float:
        """Body mass [kg]."""
        return self.values["mass"].value

    @property
    def semi_span(self) -> float:
        """Wing length R [m]."""
        return self.values["semi_span"].value

    @property
    def frequency(self) -> float:
        """Flapping frequency [Hz]."""
        return self.values["frequency"].value

    def ranged(self) -> dict[str, Sourced]:
        """The fields with a plausible range (unverified or estimated), for uncertainty studies."""
        return {k: v for k, v in self.values.items() if v.has_range}

    def ranged_fields(self, fields: Any = None, name: str = "fields") -> tuple[str, ...]:
        """``fields`` checked against :meth:`ranged` (default: all of them), for a study that
        varies each over its plausible range.

        Parameters
        ----------
        fields : sequence of str, optional
            Field names; default every field with a range.
        name : str
            The argument's name, for the messages.

        Returns
        -------
        tuple of str

        Raises
        ------
        ValueError
            If ``fields`` is not a sequence of names, or names a field without a range; the
            message lists the fields with one, and if there are none (every number of the
            preset is verified or the paper's, as the hawkmoth's) says so and names the presets
            that have some.
        """
        ranged = self.ranged()
        if fields is None:
            chosen: tuple[Any, ...] = tuple(ranged)
        elif isinstance(fields, (str, bytes)) or not hasattr(fields, "__iter__"):
            raise ValueError(f"`{name}` must be a sequence of field names; got {fields!r}")
        else:
            chosen = tuple(fields)
        for f in chosen:
            if f in ranged:
                continue
            if not ranged:
                others = ", ".join(p for p, entry in PRESETS.items() if entry.ranged())
                raise ValueError(
                    f"`{name}`: the {self.name} preset has no number with a plausible range "
                    f"(every value is verified or the paper's), so {f!r} cannot be varied; "
                    f"presets with uncertain numbers: {others}")
            raise ValueError(f"`{name}` must name fields with a plausible range in the "
                             f"{self.name} preset, one of {tuple(ranged)}; got {f!r}")
        return chosen


# =========================================================================== estimation methods
def ellipsoid_pitch_inertia(mass: float, length: float, diameter: float) -> float:
    """Pitch moment of inertia [kg m^2] of a uniform solid prolate ellipsoid about its centre.

    I_y = m (L^2 + d^2) / 20 for an ellipsoid of length L and diameter d (semi-axes L/2, d/2, d/2),
    about an axis through the centre perpendicular to the long axis. Checked on the paper's
    hawkmoth: L = 48 mm, d = 10 mm give 1.98e-7 kg m^2 against its 2.08e-7 (-5 %).

    Parameters
    ----------
    mass : float
        Body mass m [kg], > 0.
    length, diameter : float
        Body length L and diameter d [m], > 0.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If an argument is not a positive real number.
    """
    mass = _validation.positive("mass", mass, unit="kg")
    length = _validation.positive("length", length, unit="m")
    diameter = _validation.positive("diameter", diameter, unit="m")
    return mass * (length**2 + diameter**2) / 20.0


#: Ellington's (1984, part II) fit between the radii of the moments of wing area,
#: r2 = ELLINGTON_FIT[0] * r1 ** ELLINGTON_FIT[1].
ELLINGTON_FIT = (0.929, 0.732)


def ellington_r1(r2: float) -> float:
    """r1 from r2 by Ellington's empirical fit r2 = 0.929 r1^0.732, inverted.

    r1 = (r2 / 0.929)^(1/0.732). (The fit's direction follows from r1 < r2: the reverse,
    r1 = 0.929 r2^0.732, gives r1 = 0.600 > r2 = 0.55.) For r2 in [0.45, 0.65] the result
    satisfies r1 < r2 < sqrt(r1), the condition of :func:`~.morphology.beta_shape_parameters`.

    Parameters
    ----------
    r2 : float
        Non-dimensional radius of the second moment of wing area, in (0, 0.929).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If r2 is outside (0, 0.929).
    """
    a, b = ELLINGTON_FIT
    r2 = _validation.real("r2", r2, low=0.0, high=a, low_open=True, high_open=True)
    return (r2 / a) ** (1.0 / b)


#: FWUAV's monarch thorax, a cylinder: pitch inertia about its own centre [kg m^2] (J_B,yy).
_MONARCH_THORAX_IY = 2.94814204e-9

_SUPERSCRIPT = str.maketrans("-0123456789", "\u207b\u2070\u00b9\u00b2\u00b3\u2074\u2075"
                                             "\u2076\u2077\u2078\u2079")


def _inertia_text(value: float) -> str:
    """A pitch inertia [kg m^2] as text, in SI and in the tables' mg cm^2 (1 kg m^2 = 1e10 of
    them)."""
    exponent = math.floor(math.log10(value))
    mantissa = value / 10.0**exponent
    return (f"{mantissa:.2f} \u00d7 10{str(exponent).translate(_SUPERSCRIPT)} kg m\u00b2 "
            f"({value * 1e10:.3g} mg cm\u00b2)")


def _monarch_pitch_inertia() -> float:
    """I_y of FWUAV's monarch thorax + abdomen, rigid, about their joint centre of gravity.

    FWUAV models the thorax as a cylinder about its centre (J_B,yy = 2.948e-9 kg m^2) and the
    abdomen as one about its end (J_A,yy = m_A (h_A^2/3 + w_A^2/16) = 1.109e-8), attached 7.315 mm
    behind the thorax centre, its centre 8.69 mm further back. Parallel axes to the joint CG
    (6.78 mm behind the thorax centre, where the wings are attached) give 2.19e-8 kg m^2.
    """
    m_b, j_b = 1.485e-4, _MONARCH_THORAX_IY     # thorax: mass [kg], J_yy about its centre
    m_a, h_a, w_a = 1.092e-4, 1.738e-2, 3.71e-3  # abdomen: mass, length, width
    attach, centre = 7.315e-3, 8.69e-3           # abdomen joint behind thorax; its CG behind joint
    j_a_end = m_a * (h_a**2 / 3.0 + w_a**2 / 16.0)
    x_a = -(attach + centre)                     # abdomen CG from the thorax centre
    x_cg = m_a * x_a / (m_b + m_a)
    j_a_cg = j_a_end - m_a * centre**2
    return j_b + m_b * x_cg**2 + j_a_cg + m_a * (x_a - x_cg) ** 2


# =========================================================================== the data
def _v(value: float, source: str, status: Status, *cite: str, low: float | None = None,
       high: float | None = None, note: str = "") -> Sourced:
    return Sourced(value, source, status, tuple(cite), low, high, note)


#: Plausible range of an estimated pitch inertia, as a factor of the estimate: covers body length
#: +-15 %, diameter +-20 % and non-uniform density (a heavy thorax lowers I_y, a long abdomen
#: raises it).
INERTIA_RANGE = (0.6, 1.6)
#: Plausible half-width of an unverified r2 (Ellington-type measurements: 0.50-0.60).
R2_HALF_RANGE = 0.03
#: Plausible relative range of an unverified nominal stroke amplitude (+-15 %).
AMPLITUDE_RANGE = (0.85, 1.15)


#: Body length and diameter [m] behind the pitch-inertia estimates
#: (:func:`ellipsoid_pitch_inertia`), one pair per species whose body is an ellipsoid here; also
#: the scale of a hinge height (a wing base lies in the thorax, within a body diameter of the
#: centre of gravity). Both are estimates (see each preset's pitch-inertia source). The hawkmoth's
#: pair is the check against the paper's inertia (-5 %); the monarch's body is FWUAV's.
BODY_SIZES: Mapping[str, tuple[float, float]] = MappingProxyType({
    "hawkmoth": (48e-3, 10e-3),
    "bumblebee": (18e-3, 7e-3),      # L: Dudley & Ellington (1990), unverified; d estimated
    "fruit_fly": (2.5e-3, 0.9e-3),   # both estimated
    "honeybee": (13e-3, 4.5e-3),     # L unverified, d estimated
    "hoverfly": (1.29 * 11.2e-3, 5e-3),  # L = 1.29 R (second-hand), d estimated
})


def lateral_inertia_estimate(mass: float, pitch_inertia: float,
                             diameter: float) -> tuple[float, float, float]:
    """ESTIMATE of the body's (roll_inertia, yaw_inertia, roll_yaw_product) [kg m^2].

    The body as a uniform prolate ellipsoid with its long axis along body x (the presets' pitch
    inertia estimate, :func:`ellipsoid_pitch_inertia`): I_x = m d^2 / 10 about the long axis;
    I_z = I_y, the body axisymmetric about its long axis; I_xz = 0, body axes principal. No
    preset has a measured roll or yaw inertia: every six-degree-of-freedom result of a preset
    rests on this estimate (the lateral modes' sensitivity to it is the first thing to check).

    Parameters
    ----------
    mass : float
        Insect mass m [kg].
    pitch_inertia : float
        The preset's I_y [kg m^2].
    diameter : float
        Body diameter d [m] (:data:`BODY_SIZES`).

    Returns
    -------
    tuple of float
    """
    return mass * diameter**2 / 10.0, pitch_inertia, 0.0


def _inertia(mass: float, length: float, diameter: float, what: str) -> Sourced:
    value = ellipsoid_pitch_inertia(mass, length, diameter)
    return _v(value, "estimate: uniform prolate ellipsoid m (L^2 + d^2)/20", "estimate",
              low=INERTIA_RANGE[0] * value, high=INERTIA_RANGE[1] * value,
              note=f"L = {length * 1e3:g} mm, d = {diameter * 1e3:g} mm ({what})")


def _r2_r1(r2: float, source: str, status: Status, *cite: str) -> dict[str, Sourced]:
    ranged = status != "verified"
    r1 = ellington_r1(r2)
    return {
        "r2": _v(r2, source, status, *cite, low=r2 - R2_HALF_RANGE if ranged else None,
                 high=r2 + R2_HALF_RANGE if ranged else None),
        "r1": _v(r1, "estimate: Ellington's fit r2 = 0.929 r1^0.732, inverted", "estimate",
                 "ellington1984", low=r1 - 0.02, high=r1 + 0.02,
                 note="+-0.02: the scatter of measured r1 about the fit"),
    }


def _amplitude(degrees: float, source: str, status: Status, *cite: str, note: str = ""
               ) -> Sourced:
    value = math.radians(degrees)
    if status in ("verified", "paper"):
        return _v(value, source, status, *cite, note=note)
    low, high = AMPLITUDE_RANGE
    return _v(value, source, status, *cite, low=low * value, high=min(high * value, math.pi / 2),
              note=note)


# =========================================================================== the sources' geometry
def hinge_geometry(distance: float, elevation: float) -> tuple[float, float]:
    """(hinge_offset, hinge_height) [m] of a hinge ``distance`` from the body's centre of gravity.

    The hinge-to-CG line rises ``elevation`` [rad] above the stroke plane, going from the CG to
    the hinge: ``elevation = pi/2`` puts the hinge straight above the CG (the CG hangs below the
    wing base), ``elevation = beta`` is a CG on the body axis behind the hinge with the body axis
    inclined beta to the stroke plane. x_h = d cos(elevation), h_w = d sin(elevation).

    Parameters
    ----------
    distance : float
        Hinge-to-CG distance d [m], >= 0.
    elevation : float
        Angle of the CG-to-hinge line above the stroke plane [rad], in [0, pi/2].

    Returns
    -------
    tuple of 2 floats
        (x_h, h_w) [m]: the hinge ahead of and above the centre of gravity in body axes.

    Raises
    ------
    ValueError
        If an argument is outside its range.
    """
    distance = _validation.real("distance", distance, low=0.0, unit="m")
    elevation = _validation.real("elevation", elevation, low=0.0, high=math.pi / 2, unit="rad")
    if elevation == math.pi / 2:  # exactly above: x_h = 0, not cos(pi/2) d = 6e-17 d
        return 0.0, distance
    return distance * math.cos(elevation), distance * math.sin(elevation)


#: Plausible relative range of an estimated hinge-to-CG distance, and of its elevation [deg].
HINGE_DISTANCE_RANGE = (0.7, 1.3)
HINGE_ELEVATION_HALF_RANGE_DEG = 15.0


def _hinge(distance: float, elevation_deg: float, source: str, status: Status, *cite: str,
           note: str = "") -> dict[str, Sourced]:
    """Sourced (hinge_offset, hinge_height), ranged over the distance and elevation ranges."""
    corners = [hinge_geometry(distance * f, math.radians(min(max(elevation_deg + d, 0.0), 90.0)))
               for f in HINGE_DISTANCE_RANGE
               for d in (-HINGE_ELEVATION_HALF_RANGE_DEG, 0.0, HINGE_ELEVATION_HALF_RANGE_DEG)]
    x_h, h_w = hinge_geometry(distance, math.radians(elevation_deg))
    what = f"d = {distance * 1e3:.3g} mm at {elevation_deg:.3g} deg above the stroke plane"
    ranged = status != "verified"
    return {name: _v(value, f"{source}: {what}", status, *cite,
                     low=min(min(c[i] for c in corners), value) if ranged else None,
                     high=max(max(c[i] for c in corners), value) if ranged else None,
                     note=note)
            for i, (name, value) in enumerate((("hinge_offset", x_h), ("hinge_height", h_w)))}


def _fwuav_body_cg(thorax: float, abdomen: float, joint: float, abdomen_cg: float) -> float:
    """Distance [m] from FWUAV's wing root (at the thorax's CG) back to the thorax + abdomen CG,
    the abdomen straight behind the thorax: m_A (joint + abdomen_cg) / (m_B + m_A)."""
    return abdomen * (joint + abdomen_cg) / (thorax + abdomen)


_FWUAV_SCALED = ("FWUAV morp_insects.m at commit 1a25d41 (its monarch's thorax and abdomen scaled "
                 "by (m / m_monarch)^(1/3); the wing root at the thorax's CG; hover stroke plane "
                 "WK.beta from the body axis in sim_QS_x_hover_*.mat)")


def _hawkmoth_preset() -> Preset:
    moth = hawkmoth()
    paper = "the paper's appendix A (after Ellington 1984 and Willmott & Ellington 1997)"
    fwuav = f"paper; = Berman & Wang (2007) in {_FWUAV_PARAMS}"
    values = {
        "semi_span": _v(moth.semi_span, fwuav, "verified", "elsadek", "berman2007", "fwuav"),
        "wing_area": _v(moth.wing_area, fwuav + " (R x c_bar = 51.9 x 18.26 mm)", "verified",
                        "elsadek", "berman2007", "fwuav"),
        "r1": _v(moth.r1, paper, "paper", "elsadek", "ellington1984"),
        "r2": _v(moth.r2, paper, "paper", "elsadek", "ellington1984"),
        "frequency": _v(moth.frequency, fwuav, "verified", "elsadek", "berman2007", "fwuav"),
        "stroke_amplitude": _v(moth.stroke_amplitude, paper, "paper", "elsadek",
                               "willmott1997"),
        "mass": _v(moth.mass, fwuav, "verified", "elsadek", "berman2007", "fwuav"),
        "pitch_inertia": _v(moth.pitch_inertia, paper, "paper", "elsadek",
                            note="the ellipsoid estimate with L = 48 mm, d = 10 mm gives -5 %"),
    }
    extras: dict[str, Sourced] = {}
    measured = {
        **_hinge(_fwuav_body_cg(9.324e-4, 6.216e-4, 12.7957e-3, 15.2009e-3), 28.478,
                 _FWUAV_SCALED, "estimate", "fwuav",
                 note="FWUAV's scaled monarch body, not a hawkmoth measurement"),
        "wing_mass": _v(4.7e-5, _FWUAV_PARAMS, "verified", "berman2007", "fwuav",
                        note="per wing; the mass spread as the area (uniform areal density)"),
    }
    return Preset("hawkmoth", "Manduca sexta", "the paper's hawkmoth, unchanged",
                  "Elsadek et al. (appendix A); Berman & Wang 2007", values, extras, measured)


def _bumblebee_preset() -> Preset:
    mass, r, chord = 1.75e-4, 13.2e-3, 4.02e-3
    bw = f"Berman & Wang (2007) in {_FWUAV_PARAMS}"
    values = {
        "semi_span": _v(r, bw, "verified", "berman2007", "fwuav"),
        "wing_area": _v(r * chord, bw + ": S = R c_bar, c_bar = 4.02 mm", "verified",
                        "berman2007", "fwuav"),
        **_r2_r1(0.55, "Dudley & Ellington (1990) BB01, as used by Sun & Xiong (2005a)",
                 "unverified", "dudley1990", "sun2005"),
        "frequency": _v(1.0 / 6.4e-3, "Sun & Xiong (2005a), abstract: wingbeat period 6.4 ms",
                        "verified", "sun2005",
                        note="chosen over Berman & Wang's 116 Hz: the data set of the CFD "
                             "stability result we compare with (and of Phi and r2)"),
        "stroke_amplitude": _amplitude(58.0, "Dudley & Ellington (1990) BB01: 116 deg "
                                       "peak-to-peak", "unverified", "dudley1990"),
        "mass": _v(mass, bw + "; Sun & Xiong (2005a) also 175 mg", "verified", "berman2007",
                   "fwuav", "sun2005"),
        "pitch_inertia": _inertia(mass, *BODY_SIZES["bumblebee"],
                                  "L unverified (Dudley & Ellington 1990), d estimated"),
    }
    extras = {
        "frequency_berman_wang": _v(116.0, bw, "verified", "berman2007", "fwuav",
                                    note="the alternative frequency: bumblebee(frequency=116.0)"),
        "body_length": _v(18e-3, "Dudley & Ellington (1990)", "unverified", "dudley1990"),
    }
    measured = {
        **_hinge(_fwuav_body_cg(1.04448e-4, 6.9632e-5, 6.0593e-3, 7.1983e-3), 23.706,
                 _FWUAV_SCALED, "estimate", "fwuav",
                 note="FWUAV's scaled monarch body, not a bumblebee measurement"),
        "wing_mass": _v(4.6e-7, _FWUAV_PARAMS, "verified", "berman2007", "fwuav"),
    }
    return Preset("bumblebee", "Bombus", "Berman & Wang's bumblebee at Sun & Xiong's 6.4 ms "
                  "wingbeat", "Berman & Wang 2007; Sun & Xiong 2005a", values, extras, measured)


def _fruit_fly_preset() -> Preset:
    mass, r, chord = 7.2e-7, 2.02e-3, 0.67e-3
    bw = f"Berman & Wang (2007) in {_FWUAV_PARAMS}"
    values = {
        "semi_span": _v(r, bw, "verified", "berman2007", "fwuav"),
        "wing_area": _v(r * chord, bw + ": S = R c_bar, c_bar = 0.67 mm", "verified",
                        "berman2007", "fwuav"),
        **_r2_r1(0.58, "typical Drosophila value (Ellington-type measurements 0.55-0.60)",
                 "unverified", "ellington1984"),
        "frequency": _v(254.0, bw, "verified", "berman2007", "fwuav"),
        "stroke_amplitude": _amplitude(70.0, "typical hovering Drosophila (~140 deg "
                                       "peak-to-peak)", "unverified",
                                       note="FWUAV's quasi-steady hover: 66.5 deg at 285 Hz"),
        "mass": _v(mass, bw, "verified", "berman2007", "fwuav"),
        "pitch_inertia": _inertia(mass, *BODY_SIZES["fruit_fly"], "L and d estimated; Berthe & "
                                  "Lehmann (2015) model the fly's moments of inertia about its "
                                  "three body axes, their values not read here"),
    }
    measured = {
        **_hinge(_fwuav_body_cg(4.30968e-7, 2.87312e-7, 0.97093e-3, 1.15344e-3), 26.835,
                 _FWUAV_SCALED, "estimate", "fwuav",
                 note="FWUAV's scaled monarch body, not a fruit-fly measurement"),
        "wing_mass": _v(8.6e-10, _FWUAV_PARAMS, "verified", "berman2007", "fwuav"),
    }
    return Preset("fruit_fly", "Drosophila", "Berman & Wang's fruit fly",
                  "Berman & Wang 2007", values, {}, measured)


def _honeybee_preset() -> Preset:
    mass = 1.0e-4
    alt = "Altshuler et al. (2005), abstract"
    values = {
        "semi_span": _v(9.7e-3, "Ellington (1984); Altshuler et al. (2005)", "unverified",
                        "ellington1984", "altshuler2005", low=9.4e-3, high=10.0e-3),
        "wing_area": _v(2.9e-5, "fore- and hindwing coupled, c_bar ~ 3.0 mm", "unverified",
                        "ellington1984", low=2.6e-5, high=3.2e-5),
        **_r2_r1(0.55, "typical hymenopteran value", "unverified", "ellington1984"),
        "frequency": _v(230.0, alt + ": 'approximate to 230 Hz'", "verified", "altshuler2005"),
        "stroke_amplitude": _v(math.radians(45.0), alt + ": ~90 deg stroke (read as peak-to-"
                               "peak)", "verified", "altshuler2005", "vance2014",
                               note="Vance et al. (2014): 86.7 +- 7.9 deg"),
        "mass": _v(mass, "unloaded forager, 80-110 mg (Ellington 1984)", "unverified",
                   "ellington1984", low=8e-5, high=1.2e-4),
        "pitch_inertia": _inertia(mass, *BODY_SIZES["honeybee"], "L unverified, d estimated"),
    }
    measured = {
        **_hinge(0.13 * 13e-3, 90.0, "no measurement found: the hoverfly's 0.13 body lengths "
                 "(L = 13 mm), the CG straight below the hinge", "estimate",
                 note="an analogy, not a honeybee measurement"),
        "wing_mass": _v(0.0053 * mass / 2.0, "no measurement found: the bumblebee's 2 m_w / m = "
                        "0.53 %", "estimate", low=0.0025 * mass / 2.0, high=0.01 * mass / 2.0,
                        note="an analogy, not a honeybee measurement"),
    }
    return Preset("honeybee", "Apis mellifera", "Altshuler et al.'s short, fast stroke; "
                  "morphology unverified", "Altshuler et al. 2005; Ellington 1984", values, {},
                  measured)


def _hoverfly_preset() -> Preset:
    mass, r = 1.45e-4, 11.2e-3
    sun = "Sun's group's model hoverfly (data from Dudley), second-hand"
    values = {
        "semi_span": _v(r, sun, "second-hand", "sun2007"),
        "wing_area": _v(r * 3.246e-3, sun + ": S = R c_bar, c_bar = 3.246 mm", "second-hand",
                        "sun2007"),
        **_r2_r1(0.534, sun, "second-hand", "sun2007"),
        "frequency": _v(164.0, "the drone fly of Wu & Sun (2012), quoted second-hand",
                        "unverified", "wu2012", low=150.0, high=180.0),
        "stroke_amplitude": _amplitude(54.0, "drone flies, ~108 deg peak-to-peak (Liu & Sun "
                                       "2008)", "unverified", "liu2008"),
        "mass": _v(mass, sun, "second-hand", "sun2007"),
        "pitch_inertia": _inertia(mass, *BODY_SIZES["hoverfly"],
                                  "L = 1.29 R second-hand, d estimated"),
    }
    extras = {
        "hinge_to_cg": _v(0.13 * 1.29 * r, sun + ": wing root to CG 0.13 body lengths; free "
                          "body angle 53.3 deg (the CG hangs below the wing base)",
                          "second-hand", "xu2015", "sun2007"),
    }
    measured = {
        **_hinge(0.13 * 1.29 * r, 90.0, sun + " (Xu & Sun 2015's model drone fly); in hover "
                 "the CG taken straight below the hinge, as when the body hangs freely",
                 "second-hand", "xu2015", "sun2007"),
        "wing_mass": _v(3.26e-7, sun + " (Xu & Sun 2015)", "second-hand", "xu2015", "sun2007",
                        low=0.8 * 3.26e-7, high=1.2 * 3.26e-7, note="+-20 %: not re-read here"),
    }
    return Preset("hoverfly", "Eristalis-type model hoverfly", "Sun's group's model hoverfly "
                  "(an Eristalis-type drone fly)", "Sun et al. 2007 (data from Dudley)",
                  values, extras, measured)


def _monarch_preset() -> Preset:
    values = {
        "semi_span": _v(60.997e-3, _FWUAV_MONARCH, "verified", "fwuav"),
        "wing_area": _v(1.2751313e-3, _FWUAV_MONARCH + " (measured planform)", "verified",
                        "fwuav"),
        "r1": _v(0.4976094, _FWUAV_MONARCH + " (measured planform)", "verified", "fwuav"),
        "r2": _v(0.5433245, _FWUAV_MONARCH + " (measured planform)", "verified", "fwuav"),
        "frequency": _v(11.721978, _FWUAV_HOVER + ": WK.f", "verified", "fwuav",
                        note="FWUAV's hover; its forward-flight measurement is 10.22 Hz"),
        "stroke_amplitude": _v(0.6072701, _FWUAV_HOVER + ": WK.phi_m", "verified", "fwuav",
                               note="FWUAV's hover (stroke plane tilted 17.5 deg); measured in "
                                    "forward flight: ~60 deg at 10.22 Hz, with which this model "
                                    "finds no hover orbit below 90 deg"),
        "mass": _v(3.079e-4, _FWUAV_MONARCH + ": thorax, abdomen and both wings", "verified",
                   "fwuav"),
        "pitch_inertia": _v(_monarch_pitch_inertia(), "FWUAV's thorax and abdomen about their "
                            "joint CG (arithmetic on verified data)", "estimate", "fwuav",
                            low=INERTIA_RANGE[0] * _monarch_pitch_inertia(),
                            high=INERTIA_RANGE[1] * _monarch_pitch_inertia(),
                            note="the thorax alone (a free abdomen) would give "
                                 + _inertia_text(_MONARCH_THORAX_IY)),
    }
    measured = {
        **_hinge(_fwuav_body_cg(1.485e-4, 1.092e-4, 7.315e-3, 8.69e-3), 17.513,
                 _FWUAV_MONARCH + "; stroke plane WK.beta of " + _FWUAV_HOVER, "estimate",
                 "fwuav", note="arithmetic on FWUAV's measured monarch, the abdomen straight"),
        "wing_mass": _v(2.51e-5, _FWUAV_MONARCH, "verified", "fwuav",
                        note="per wing, 8 % of the total"),
    }
    return Preset("monarch", "Danaus plexippus", "FWUAV's monarch: every number from its data "
                  "files", "FWUAV (fdcl-gwu)", values, {}, measured)


_BUILDERS: tuple[Callable[[], Preset], ...] = (
    _hawkmoth_preset, _bumblebee_preset, _fruit_fly_preset, _honeybee_preset, _hoverfly_preset,
    _monarch_preset,
)

#: The presets by name, in order of the table in the module docstring (read-only).
PRESETS: Mapping[str, Preset] = MappingProxyType({p.name: p for p in (b() for b in _BUILDERS)})


def preset_names() -> tuple[str, ...]:
    """The names of the presets, in the order of :data:`PRESETS`."""
    return tuple(PRESETS)


def preset(name: str, /, geometry: str = "paper", **overrides: Any) -> Insect:
    """The preset ``name`` as an :class:`Insect`, with some fields changed.

    Parameters
    ----------
    name : str
        One of :func:`preset_names` (positional: ``name=`` renames the insect).
    geometry : {"paper", "source"}
        The paper's geometry (hinge at the centre of gravity, massless wings; the default) or the
        sources' hinge position and wing mass (:attr:`Preset.measured`, estimated for the most
        part: each number's status says). ``"measured"``, the former name of ``"source"``, is
        deprecated.
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        If ``name`` is not a preset (the message lists them) or an override is out of range.

    Warns
    -----
    DeprecationWarning
        For ``geometry="measured"``, naming ``"source"``.
    """
    _validation.choice("name", name, tuple(PRESETS))
    return PRESETS[name].insect(_geometry(geometry, stacklevel=3), **overrides)


def _geometry(geometry: str, stacklevel: int = 3) -> str:
    """A geometry of :data:`GEOMETRIES`, its former name translated with a DeprecationWarning
    (at ``stacklevel``: the user's call), anything else refused naming the choices."""
    if isinstance(geometry, str) and geometry in DEPRECATED_GEOMETRIES:
        new = DEPRECATED_GEOMETRIES[geometry]
        warnings.warn(f"geometry={geometry!r} is deprecated: use geometry={new!r} (most of its "
                      "hinge positions are estimated, not measured)", DeprecationWarning,
                      stacklevel=stacklevel)
        return new
    return _validation.choice("geometry", geometry, GEOMETRIES)


def species_table() -> list[dict[str, Any]]:
    """One row per preset: name, species, mass [kg], wing length [m], frequency [Hz], source, and
    the sources' geometry (``geometry="source"``) with its sources and statuses.

    Returns
    -------
    list of dict
        Keys ``name``, ``species``, ``mass_kg``, ``wing_length_m`` (the semi-span R),
        ``frequency_hz``, ``source``, and ``measured_geometry`` (the key keeps its former name:
        the sources' geometry, mostly estimated): for each field of
        :attr:`Preset.measured`, keyed by the field and its unit (``hinge_offset_m``,
        ``hinge_height_m``, ``wing_mass_kg``), a dict of ``value``, ``source``, ``status``,
        ``cite`` and ``low``/``high`` (None without a range).
    """
    units = {"hinge_offset": "m", "hinge_height": "m", "wing_mass": "kg"}
    return [{"name": p.name, "species": p.species, "mass_kg": p.mass,
             "wing_length_m": p.semi_span, "frequency_hz": p.frequency, "source": p.source,
             "measured_geometry": {
                 f"{k}_{units.get(k, 'si')}": {"value": v.value, "source": v.source,
                                               "status": v.status, "cite": list(v.cite),
                                               "low": v.low, "high": v.high}
                 for k, v in p.measured.items()}}
            for p in PRESETS.values()]


# =========================================================================== the functions
def bumblebee(**overrides: Any) -> Insect:
    """A hovering bumblebee (*Bombus*): Berman & Wang's morphology at Sun & Xiong's wingbeat.

    m = 175 mg, R = 13.2 mm, c_bar = 4.02 mm (S = R c_bar = 53.06 mm^2): Berman & Wang (2007),
    read in FWUAV's ``morp_params.mat`` (verified); Sun & Xiong (2005a) use the same 175 mg.
    f = 156.25 Hz = 1 / 6.4 ms: Sun & Xiong's abstract (verified). Berman & Wang give 116 Hz
    (verified); we take Sun & Xiong's because theirs is the stability result we compare with, and
    their bee (Dudley & Ellington's BB01) is also the source of Phi and r2; use
    ``bumblebee(frequency=116.0)`` for the other. r2 = 0.55 (Dudley & Ellington 1990,
    UNVERIFIED); r1 = 0.489 by Ellington's fit (ESTIMATE, :func:`ellington_r1`).
    Phi = 58 deg nominal (116 deg peak-to-peak, Dudley & Ellington 1990, UNVERIFIED).
    I_y = 3.26e-9 kg m^2: ellipsoid, L = 18 mm (UNVERIFIED), d = 7 mm (ESTIMATE).

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect
    """
    return PRESETS["bumblebee"].insect(**overrides)


def fruit_fly(**overrides: Any) -> Insect:
    """A hovering fruit fly (*Drosophila*), after Berman & Wang (2007).

    m = 0.72 mg, R = 2.02 mm, c_bar = 0.67 mm (S = 1.353 mm^2), f = 254 Hz: Berman & Wang, read in
    FWUAV's ``morp_params.mat`` (verified). r2 = 0.58 (typical, UNVERIFIED); r1 = 0.525 by
    Ellington's fit (ESTIMATE). Phi = 70 deg nominal (UNVERIFIED; FWUAV's quasi-steady hover:
    66.5 deg at 285 Hz). I_y = 2.54e-13 kg m^2: ellipsoid, L = 2.5 mm, d = 0.9 mm (ESTIMATE).

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect
    """
    return PRESETS["fruit_fly"].insect(**overrides)


def honeybee(**overrides: Any) -> Insect:
    """A hovering honeybee (*Apis mellifera*): Altshuler et al.'s short, fast stroke.

    f = 230 Hz and a ~90 deg stroke (read as peak-to-peak: Phi = 45 deg): Altshuler et al. (2005)
    abstract (verified; Vance et al. 2014: 226.8 Hz, 86.7 deg). The morphology is UNVERIFIED
    (memory of Ellington 1984): m = 100 mg (80-120), R = 9.7 mm, S = 29 mm^2 (fore- and hindwing
    coupled), r2 = 0.55; r1 = 0.489 by Ellington's fit (ESTIMATE); I_y = 9.46e-10 kg m^2:
    ellipsoid, L = 13 mm (UNVERIFIED), d = 4.5 mm (ESTIMATE).

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect
    """
    return PRESETS["honeybee"].insect(**overrides)


def hoverfly(**overrides: Any) -> Insect:
    """Sun's group's model hoverfly (an *Eristalis*-type drone fly; data from Dudley).

    m = 145 mg, R = 11.2 mm, c_bar = 3.246 mm (S = 36.36 mm^2), r2 = 0.534, body length 1.29 R,
    wing root 0.13 body lengths from the CG, wing mass 0.326 mg: second-hand (quoted from Sun's
    group by the project's reading notes). r1 = 0.469 by Ellington's fit (ESTIMATE).
    f = 164 Hz (Wu & Sun's 2012 drone fly, quoted second-hand, UNVERIFIED) and Phi = 54 deg
    nominal (drone flies, Liu & Sun 2008, UNVERIFIED). I_y = 1.70e-9 kg m^2: ellipsoid,
    L = 14.45 mm, d = 5 mm (ESTIMATE). Wu & Sun's drone fly itself is a different data set.

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect
    """
    return PRESETS["hoverfly"].insect(**overrides)


def monarch(**overrides: Any) -> Insect:
    """The monarch butterfly (*Danaus plexippus*) of FWUAV: every number from its data files.

    m = 307.9 mg (thorax 148.5, abdomen 109.2, wings 2 x 25.1), R = 60.997 mm, S = 1275.1 mm^2,
    r1 = 0.4976, r2 = 0.5433 (measured planform): FWUAV ``morp_MONARCH.m`` (verified).
    f = 11.72 Hz, Phi = 34.8 deg: FWUAV's quasi-steady hover, the one of its Floquet exponents
    (``other_insects/sim_QS_x_hover_mona.mat``, commit 1a25d41, verified). Its forward-flight
    measurement (~60 deg at 10.22 Hz) gives no hover orbit below 90 deg in this model; at 10.22 Hz
    with FWUAV's amplitude the default guess fails and
    :func:`flapping.studies.atlas.hover_by_homotopy` finds the orbit.
    I_y = 2.19e-8 kg m^2: FWUAV's thorax and abdomen as one rigid body about their joint centre
    of gravity (ESTIMATE: arithmetic on verified data). The lowest frequency of the atlas, where
    averaging is worst; the body pitches ~ +-30 deg per wingbeat in this model, far outside the
    small-perturbation loads of eq. (29): read its numbers as the model's, not the butterfly's.

    Parameters
    ----------
    **overrides
        Any :class:`Insect` field, in SI units.

    Returns
    -------
    Insect
    """
    return PRESETS["monarch"].insect(**overrides)

"""Our model at FWUAV's morphology, the pitch free: which difference turns the mode type (issue 28).

FWUAV's multibody hawkmoth with the thorax pitch free
(:func:`flapping.peers.fwuav.pitch_free_floquet`) is unstable through an oscillatory mode;
our one-body model at FWUAV's frequency and amplitude but with our preset's body is unstable
through a real multiplier. This module puts our model on FWUAV's morphology and asks which
difference decides the type:

1. :func:`fwuav_translation` (and :func:`fwuav_insect`, its insect alone): FWUAV's insect as our
   :class:`~flapping.model.morphology.Insect`, every field with its status (``"taken"`` as
   stored, ``"derived"`` from stored numbers by a stated computation, ``"approximated"`` where
   our model has a simpler form), and what our model cannot represent, with its size.
2. :func:`compare_fwuav`: our hover orbit of that insect (trimmed as
   :func:`flapping.studies.cfd.compare` trims: stroke amplitude and mean stroke angle), its
   Floquet multipliers and cycle-averaged derivatives in Sun's non-dimensional form
   (:mod:`flapping.studies.cfd`), beside FWUAV's pitch-free model's cycle-averaged derivatives
   (central differences of its right-hand side along its pitch-free orbit, averaged over the
   wingbeat) in the same form.
3. :func:`fwuav_swap_table` (our averaged system with FWUAV's terms swapped in, one at a time and
   in groups, and the reverse) and :func:`fwuav_physics_table` (one physics at a time moved from
   ours toward FWUAV's, alone and accumulated).

Frames. FWUAV's thorax frame has x forward along the body, z down; the stroke plane's normal is
``Ry(beta) e1`` in it (``Q_R = Ry(beta) Rx(phi) ...``), so our body axes (x in the stroke plane,
forward; z down, normal to it) are the columns of ``Ry(beta - pi/2)``: a vector ``d`` of the
thorax frame is ``Ry(pi/2 - beta) d`` in ours, whatever the thorax pitch. The thorax's x axis is
``pi/2 - beta`` nose up from the stroke plane (the body angle), and the stroke plane is inclined
``theta_B0 + beta - pi/2`` from the horizontal at FWUAV's hover posture; ours is horizontal.

FWUAV's state is ``(theta, v_1, v_3, q)`` with inertial velocities. Its averaged Jacobian is
taken in those coordinates and rotated (a constant change of coordinates: the modes do not
change) into axes along and normal to the mean stroke plane of its pitch-free orbit, ordered
``(u, w, q, theta)`` as ours. Body-axis and inertial-axis linearisations differ by terms of
the orbit's velocity (its drift, if it drifts, and its swing within the wingbeat) and of its
pitch swing about the mean, times the pitch perturbation; that difference is not removed (on a
re-trimmed hover there is no drift, and the swings are small).

Both sets of derivatives are non-dimensionalised with one reference: FWUAV's kinematics
(U = 2 Phi n r2 R with Phi = 2 phi_m peak to peak, T = 1/n, c = S/R, S = 2 R c) and the
translated insect's m and I_y. Swapping a derivative is then swapping an entry of A+.
"""

from __future__ import annotations

import json
import math
import sys
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy.integrate import quad, solve_ivp
from scipy.optimize import brentq

from flapping import _validation
from flapping._numdiff import central_jacobian
from flapping.errors import require_success
from flapping.hover import HoverOrbit, find_hover_orbit
from flapping.hover.stability import HoverStability, hover_stability
from flapping.model.morphology import Insect, lev_lift_slope
from flapping.peers.fwuav import (
    FwuavPitchFree,
    PitchFreeFloquet,
    pitch_free_floquet,
    pitch_free_model,
)
from flapping.peers.fwuav.attitude import _shift_to_centre
from flapping.peers.fwuav.data import Species, species
from flapping.peers.fwuav.model import _rot, prescribed_motion, wing_angles
from flapping.studies._modes import DERIVATIVES, SWAP_GROUPS, mode_summary

if TYPE_CHECKING:  # pandas is the optional ``sweep`` extra, imported when a table is built
    import pandas

__all__ = [
    "PITCH_FREE_CASES",
    "pitch_free_case",
    "pitch_free_to_json",
    "pitch_free_from_json",
    "write_pitch_free_study",
    "load_pitch_free_study",
    "DERIVATIVES",
    "SWAP_GROUPS",
    "mode_summary",
    "FWUAV_NAMES",
    "WINGS",
    "STATUSES",
    "FwuavTranslation",
    "fwuav_translation",
    "fwuav_insect",
    "Reference",
    "FwuavComparison",
    "compare_fwuav",
    "fwuav_averaged_jacobian",
    "fwuav_swap_table",
    "fwuav_physics_table",
]

#: FWUAV's insects with Sane & Dickinson's coefficients (the pitch-free model takes these).
FWUAV_NAMES: tuple[str, ...] = ("hawkmoth", "bumblebee", "fruit_fly")
#: How FWUAV's wings enter our insect: our wing-inertia model (``wing_mass``), or lumped into the
#: body at their mean over a wingbeat (massless wings, their mass and pitch inertia in the body's).
WINGS: tuple[str, ...] = ("inertia", "lumped")
#: Statuses of a translated field.
STATUSES: tuple[str, ...] = ("taken", "derived", "approximated", "ours")

_N_POSTURE = 256  # samples of a wingbeat for the wings' mean posture (smooth periodic: spectral)


# =========================================================================== translation
@dataclass(frozen=True)
class FwuavTranslation:
    """FWUAV's insect as ours (:func:`fwuav_translation`).

    Attributes
    ----------
    name : str
        FWUAV's insect.
    wings : {"inertia", "lumped"}
        How the wings enter (:data:`WINGS`).
    insect : Insect
        Ours, SI.
    alpha_m : float
        FWUAV's geometric angle of attack at mid-stroke, the mean of the two half-strokes
        [rad]: our ``alpha_m`` (constant within a half-stroke in ours).
    stroke_mean : float
        FWUAV's mean stroke angle ``phi_0`` [rad] (positive forward, as ours); our hover solve
        trims its own.
    body_angle : float
        The thorax's x axis above the stroke plane, ``pi/2 - beta`` [rad].
    stroke_plane_inclination : float
        The stroke plane's inclination from the horizontal at FWUAV's hover posture,
        ``theta_B0 + beta - pi/2`` [rad] (ours: 0).
    centre_of_mass : ndarray, shape (3,)
        The centre of mass our insect's ``mass`` and ``pitch_inertia`` refer to, from the
        thorax's, thorax frame [m] (of thorax and abdomen with ``wings="inertia"``, of all four
        bodies at their mean with ``"lumped"``).
    rows : tuple of mapping
        One per field: ``field``, ``value`` (SI), ``unit``, ``status`` (:data:`STATUSES`),
        ``how``.
    not_represented : tuple of mapping
        What our model cannot take: ``what``, ``size`` (a number), ``unit``, ``note``.
    """

    name: str
    wings: str
    insect: Insect
    alpha_m: float
    stroke_mean: float
    body_angle: float
    stroke_plane_inclination: float
    centre_of_mass: np.ndarray
    rows: tuple[Mapping[str, Any], ...]
    not_represented: tuple[Mapping[str, Any], ...]

    def table(self) -> pandas.DataFrame:
        """:attr:`rows` as a DataFrame indexed by field."""
        import pandas

        return pandas.DataFrame(list(self.rows)).set_index("field")

    def gaps(self) -> pandas.DataFrame:
        """:attr:`not_represented` as a DataFrame."""
        import pandas

        return pandas.DataFrame(list(self.not_represented))


def _chord(sp: Species, r: float) -> float:
    m = sp.morphology
    return float(np.polyval(np.array(m.chord_poly), r / m.scale) * m.scale)


def _area_radii(sp: Species) -> tuple[float, float, float]:
    """(area, r1, r2) of one wing from FWUAV's chord polynomial (Ellington's radii over R)."""
    R = sp.morphology.span
    moment = [quad(lambda r, k=k: _chord(sp, r) * r ** k, 0.0, R, limit=200)[0]
              for k in range(3)]
    return moment[0], moment[1] / (moment[0] * R), math.sqrt(moment[2] / (moment[0] * R ** 2))


def _wing_mean(sp: Species) -> tuple[np.ndarray, float, np.ndarray]:
    """Right wing over a wingbeat: mean centre of mass (thorax frame), mean pitch inertia about
    its own centre of mass, and the centre of mass at each sample (3, N)."""
    m = sp.morphology
    nu = np.array(m.nu_R)
    Jc = _shift_to_centre(np.array(m.J_R).reshape(3, 3), m.m_wing, nu)
    T = 1.0 / sp.kinematics.f
    pos, iyy = [], []
    for t in np.arange(_N_POSTURE) * T / _N_POSTURE:
        Q = prescribed_motion(sp, float(t)).Q_R
        pos.append(np.array(m.mu_R) + Q @ nu)
        iyy.append(float((Q @ Jc @ Q.T)[1, 1]))
    p = np.array(pos).T
    return p.mean(axis=1), float(np.mean(iyy)), p


def _mid_stroke_alpha(sp: Species) -> float:
    """Mean over the two half-strokes of the geometric angle of attack at mid-stroke [rad].

    The flapping angle passes its mean at ``w t = pi/2, 3 pi/2``; there the chord, normal to the
    stroke plane at wing pitch ``theta = 0``, meets the stroke plane at ``pi/2 - |theta|``.
    """
    k = sp.kinematics
    period = 1.0 / k.f
    thetas = [wing_angles(k, t)[0, 1] for t in (0.25 * period, 0.75 * period)]
    return float(np.mean([0.5 * math.pi - abs(theta) for theta in thetas]))


def fwuav_translation(name: str = "hawkmoth", wings: str = "inertia") -> FwuavTranslation:
    """FWUAV's insect as our :class:`~flapping.model.morphology.Insect`, field by field.

    Mass: the four bodies' (taken). Centre of mass and pitch inertia (derived): thorax and
    abdomen at the abdomen's mean angle ``theta_A0`` (its oscillation is not represented); the
    wings either as our wing-inertia model (``wings="inertia"``: ``wing_mass`` and its radii from
    FWUAV's wing centre of mass and inertia about the root; the body's centre of mass and
    inertia are those of thorax and abdomen, as our model's ``pitch_inertia`` is the body's
    without the wings) or lumped (``"lumped"``: massless wings; their mass at its mean position
    over a wingbeat and their mean pitch inertia added to the body's). Hinge height and offset
    (derived): FWUAV's wing root from that centre of mass in our stroke-plane axes (module
    docstring). Wing (derived): span and area taken, r1 and r2 from FWUAV's chord polynomial
    (ours is Ellington's beta distribution with those radii: approximated). Kinematics:
    frequency and flapping amplitude ``phi_m`` taken (FWUAV's stroke is not quite harmonic,
    ``phi_K``); our ``alpha_m`` is FWUAV's mid-stroke angle of attack (approximated: ours flips
    at reversal, FWUAV's rotates over a tanh profile). Our loads' own constants (lift slope,
    centre of pressure, rotational terms) stay ours (status ``"ours"``).

    Parameters
    ----------
    name : {"hawkmoth", "bumblebee", "fruit_fly"}
    wings : {"inertia", "lumped"}

    Returns
    -------
    FwuavTranslation

    Raises
    ------
    ValueError
        For a name not in :data:`FWUAV_NAMES` or ``wings`` not in :data:`WINGS`.
    """
    _validation.choice("name", name, FWUAV_NAMES)
    _validation.choice("wings", wings, WINGS)
    sp = species(name)
    m, k = sp.morphology, sp.kinematics
    area, r1, r2 = _area_radii(sp)
    cg, inertia = _body(sp, wings)
    d = _rot(1, 0.5 * math.pi - k.beta) @ (np.array(m.mu_R) * np.array([1.0, 0.0, 1.0]) - cg)
    alpha_m = _mid_stroke_alpha(sp)
    wing_mass = m.m_wing if wings == "inertia" else 0.0
    J_R = np.array(m.J_R).reshape(3, 3)
    mass_r1 = float(m.nu_R[1]) / m.span
    mass_r2 = math.sqrt(J_R[0, 0] / m.m_wing) / m.span
    extra: dict[str, Any] = ({"wing_mass": wing_mass, "wing_mass_r1": mass_r1,
                              "wing_mass_r2": mass_r2} if wings == "inertia" else {})
    insect = Insect(
        name=f"{name} (FWUAV morphology, wings {wings})", semi_span=m.span, wing_area=area,
        r1=r1, r2=r2, frequency=k.f, stroke_amplitude=k.phi_m, mass=m.mass,
        pitch_inertia=inertia, air_density=m.rho, gravity=m.g, hinge_offset=float(d[0]),
        hinge_height=float(-d[2]), stroke_mean=k.phi_0, **extra)
    rows = _rows(sp, insect, wings, alpha_m)
    gamma = k.theta_B_0 + k.beta - 0.5 * math.pi
    return FwuavTranslation(name, wings, insect, alpha_m, k.phi_0, 0.5 * math.pi - k.beta, gamma,
                            cg, tuple(MappingProxyType(r) for r in rows),
                            tuple(MappingProxyType(g) for g in _gaps(sp, insect, alpha_m)))


def _body(sp: Species, wings: str) -> tuple[np.ndarray, float]:
    """Centre of mass (thorax frame) and pitch inertia about it of thorax and abdomen, and of
    the wings' wingbeat mean if ``wings == "lumped"``."""
    m, k = sp.morphology, sp.kinematics
    nu_A = np.array(m.nu_A)
    p_A = np.array(m.mu_A) + _rot(1, k.theta_A_0) @ nu_A
    iyy_A = float(_shift_to_centre(np.array(m.J_A).reshape(3, 3), m.m_A, nu_A)[1, 1])
    bodies = [(m.m_B, np.zeros(3), float(np.array(m.J_B).reshape(3, 3)[1, 1])),
              (m.m_A, p_A, iyy_A)]
    wing_p, wing_iyy, _ = _wing_mean(sp)
    if wings == "lumped":
        mirror = np.array([1.0, -1.0, 1.0])
        bodies += [(m.m_wing, wing_p, wing_iyy), (m.m_wing, wing_p * mirror, wing_iyy)]
    mass_in = sum(b[0] for b in bodies)
    cg = sum((b[0] * b[1] for b in bodies), np.zeros(3)) / mass_in
    inertia = sum(b[2] + b[0] * ((b[1][0] - cg[0]) ** 2 + (b[1][2] - cg[2]) ** 2)
                  for b in bodies)
    if wings == "lumped":  # the wings' own positions vary over the stroke: their mean square
        _, _, p = _wing_mean(sp)
        spread = float(np.mean((p[0] - wing_p[0]) ** 2 + (p[2] - wing_p[2]) ** 2))
        inertia += 2.0 * m.m_wing * spread
    return cg, float(inertia)


def _rows(sp: Species, insect: Insect, wings: str, alpha_m: float) -> list[dict[str, Any]]:
    """The translation's table (:attr:`FwuavTranslation.rows`)."""
    m, k = sp.morphology, sp.kinematics
    area, r1, r2 = insect.wing_area, insect.r1, insect.r2
    inertia, d0, height = insect.pitch_inertia, insect.hinge_offset, insect.hinge_height
    wing_mass = insect.wing_mass
    mass_r1, mass_r2 = insect.wing_mass_r1, insect.wing_mass_r2
    return [
        _row("semi_span", m.span, "m", "taken", "INSECT.l"),
        _row("wing_area", area, "m^2", "derived",
             f"integral of FWUAV's chord polynomial (INSECT.S = {m.area:.6g})"),
        _row("r1", r1, "", "derived", "first area moment of the chord polynomial; our chord is "
             "Ellington's beta distribution with these r1, r2 (approximated shape)"),
        _row("r2", r2, "", "derived", "second area moment of the chord polynomial"),
        _row("frequency", k.f, "Hz", "taken", "WK.f"),
        _row("stroke_amplitude", k.phi_m, "rad", "taken",
             f"WK.phi_m (FWUAV's stroke shape phi_K = {k.phi_K:.3f}, ours harmonic); our "
             "hover solve trims it"),
        _row("stroke_mean", k.phi_0, "rad", "taken", "WK.phi_0 (positive forward); our hover "
             "solve trims it"),
        _row("mass", m.mass, "kg", "taken", "m_B + m_A + 2 m_R"),
        _row("pitch_inertia", inertia, "kg m^2", "derived",
             "J_B + J_A (about its centre of mass) + parallel axes, abdomen at theta_A0"
             + (", wings' mean over a wingbeat lumped in" if wings == "lumped"
                else " (without the wings: our wing-inertia model carries them)")),
        _row("hinge_offset", d0, "m", "derived",
             "wing root ahead of the centre of mass along the stroke plane"),
        _row("hinge_height", height, "m", "derived",
             "wing root above the centre of mass, normal to the stroke plane"),
        _row("wing_mass", wing_mass, "kg", "taken" if wings == "inertia" else "approximated",
             "INSECT.m_R" if wings == "inertia" else "0: lumped into the body"),
        _row("wing_mass_r1", math.nan if mass_r1 is None else mass_r1, "", "derived",
             "nu_R (span component) / l"),
        _row("wing_mass_r2", math.nan if mass_r2 is None else mass_r2, "", "derived",
             "sqrt(J_R[x, x] / m_R) / l (about the root)"),
        _row("alpha_m", alpha_m, "rad", "approximated",
             "pi/2 - |wing pitch| at mid-stroke, mean of the half-strokes (a hover option)"),
        _row("air_density", m.rho, "kg/m^3", "taken", "INSECT.rho"),
        _row("gravity", m.g, "m/s^2", "taken", "INSECT.g"),
        _row("lift_slope", insect.lift_slope, "", "ours",
             f"C_L = A sin 2a, C_D = 2 A sin^2 a; FWUAV's C_L = {m.C_T} sin 2a, "
             f"C_D = {m.C_D_0} cos^2 a + {m.C_D_pi2} sin^2 a"),
        _row("center_of_pressure", insect.center_of_pressure, "", "ours",
             "FWUAV's loads act on the span axis (x_hat = 0)"),
        _row("mu1, mu2, pitch_axis", insect.mu1, "", "ours",
             "rotational damping and rotational lift: FWUAV has neither"),
    ]


def _gaps(sp: Species, insect: Insect, alpha_m: float) -> tuple[dict[str, Any], ...]:
    """What our model cannot represent (:attr:`FwuavTranslation.not_represented`)."""
    m, k = sp.morphology, sp.kinematics
    nu_A = np.array(m.nu_A)
    gamma = k.theta_B_0 + k.beta - 0.5 * math.pi
    cl_ours = insect.lift_slope * math.sin(2 * alpha_m)
    cl_fw = float(m.C_T) * math.sin(2 * alpha_m)  # type: ignore[arg-type]
    cd_ours = 2 * insect.lift_slope * math.sin(alpha_m) ** 2
    cd_fw = (float(m.C_D_0) * math.cos(alpha_m) ** 2  # type: ignore[arg-type]
             + float(m.C_D_pi2) * math.sin(alpha_m) ** 2)  # type: ignore[arg-type]
    return (
        _gap("stroke-plane inclination at hover", math.degrees(gamma), "deg",
             "ours horizontal at hover"),
        _gap("wing deviation amplitude psi_m", math.degrees(k.psi_m), "deg", "ours none"),
        _gap("wing rotation profile theta_C", k.theta_C, "",
             "tanh profile; ours flips at reversal"),
        _gap("thorax pitch oscillation theta_B_m", math.degrees(k.theta_B_m), "deg",
             "FWUAV's prescribed hover; free in both pitch-free analyses"),
        _gap("abdomen oscillation theta_A_m", math.degrees(k.theta_A_m), "deg",
             "ours one rigid body: abdomen frozen at theta_A0"),
        _gap("centre-of-mass motion from the abdomen", 1e3 * m.m_A * float(np.linalg.norm(nu_A))
             * k.theta_A_m / m.mass, "mm", "amplitude, m_A |nu_A| theta_A_m / m"),
        _gap("wing root lateral offset", 1e3 * m.mu_R[1], "mm", "ours on the plane of symmetry"),
        _gap("lift coefficient at alpha_m, ours / FWUAV's", cl_ours / cl_fw, "",
             "A sin 2a against C_T sin 2a"),
        _gap("drag coefficient at alpha_m, ours / FWUAV's", cd_ours / cd_fw, "",
             "2 A sin^2 a against C_D_0 cos^2 a + C_D_pi2 sin^2 a"),
    )


def _row(name: str, value: float, unit: str, status: str, how: str) -> dict[str, Any]:
    return {"field": name, "value": float(value), "unit": unit, "status": status, "how": how}


def _gap(what: str, size: float, unit: str, note: str) -> dict[str, Any]:
    return {"what": what, "size": float(size), "unit": unit, "note": note}


def fwuav_insect(name: str = "hawkmoth", wings: str = "inertia") -> Insect:
    """FWUAV's insect as our :class:`~flapping.model.morphology.Insect` (SI).

    The insect of :func:`fwuav_translation`, which also returns each field's status and what
    our model cannot represent.

    Parameters
    ----------
    name : {"hawkmoth", "bumblebee", "fruit_fly"}
    wings : {"inertia", "lumped"}

    Returns
    -------
    Insect
    """
    return fwuav_translation(name, wings).insect


# =========================================================================== comparison
@dataclass(frozen=True)
class Reference:
    """Sun's non-dimensional form at FWUAV's kinematics (module docstring of
    :mod:`flapping.studies.cfd`).

    Attributes
    ----------
    speed, period, chord, area : float
        U = 2 Phi n r2 R [m/s] (Phi = 2 phi_m), T = 1/n [s], c = S/R [m], S = 2 R c [m^2].
    mass_ratio, inertia_ratio : float
        m+ and I+ of the translated insect's m and I_y.
    """

    speed: float
    period: float
    chord: float
    area: float
    mass_ratio: float
    inertia_ratio: float

    @classmethod
    def of(cls, translation: FwuavTranslation) -> Reference:
        """The reference of a translation."""
        i = translation.insect
        k = species(translation.name).kinematics
        U = 2.0 * (2.0 * k.phi_m) * k.f * i.r2 * i.semi_span
        T, c = 1.0 / k.f, i.wing_area / i.semi_span
        S = 2.0 * i.semi_span * c
        q = 0.5 * i.air_density
        return cls(U, T, c, S, i.mass / (q * U * S * T),
                   i.pitch_inertia / (q * U ** 2 * S * c * T ** 2))

    def nondimensional(self, jacobian: np.ndarray) -> np.ndarray:
        """A+ = T D^-1 J D of a dimensional (u, w, q, theta) Jacobian, D = diag(U, U, 1/T, 1)."""
        d = np.diag([self.speed, self.speed, 1.0 / self.period, 1.0])
        return self.period * np.linalg.solve(d, np.asarray(jacobian, dtype=float)) @ d

    def derivatives(self, a_plus: np.ndarray) -> np.ndarray:
        """X_u+ ... M_q+ (:data:`~flapping.studies.cfd.DERIVATIVES`) of A+."""
        block = np.array(a_plus[:3, :3], dtype=float)
        block[:2] *= self.mass_ratio
        block[2] *= self.inertia_ratio
        return block.reshape(-1)


def fwuav_averaged_jacobian(model: FwuavPitchFree, y0: Sequence[float] | np.ndarray,
                            n_average: int = 64, rtol: float = 1e-9
                            ) -> tuple[np.ndarray, float]:
    """FWUAV's pitch-free model's Jacobian averaged over a wingbeat along its orbit.

    Central differences of its right-hand side of ``(theta, v_1, v_3, q)`` at ``n_average``
    equally spaced instants of the orbit from ``y0`` (the rectangle rule; the strip loads have
    kinks where a strip's velocity components change sign, so it converges algebraically: on the
    hawkmoth the change from 32 to 64 instants is 6e-5 of the largest entry, from 64 to 128
    2e-6), rotated into axes along and normal to the orbit's mean
    stroke plane and ordered ``(u, w, q, theta)`` (module docstring).

    Parameters
    ----------
    model : FwuavPitchFree
        With ``pitch="free"``.
    y0 : sequence of 4 floats
        ``(theta, v_1, v_3, q)`` at ``t = 0`` on the orbit.
    n_average : int
        Instants, in [8, 4096].
    rtol : float
        Of the integration along the orbit, in [1e-12, 1e-6].

    Returns
    -------
    jacobian : ndarray, shape (4, 4)
        [1/s and SI], in (u, w, q, theta).
    inclination : float
        The mean stroke plane's inclination from the horizontal [rad] (the rotation used).
    """
    _validation.instance("model", model, FwuavPitchFree)
    if model.pitch != "free":
        raise ValueError(f"`model` must have pitch='free'; got {model.pitch!r}")
    y0 = _validation.vector("y0", y0, size=4)
    n = _validation.integer("n_average", n_average, low=8, high=4096)
    rtol = _validation.real("rtol", rtol, low=1e-12, high=1e-6)

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        return model.rhs(t, np.concatenate([[0.0, 0.0], y]))[2:]

    T = model.period
    ts = np.arange(n) * T / n
    sol = solve_ivp(fun, (0.0, T), y0, t_eval=ts, rtol=rtol, atol=0.1 * rtol, method="DOP853")
    require_success(sol, "the integration along FWUAV's pitch-free orbit")

    def at(t: float, y: np.ndarray) -> np.ndarray:
        return central_jacobian(lambda z: fun(t, z), y)

    jac = np.mean([at(float(t), y) for t, y in zip(ts, sol.y.T, strict=True)], axis=0)
    gamma = float(np.mean(sol.y[0])) + model.species.kinematics.beta - 0.5 * math.pi
    c, s = math.cos(gamma), math.sin(gamma)
    P = np.array([[0.0, c, -s, 0.0], [0.0, s, c, 0.0], [0.0, 0.0, 0.0, 1.0],
                  [1.0, 0.0, 0.0, 0.0]])
    return P @ jac @ np.linalg.inv(P), gamma


@dataclass(frozen=True)
class FwuavComparison:
    """Our model at FWUAV's morphology beside FWUAV's pitch-free model (:func:`compare_fwuav`).

    Attributes
    ----------
    translation : FwuavTranslation
    orbit : HoverOrbit
        Ours, trimmed in stroke amplitude and mean stroke angle at ``translation.alpha_m``.
    stability : HoverStability
    floquet : PitchFreeFloquet
        FWUAV's pitch-free orbit and multipliers.
    fwuav_jacobian : ndarray, shape (4, 4)
        FWUAV's averaged Jacobian in (u, w, q, theta) (:func:`fwuav_averaged_jacobian`).
    reference : Reference
    our_matrix, fwuav_matrix : ndarray, shape (4, 4)
        A+ of each.
    base_matrix : ndarray, shape (4, 4)
        A+ of ours at FWUAV's morphology with the hinge at the centre of mass, massless wings
        and eq. (40)'s angle of attack (the base of :func:`fwuav_physics_table`: a real mode).
    table : pandas.DataFrame
        Index :data:`~flapping.studies.cfd.DERIVATIVES`; columns ``ours``, ``fwuav``,
        ``ratio``.
    modes : pandas.DataFrame
        Rows ``ours Floquet``, ``ours averaged``, ``FWUAV Floquet``, ``FWUAV averaged``;
        columns of :func:`~flapping.studies.cfd.mode_summary` and ``leading`` (the eigenvalue or
        exponent [1/s], complex).
    trim : dict of str to float
        ``our_stroke_amplitude_deg``, ``fwuav_stroke_amplitude_deg`` (half peak to peak),
        ``our_stroke_mean_deg``, ``fwuav_stroke_mean_deg``.
    """

    translation: FwuavTranslation
    orbit: HoverOrbit
    stability: HoverStability
    floquet: PitchFreeFloquet
    fwuav_jacobian: np.ndarray
    reference: Reference
    our_matrix: np.ndarray
    fwuav_matrix: np.ndarray
    base_matrix: np.ndarray
    table: pandas.DataFrame
    modes: pandas.DataFrame
    trim: Mapping[str, float] = field(default_factory=dict)


def _solve(insect: Insect, alpha_m: float | None, guess: HoverOrbit | None = None,
           **hover_options: Any) -> tuple[HoverOrbit, HoverStability]:
    """Our hover orbit trimmed in stroke amplitude and mean stroke angle (``alpha_m`` None:
    eq. 40's)."""
    # Both trims always: FWUAV's mean stroke angle is not zero, so even with the hinge at the
    # centre of mass the amplitude alone would leave an orbit that drifts.
    options: dict[str, Any] = {"trims": ("amplitude", "stroke_mean"), "alpha_m": alpha_m,
                               **hover_options}
    if guess is not None:
        options.setdefault("x0_guess", np.asarray(guess.x0).tolist())
        options.setdefault("amplitude_guess", guess.amplitude)
        insect = insect.with_(stroke_mean=guess.stroke_mean)
    orbit = find_hover_orbit(insect, **options)
    return orbit, hover_stability(orbit)


def _lead(values: np.ndarray) -> complex:
    v = np.asarray(values, dtype=complex)
    return complex(v[np.argmax(v.real)])


def compare_fwuav(name: str = "hawkmoth", wings: str = "inertia", *,
                  floquet: PitchFreeFloquet | None = None, n_average: int = 64,
                  **hover_options: Any) -> FwuavComparison:
    """Our model at FWUAV's morphology, pitch free, beside FWUAV's pitch-free model.

    Parameters
    ----------
    name : {"hawkmoth", "bumblebee", "fruit_fly"}
    wings : {"inertia", "lumped"}
        :func:`fwuav_translation`.
    floquet : PitchFreeFloquet, optional
        FWUAV's pitch-free result for ``name``, on FWUAV's kinematics or re-trimmed (its own
        kinematics are used: :func:`~flapping.peers.fwuav.attitude.pitch_free_model`); default
        :func:`~flapping.peers.fwuav.pitch_free_floquet` at ``rtol=1e-8``.
    n_average : int
        Instants of FWUAV's averaging, in [8, 4096].
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    FwuavComparison

    Raises
    ------
    ValueError
        For bad arguments, or a ``floquet`` of another insect.
    ConvergenceError
        If our hover orbit or FWUAV's cannot be found.
    """
    import pandas

    tr = fwuav_translation(name, wings)
    if floquet is None:
        floquet = pitch_free_floquet(name, rtol=1e-8)
    _validation.instance("floquet", floquet, PitchFreeFloquet)
    if floquet.name != name:
        raise ValueError(f"`floquet` must be of {name!r}; got one of {floquet.name!r}")
    orbit, stab = _solve(tr.insect, tr.alpha_m, **hover_options)
    model = pitch_free_model(floquet)  # FWUAV's kinematics, or the re-trimmed ones
    fj, _ = fwuav_averaged_jacobian(model, floquet.y0, n_average)
    ref = Reference.of(tr)
    ours_a, fw_a = ref.nondimensional(stab.averaged_jacobian), ref.nondimensional(fj)
    _, base = _solve(_physics_base(tr), None, orbit, **hover_options)
    base_a = ref.nondimensional(base.averaged_jacobian)
    ours, theirs = ref.derivatives(ours_a), ref.derivatives(fw_a)
    table = pandas.DataFrame({"ours": ours, "fwuav": theirs, "ratio": ours / theirs},
                             index=pandas.Index(DERIVATIVES, name="derivative"))
    rows = []
    for label, values in (("ours Floquet", stab.exponents),
                          ("ours averaged", stab.averaged_eigenvalues),
                          ("FWUAV Floquet", floquet.exponents),
                          ("FWUAV averaged", np.linalg.eigvals(fj))):
        rows.append({"model": label, **mode_summary(values), "leading": _lead(values)})
    modes = pandas.DataFrame(rows).set_index("model")
    k = model.species.kinematics
    trim = {"our_stroke_amplitude_deg": math.degrees(orbit.amplitude),
            "fwuav_stroke_amplitude_deg": math.degrees(k.phi_m),
            "our_stroke_mean_deg": math.degrees(orbit.stroke_mean),
            "fwuav_stroke_mean_deg": math.degrees(k.phi_0)}
    return FwuavComparison(tr, orbit, stab, floquet, fj, ref, ours_a, fw_a, base_a, table,
                           modes, MappingProxyType(trim))


# =========================================================================== which term
#: Groups of :func:`fwuav_swap_table` beyond :data:`~flapping.studies.cfd.SWAP_GROUPS`: the
#: theta column (gravity, and in FWUAV's inertial velocities the loads turning with the body).
THETA = "theta column"


def fwuav_swap_table(comparison: FwuavComparison) -> pandas.DataFrame:
    """Our averaged system with FWUAV's terms swapped in, one at a time and in groups, and the
    reverse.

    Rows "none" give each side's own averaged modes; "all" swaps the nine derivatives; "all +
    theta column" swaps the whole matrix (the other side's modes). A third direction starts
    from ours with the hinge at the centre of mass (:attr:`FwuavComparison.base_matrix`, a real
    mode): which of FWUAV's terms turns it oscillatory.

    Parameters
    ----------
    comparison : FwuavComparison

    Returns
    -------
    pandas.DataFrame
        ``direction`` ("ours <- FWUAV", "FWUAV <- ours", "ours at the CG <- FWUAV"),
        ``swapped``, ``Mu`` (the M_u+ in the
        system), and :func:`~flapping.studies.cfd.mode_summary`'s ``type``, ``rate`` [1/s],
        ``period`` [s], ``doubling_time`` [s].
    """
    import pandas

    _validation.instance("comparison", comparison, FwuavComparison)
    ref = comparison.reference
    groups: list[tuple[str, ...]] = [(), *((n,) for n in DERIVATIVES), *SWAP_GROUPS,
                                     (THETA,), (*DERIVATIVES, THETA)]
    rows = []
    for direction, base, other in (("ours <- FWUAV", comparison.our_matrix,
                                    comparison.fwuav_matrix),
                                   ("FWUAV <- ours", comparison.fwuav_matrix,
                                    comparison.our_matrix),
                                   ("ours at the CG <- FWUAV", comparison.base_matrix,
                                    comparison.fwuav_matrix)):
        for group in groups:
            a = np.array(base, dtype=float)
            for n in group:
                if n == THETA:
                    a[:, 3] = other[:, 3]
                else:
                    i, j = divmod(DERIVATIVES.index(n), 3)
                    a[i, j] = other[i, j]
            label = ("all" if group == DERIVATIVES else "all + " + THETA
                     if len(group) == 10 else "+".join(group) or "none")
            mu = a[2, 0] * ref.inertia_ratio
            rows.append({"direction": direction, "swapped": label, "Mu": mu,
                         **mode_summary(np.linalg.eigvals(a) / ref.period)})
    return pandas.DataFrame(rows)


def _physics_steps(tr: FwuavTranslation) -> list[tuple[str, dict[str, Any]]]:
    """(label, changes) from FWUAV's body with the hinge at the centre of mass, massless wings
    and our loads at eq. (40)'s angle of attack, toward FWUAV's."""
    i = tr.insect
    lift = float(species(tr.name).morphology.C_T or math.nan)  # Sane & Dickinson's: not None
    a0 = brentq(lambda x: lev_lift_slope(i.aspect_ratio, x) - lift, 0.1, 50.0)
    return [
        ("hinge position", {"hinge_offset": i.hinge_offset, "hinge_height": i.hinge_height}),
        ("wing inertia", {"wing_mass": i.wing_mass, "wing_mass_r1": i.wing_mass_r1,
                          "wing_mass_r2": i.wing_mass_r2}),
        ("angle of attack", {"alpha_m": tr.alpha_m}),
        ("lift coefficient C_T", {"a0": a0}),
        ("loads on the span axis", {"center_of_pressure": 0.0}),
        ("no rotational terms", {"mu1": 0.0, "mu2": 0.0, "pitch_axis": 0.75}),
    ]


def fwuav_physics_table(comparison: FwuavComparison | FwuavTranslation, **hover_options: Any
                        ) -> pandas.DataFrame:
    """One physics at a time moved from ours toward FWUAV's: its effect on M_u+ and the type.

    The base is the translated insect (``wings="inertia"``) with the hinge at its centre of
    mass, massless wings and eq. (40)'s angle of attack; the steps are FWUAV's hinge position,
    its wing inertia, its angle of attack, its lift coefficient (our lift slope set to C_T
    through ``a0``), its loads acting on the span axis (``center_of_pressure = 0``) and no
    rotational lift or damping. Each step is taken alone from the base (``how = "alone"``) and
    accumulated (``"accumulated"``); each orbit is trimmed as in :func:`compare_fwuav`.

    Parameters
    ----------
    comparison : FwuavComparison or FwuavTranslation
        With ``wings="inertia"`` (only its translation is used).
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    pandas.DataFrame
        ``how``, ``step``, ``alpha_m_deg`` (the angle of attack flown), ``Mu``, ``Xu``, ``Mq``
        (non-dimensional, :class:`Reference` of the translation),
        ``averaged_type``, ``floquet_type``, ``leading_multiplier`` (complex),
        ``floquet_rate`` [1/s], ``stroke_amplitude_deg``, ``stroke_mean_deg``, ``message``
        (empty, or why no orbit was found).
    """
    import pandas

    if not isinstance(comparison, (FwuavComparison, FwuavTranslation)):
        raise ValueError("`comparison` must be a FwuavComparison or a FwuavTranslation; got "
                         f"{type(comparison).__name__}")
    tr = comparison if isinstance(comparison, FwuavTranslation) else comparison.translation
    if tr.wings != "inertia":
        raise ValueError("`comparison` must be made with wings='inertia'")
    base = _physics_base(tr)
    steps = _physics_steps(tr)
    cases: list[tuple[str, str, dict[str, Any]]] = [("base", "FWUAV's body, ours otherwise", {})]
    cases += [("alone", label, changes) for label, changes in steps]
    acc: dict[str, Any] = {}
    for label, changes in steps:
        acc = {**acc, **changes}
        cases.append(("accumulated", "+ " + label, dict(acc)))
    ref = Reference.of(tr)
    rows = []
    guess: HoverOrbit | None = None
    for how, label, changes in cases:
        row: dict[str, Any] = {"how": how, "step": label}
        fields = {k: v for k, v in changes.items() if k != "alpha_m"}
        alpha = changes.get("alpha_m")
        try:
            insect = base.with_(**fields) if fields else base
            orbit, stab = _solve(insect, alpha, guess, **hover_options)
        except (ArithmeticError, ValueError, RuntimeError) as exc:  # ConvergenceError included
            rows.append({**row, "message": f"{type(exc).__name__}: {exc}"})
            continue
        if how == "base":
            guess = orbit
        d = ref.derivatives(ref.nondimensional(stab.averaged_jacobian))
        lead = int(np.argmax(np.asarray(stab.exponents).real))
        row.update(alpha_m_deg=math.degrees(orbit.alpha_m), Mu=d[DERIVATIVES.index("Mu")],
                   Xu=d[DERIVATIVES.index("Xu")], Mq=d[DERIVATIVES.index("Mq")],
                   averaged_type=mode_summary(stab.averaged_eigenvalues)["type"],
                   floquet_type=mode_summary(stab.exponents)["type"],
                   leading_multiplier=complex(stab.multipliers[lead]),
                   floquet_rate=float(np.asarray(stab.exponents)[lead].real),
                   stroke_amplitude_deg=math.degrees(orbit.amplitude),
                   stroke_mean_deg=math.degrees(orbit.stroke_mean), message="")
        rows.append(row)
    return pandas.DataFrame(rows)



def _physics_base(tr: FwuavTranslation) -> Insect:
    """FWUAV's body with the hinge at the centre of mass and massless wings."""
    return tr.insect.with_(hinge_offset=0.0, hinge_height=0.0, wing_mass=0.0,
                           wing_mass_r1=None, wing_mass_r2=None)


# ==================================================== the chapter's pitch-free study, stored
# The hawkmoth's pitch-free results of the chapter "A second model" (pitch_free_floquet on
# FWUAV's kinematics and re-trimmed, both body-rate terms, and the re-trimmed hover at a tenfold
# tighter tolerance) are about 90 % of the chapter's execution: a minute and a half of CPU on
# the central-difference Jacobians of the pitch-free model. They are computed once by
#
#     python -m flapping.studies.fwuav book/_data/fwuav_pitch_free.json
#
# and the chapter loads the file. JSON keeps every float exactly (Python writes the shortest
# repr that reads back to the same double), so what the chapter computes from a loaded result
# is bit for bit what it computes from a fresh one. tests/test_fwuav_ours.py checks the
# versioned file: its cases are these, and recomputed entries agree with it to the study's
# tolerance.

#: The chapter's cases: key -> keyword arguments of ``pitch_free_floquet("hawkmoth", ...)``.
PITCH_FREE_CASES: dict[str, dict[str, Any]] = {
    "free fwuav": {"body_rate_term": "fwuav", "rtol": 1e-8, "trim": False},
    "free rotated": {"body_rate_term": "rotated", "rtol": 1e-8, "trim": False},
    "trimmed fwuav": {"body_rate_term": "fwuav", "rtol": 1e-8, "trim": True},
    "trimmed rotated": {"body_rate_term": "rotated", "rtol": 1e-8, "trim": True},
    "trimmed fwuav rtol 1e-9": {"body_rate_term": "fwuav", "rtol": 1e-9, "trim": True},
}
_PF_ARRAYS = ("y0", "multipliers", "exponents", "mean_velocity", "monodromy")
_PF_FLOATS = ("period", "mean_pitch", "pitch_amplitude", "residual_norm", "liouville_error")


def pitch_free_case(key: str) -> PitchFreeFloquet:
    """Case ``key`` of :data:`PITCH_FREE_CASES`, computed now (the hawkmoth)."""
    return pitch_free_floquet("hawkmoth", **PITCH_FREE_CASES[key])


def _pf_array(a: np.ndarray) -> dict[str, Any]:
    a = np.asarray(a)
    if np.iscomplexobj(a):
        return {"real": a.real.tolist(), "imag": a.imag.tolist()}
    return {"real": a.tolist()}


def _pf_unarray(d: dict[str, Any]) -> np.ndarray:
    real = np.array(d["real"], dtype=float)
    return real + 1j * np.array(d["imag"], dtype=float) if "imag" in d else real


def pitch_free_to_json(result: PitchFreeFloquet) -> dict[str, Any]:
    """Every field of ``result`` as JSON types (complex arrays as real and imaginary parts).

    Parameters
    ----------
    result : PitchFreeFloquet

    Returns
    -------
    dict
        Read back, exactly, by :func:`pitch_free_from_json`.
    """
    out: dict[str, Any] = {"name": result.name, "body_rate_term": result.body_rate_term}
    out.update({k: _pf_array(getattr(result, k)) for k in _PF_ARRAYS})
    out.update({k: float(getattr(result, k)) for k in _PF_FLOATS})
    out.update(trim_parameters=list(result.trim_parameters),
               trim_values=[float(v) for v in result.trim_values],
               trim_nfev=int(result.trim_nfev))
    return out


def pitch_free_from_json(d: dict[str, Any]) -> PitchFreeFloquet:
    """The :class:`~flapping.peers.fwuav.PitchFreeFloquet` that :func:`pitch_free_to_json`
    wrote.

    Parameters
    ----------
    d : dict

    Returns
    -------
    PitchFreeFloquet
    """
    fields: dict[str, Any] = {k: _pf_unarray(d[k]) for k in _PF_ARRAYS}
    fields.update({k: float(d[k]) for k in _PF_FLOATS})
    return PitchFreeFloquet(
        name=d["name"], body_rate_term=d["body_rate_term"], **fields,
        trim_parameters=tuple(d["trim_parameters"]),
        trim_values=tuple(float(v) for v in d["trim_values"]), trim_nfev=int(d["trim_nfev"]))


def write_pitch_free_study(path: str | Path) -> None:
    """Compute every case of :data:`PITCH_FREE_CASES` and write them to ``path`` (JSON).

    Parameters
    ----------
    path : str or Path
    """
    data = {"what": "pitch_free_floquet('hawkmoth', **arguments): "
                    "flapping.studies.fwuav.PITCH_FREE_CASES",
            "cases": {key: {"arguments": PITCH_FREE_CASES[key],
                            "result": pitch_free_to_json(pitch_free_case(key))}
                      for key in PITCH_FREE_CASES}}
    Path(path).write_text(json.dumps(data, indent=1) + "\n")


def load_pitch_free_study(path: str | Path) -> dict[str, PitchFreeFloquet]:
    """The stored results of :func:`write_pitch_free_study`, by case key.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    dict of str to PitchFreeFloquet

    Raises
    ------
    ValueError
        If the file's cases or their arguments are not :data:`PITCH_FREE_CASES` (a stale file).
    """
    data = json.loads(Path(path).read_text())
    cases = data["cases"]
    if {key: case["arguments"] for key, case in cases.items()} != PITCH_FREE_CASES:
        raise ValueError(f"`path` {path} holds other cases than PITCH_FREE_CASES: rewrite it "
                         "with `python -m flapping.studies.fwuav PATH`")
    return {key: pitch_free_from_json(case["result"]) for key, case in cases.items()}


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python -m flapping.studies.fwuav PATH.json")
    write_pitch_free_study(sys.argv[1])

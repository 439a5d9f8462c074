"""Wing kinematics in hover: harmonic flapping in a horizontal stroke plane, pitch fixed per stroke.

phi(t) = Phi cos(2 pi f t) (eq. 39), phi > 0 forward (the model layers add the insect's mean
stroke angle phi_bar, ``Insect.stroke_mean``, default 0; the functions here are eq. 39's). The
stroke starts at the forward extreme, so the first half-period (0 < t < T/2) is the *backward*
stroke (phi_dot < 0) and the second is the forward stroke (phi_dot > 0). Stroke reversal happens
at t = 0 and t = T/2 (mod T).

The geometric pitch of the wing is constant within a half-stroke (alpha_dot = 0, paper Sec. II.D)
and switches at reversal (eq. 11): alpha_m on the forward stroke, pi - alpha_m on the backward
stroke. Right-hand sides built on these kinematics are smooth within each half-stroke only, so
integrators should restart at :data:`HALF_STROKE_BREAKPOINTS`.

The two kinematic parameters have one accepted range each, checked by :func:`check_amplitude` and
:func:`check_alpha_m` wherever the model takes them (morphology, aerodynamics, derivatives,
dynamics). The public formula functions check their arguments too (a NaN time or angle is a
ValueError naming it, not a NaN answer); the right-hand sides call the unchecked ``_`` forms
inside integrations. This module imports nothing else from :mod:`flapping.model`.
"""

from __future__ import annotations

import math

import numpy as np

import flapping._validation as _validation

__all__ = [
    "HALF_STROKE_BREAKPOINTS",
    "flapping_angle",
    "flapping_rate",
    "stroke_sign",
    "stroke_sign_scalar",
    "segment_stroke_sign",
    "geometric_pitch",
    "reversed_flow_fraction",
    "check_amplitude",
    "check_alpha_m",
    "MAX_SAMPLES",
]

_SNAP = 1e-9  # phases this close to a reversal are taken to be at it

#: Most samples per period :func:`reversed_flow_fraction` takes: its fraction resolves 1/n, and
#: 4e6 samples (2.4e-7) already cost ~0.2 GB of temporaries; 1e12 would allocate terabytes.
MAX_SAMPLES = 1 << 22

#: Breakpoints of the half-strokes as fractions of the period (stroke reversal at 0 and 1/2).
HALF_STROKE_BREAKPOINTS: tuple[float, ...] = (0.5,)


def check_amplitude(amplitude: object, name: str = "amplitude") -> float:
    """Validate a stroke amplitude Phi of eq. (39): a real number in (0, pi/2] rad.

    Beyond 90 deg the two wings would cross; at 0 the wing does not flap.

    Parameters
    ----------
    amplitude : float
        Stroke amplitude [rad] (any real scalar type; bools and strings are refused).
    name : str
        The argument's name, for the message.

    Returns
    -------
    float
        ``amplitude`` as a Python float.

    Raises
    ------
    ValueError
        Naming ``name`` and the range.
    """
    return _validation.real(name, amplitude, low=0.0, high=math.pi / 2, low_open=True,
                            unit="rad")


def check_alpha_m(alpha_m: object, name: str = "alpha_m") -> float:
    """Validate a mid-stroke angle of attack alpha_m of eq. (11): a real number in (0, pi/2) rad.

    At either end the wing makes no leading-edge-vortex lift (C_L = A sin(2 alpha) = 0, eq. 3):
    at 0 it slices edgewise, at pi/2 it is broadside to the stroke, and eq. (40) has no trim.
    The open interval is the one range used across the model.

    Parameters
    ----------
    alpha_m : float
        Mid-stroke angle of attack [rad] (any real scalar type; bools and strings are refused).
    name : str
        The argument's name, for the message.

    Returns
    -------
    float
        ``alpha_m`` as a Python float.

    Raises
    ------
    ValueError
        Naming ``name`` and the range.
    """
    return _validation.real(name, alpha_m, low=0.0, high=math.pi / 2, low_open=True,
                            high_open=True, unit="rad")


def flapping_angle(t: np.ndarray | float, amplitude: float, frequency: float) -> np.ndarray:
    """Flapping angle phi(t) = Phi cos(2 pi f t), eq. (39).

    Parameters
    ----------
    t : array_like
        Time [s].
    amplitude : float
        Stroke amplitude Phi [rad].
    frequency : float
        Flapping frequency f [Hz].

    Returns
    -------
    numpy.ndarray
        phi [rad], the shape of ``t`` (positive forward).

    Raises
    ------
    ValueError
        If an argument is not finite or outside its range (the message names it).
    """
    t = _validation.array("t", t)
    amplitude = check_amplitude(amplitude)
    frequency = _validation.positive("frequency", frequency, unit="Hz")
    return amplitude * np.cos(2.0 * math.pi * frequency * t)


def flapping_rate(t: np.ndarray | float, amplitude: float, frequency: float) -> np.ndarray:
    """Flapping rate phi_dot(t) = -2 pi f Phi sin(2 pi f t), the derivative of eq. (39).

    Parameters
    ----------
    t : array_like
        Time [s].
    amplitude : float
        Stroke amplitude Phi [rad].
    frequency : float
        Flapping frequency f [Hz].

    Returns
    -------
    numpy.ndarray
        phi_dot [rad/s], the shape of ``t``.

    Raises
    ------
    ValueError
        If an argument is not finite or outside its range (the message names it).
    """
    t = _validation.array("t", t)
    amplitude = check_amplitude(amplitude)
    frequency = _validation.positive("frequency", frequency, unit="Hz")
    omega = 2.0 * math.pi * frequency
    return -omega * amplitude * np.sin(omega * t)


def stroke_sign(t: np.ndarray | float, frequency: float) -> np.ndarray:
    """Sign of phi_dot: -1 on the backward half-stroke [0, T/2), +1 on the forward [T/2, T).

    Parameters
    ----------
    t : array_like
        Time [s].
    frequency : float
        Flapping frequency f [Hz].

    Returns
    -------
    numpy.ndarray
        -1.0 or +1.0, the shape of ``t``.

    Notes
    -----

    Decided from the phase, not from the sign of a computed sine, so that it is exact away from
    reversal. At reversal itself the value is the one of the half-stroke that *starts* there;
    integrators that need the left limit use :func:`segment_stroke_sign` per segment.

    Raises
    ------
    ValueError
        If ``t`` is not finite or ``frequency`` not positive (the message names it).
    """
    return _stroke_sign(_validation.array("t", t),
                        _validation.positive("frequency", frequency, unit="Hz"))


def _stroke_sign(t: np.ndarray | float, frequency: float) -> np.ndarray:
    """:func:`stroke_sign` of trusted arguments (inside right-hand sides)."""
    phase = np.mod(np.asarray(t, dtype=float) * frequency, 1.0)
    # t * f rounds: snap phases within 1e-9 of a reversal onto it, so that k T and k T + T/2
    # consistently start their half-stroke.
    snapped = np.round(phase * 2.0) / 2.0
    phase = np.where(np.abs(phase - snapped) < _SNAP, np.mod(snapped, 1.0), phase)
    return np.where(phase < 0.5, -1.0, 1.0)


def stroke_sign_scalar(t: float, frequency: float) -> float:
    """:func:`stroke_sign` for one float time, without NumPy (for ODE right-hand sides).

    Parameters
    ----------
    t : float
        Time [s].
    frequency : float
        Flapping frequency f [Hz].

    Returns
    -------
    float
        -1.0 on the backward half-stroke, +1.0 on the forward one (eq. 11).

    Raises
    ------
    ValueError
        If ``t`` is not finite or ``frequency`` not positive (the message names it).
    """
    if type(t) is not float or not math.isfinite(t) or type(frequency) is not float \
            or not frequency > 0.0 or not math.isfinite(frequency):
        t = _validation.real("t", t)
        frequency = _validation.positive("frequency", frequency, unit="Hz")
    phase = (t * frequency) % 1.0
    snapped = round(phase * 2.0) / 2.0
    if abs(phase - snapped) < _SNAP:
        phase = snapped % 1.0
    return -1.0 if phase < 0.5 else 1.0


def segment_stroke_sign(segment: int) -> float:
    """Stroke sign on half-stroke segment ``segment`` of a period split at reversal.

    Parameters
    ----------
    segment : int
        Segment index (0: the backward stroke, 1: the forward stroke; taken modulo 2).

    Returns
    -------
    float
        -1.0 for the backward stroke, +1.0 for the forward one.

    Raises
    ------
    ValueError
        If ``segment`` is not an integer.
    """
    return -1.0 if _validation.integer("segment", segment) % 2 == 0 else 1.0


def geometric_pitch(alpha_m: float, sign: np.ndarray | float) -> np.ndarray:
    """Geometric pitch of the wing, eq. (11): alpha_m on the forward stroke, pi - alpha_m backward.

    Parameters
    ----------
    alpha_m : float
        Mean geometric angle of attack [rad].
    sign : array_like
        Stroke sign (+1 forward, -1 backward), e.g. from :func:`stroke_sign`.

    Returns
    -------
    numpy.ndarray
        alpha_g [rad].

    Raises
    ------
    ValueError
        If ``alpha_m`` is outside (0, pi/2) or a ``sign`` is not +1 or -1 (named).
    """
    alpha_m = check_alpha_m(alpha_m)
    sign = _validation.array("sign", sign)
    if not np.all(np.abs(sign) == 1.0):
        raise ValueError(f"`sign` must be +1 (forward) or -1 (backward); got {sign!r}")
    return np.where(sign > 0, alpha_m, math.pi - alpha_m)


def reversed_flow_fraction(radius: float, u: float, amplitude: float, frequency: float,
                           n_samples: int = 200_000) -> float:
    """Fraction of the wingbeat in which the section at ``radius`` moves against its stroke.

    The chordwise velocity U = r phi_dot + u cos(phi) (eq. 9) has the sign of phi_dot except
    where ``|r phi_dot|`` < ``|u cos(phi)|``, near stroke reversal: there the linearisation's
    assumption
    sign(U) = sign(phi_dot) fails. Uniform sampling of one period.

    Parameters
    ----------
    radius : float
        Radius of the section [m], >= 0.
    u : float
        Forward body speed [m/s].
    amplitude : float
        Stroke amplitude Phi [rad], in (0, pi/2].
    frequency : float
        Flapping frequency f [Hz], > 0.
    n_samples : int
        Samples per period, in [1, :data:`MAX_SAMPLES`].

    Returns
    -------
    float
        The fraction, in [0, 1].

    Raises
    ------
    ValueError
        If an argument is outside its range (the message names it).
    """
    radius = _validation.nonnegative("radius", radius, unit="m")
    u = _validation.real("u", u, unit="m/s")
    amplitude = check_amplitude(amplitude)
    frequency = _validation.positive("frequency", frequency, unit="Hz")
    n_samples = _validation.integer("n_samples", n_samples, low=1, high=MAX_SAMPLES)
    t = np.arange(n_samples) / (n_samples * frequency)
    phi = flapping_angle(t, amplitude, frequency)
    return float(np.mean(np.abs(radius * flapping_rate(t, amplitude, frequency))
                         < np.abs(u * np.cos(phi))))

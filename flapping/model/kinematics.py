"""Wing kinematics in hover: harmonic flapping in a horizontal stroke plane, piecewise-constant pitch.

phi(t) = Phi cos(2 pi f t) (eq. 39), phi > 0 forward. The stroke starts at the forward extreme, so
the first half-period (0 < t < T/2) is the *backward* stroke (phi_dot < 0) and the second is the
forward stroke (phi_dot > 0). Stroke reversal happens at t = 0 and t = T/2 (mod T).

The geometric pitch of the wing is constant within a half-stroke (alpha_dot = 0, paper Sec. II.D)
and switches at reversal (eq. 11): alpha_m on the forward stroke, pi - alpha_m on the backward
stroke. Right-hand sides built on these kinematics are smooth within each half-stroke only, so
integrators should restart at :data:`HALF_STROKE_BREAKPOINTS`.
"""

from __future__ import annotations

import math

import numpy as np

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
]

_SNAP = 1e-9  # phases this close to a reversal are taken to be at it

#: Breakpoints of the half-strokes as fractions of the period (stroke reversal at 0 and 1/2).
HALF_STROKE_BREAKPOINTS: tuple[float, ...] = (0.5,)


def check_amplitude(amplitude, name: str = "amplitude") -> float:
    """Validate a stroke amplitude: a real number in (0, pi/2] rad; return it as a float.

    Raises
    ------
    ValueError
        Naming ``name`` and the range: beyond 90 deg the two wings would cross.
    """
    try:
        value = float(amplitude)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number; got {amplitude!r}") from None
    if not (math.isfinite(value) and 0.0 < value <= math.pi / 2):
        raise ValueError(
            f"{name} must lie in (0, pi/2] rad (0 to 90 degrees: a larger stroke makes the wings "
            f"cross); got {amplitude!r}")
    return value


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
    """
    return amplitude * np.cos(2.0 * math.pi * frequency * np.asarray(t, dtype=float))


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
    """
    omega = 2.0 * math.pi * frequency
    return -omega * amplitude * np.sin(omega * np.asarray(t, dtype=float))


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
    """
    phase = np.mod(np.asarray(t, dtype=float) * frequency, 1.0)
    # t * f rounds: snap phases within 1e-9 of a reversal onto it, so that k T and k T + T/2
    # consistently start their half-stroke.
    snapped = np.round(phase * 2.0) / 2.0
    phase = np.where(np.abs(phase - snapped) < _SNAP, np.mod(snapped, 1.0), phase)
    return np.where(phase < 0.5, -1.0, 1.0)


def stroke_sign_scalar(t: float, frequency: float) -> float:
    """:func:`stroke_sign` for one float time, without NumPy (for ODE right-hand sides)."""
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
    """
    return -1.0 if segment % 2 == 0 else 1.0


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
    """
    sign = np.asarray(sign, dtype=float)
    return np.where(sign > 0, alpha_m, math.pi - alpha_m)


def reversed_flow_fraction(radius: float, u: float, amplitude: float, frequency: float,
                           n_samples: int = 200_000) -> float:
    """Fraction of the wingbeat in which the section at ``radius`` moves against its stroke.

    The chordwise velocity U = r phi_dot + u cos(phi) (eq. 9) has the sign of phi_dot except
    where |r phi_dot| < |u cos(phi)|, near stroke reversal: there the linearisation's assumption
    sign(U) = sign(phi_dot) fails. Uniform sampling of one period.

    Parameters
    ----------
    radius : float
        Radius of the section [m], >= 0.
    u : float
        Forward body speed [m/s].
    amplitude, frequency : float
        Stroke amplitude [rad] and flapping frequency [Hz].
    n_samples : int
        Samples per period.
    """
    if not radius >= 0.0:
        raise ValueError(f"radius must be >= 0; got {radius!r}")
    t = np.arange(n_samples) / (n_samples * frequency)
    phi = flapping_angle(t, amplitude, frequency)
    return float(np.mean(np.abs(radius * flapping_rate(t, amplitude, frequency))
                         < np.abs(u * np.cos(phi))))

"""The one schema of a hover orbit and of its stability, whatever the degrees of freedom.

:class:`~flapping.hover.orbit.HoverOrbit` (four states) and
:class:`~flapping.hover.sixdof.SixDofHoverOrbit` (eight) derive every view of an orbit here from
what each holds (its states over a period, its cycle-mean inertial velocities, its insect), so
the two have the same public attributes and the same meaning for each: what the orbit is
(:attr:`OrbitViews.status`, a :class:`~flapping.results.HoverStatus` word), its speeds, its
state ranges. The six-degree-of-freedom orbit adds its own views and loses nothing (a test
compares the attribute sets). Likewise :class:`StabilityViews` for the two stabilities.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Protocol

import numpy as np

from flapping.results import HoverStatus

__all__ = ["HOVER_SPEED_ATOL", "HOVER_SPEED_RTOL", "OrbitViews", "StabilityViews"]

#: Largest cycle-mean inertial speed (horizontal and vertical) of an orbit still called hover,
#: relative to the mean wingtip speed 4 Phi f R (~5.8 m/s for the hawkmoth, so ~6 um/s). A hover
#: orbit with the half-period symmetry (x_h = 0) drifts only at round-off (~1e-12 m/s); a hinge
#: 1 mm off the centre of gravity makes it fly at ~0.4 m/s.
HOVER_SPEED_RTOL = 1e-6

#: Largest cycle-mean inertial speed of an orbit still called hover, in absolute terms [m/s]
#: (10 um/s, under a body length an hour for any insect): the relative test alone would call an
#: orbit hover whatever its speed for an absurd wingtip speed.
HOVER_SPEED_ATOL = 1e-5


class _Orbit(Protocol):
    """What :class:`OrbitViews` reads of an orbit."""

    state_names: ClassVar[tuple[str, ...]]
    half_period_symmetry: ClassVar[np.ndarray]

    @property
    def amplitude(self) -> float: ...
    @property
    def x(self) -> np.ndarray: ...
    @property
    def insect(self) -> Any: ...
    @property
    def mean_inertial_velocity(self) -> dict[str, float]: ...
    @property
    def status(self) -> HoverStatus: ...
    @property
    def mean_horizontal_speed(self) -> float: ...
    @property
    def wingtip_speed(self) -> float: ...
    @property
    def hover_speed_tol(self) -> float: ...


class _Stability(Protocol):
    """What :class:`StabilityViews` reads of a stability."""

    @property
    def multipliers(self) -> np.ndarray: ...
    @property
    def eigenvectors(self) -> np.ndarray: ...
    @property
    def is_stable(self) -> bool: ...


class OrbitViews:
    """What every hover orbit derives from its states, speeds and insect.

    A subclass provides ``amplitude`` [rad], ``x`` (its states over one period, one row each),
    ``insect``, ``mean_inertial_velocity`` (``forward`` and ``climb``, and ``side`` where the
    orbit has lateral states) and the class attributes ``state_names`` and
    ``half_period_symmetry`` (x(t + T/2) = S x(t) for the symmetric stroke).
    """

    state_names: ClassVar[tuple[str, ...]]
    half_period_symmetry: ClassVar[np.ndarray]

    @property
    def amplitude_deg(self: _Orbit) -> float:
        """Stroke amplitude in degrees."""
        return math.degrees(self.amplitude)

    @property
    def mean_state(self: _Orbit) -> dict[str, float]:
        """Cycle mean of each state."""
        return {k: float(np.mean(self.x[i, :-1])) for i, k in enumerate(self.state_names)}

    @property
    def state_range(self: _Orbit) -> dict[str, tuple[float, float]]:
        """(min, max) of each state over the period."""
        return {k: (float(self.x[i].min()), float(self.x[i].max()))
                for i, k in enumerate(self.state_names)}

    @property
    def mean_horizontal_speed(self: _Orbit) -> float:
        """Magnitude of the cycle-mean inertial horizontal velocity [m/s]: 0 on a hover orbit."""
        v = self.mean_inertial_velocity
        return math.hypot(v["forward"], v.get("side", 0.0))

    @property
    def wingtip_speed(self: _Orbit) -> float:
        """Mean wingtip speed 4 Phi f R [m/s], the scale of :attr:`is_hover`'s tolerance."""
        return 4.0 * self.amplitude * self.insect.frequency * self.insect.semi_span

    @property
    def hover_speed_tol(self: _Orbit) -> float:
        """The largest cycle-mean speed of a hover orbit [m/s]: :data:`HOVER_SPEED_RTOL` times
        the :attr:`wingtip_speed`, at most :data:`HOVER_SPEED_ATOL`."""
        return min(HOVER_SPEED_RTOL * self.wingtip_speed, HOVER_SPEED_ATOL)

    @property
    def status(self: _Orbit) -> HoverStatus:
        """:class:`~flapping.results.HoverStatus`: hover, drifting horizontally, or
        climbing/sinking.

        A mean speed counts if it exceeds :data:`HOVER_SPEED_RTOL` times the
        :attr:`wingtip_speed` or :data:`HOVER_SPEED_ATOL`.
        """
        limit = self.hover_speed_tol
        if abs(self.mean_inertial_velocity["climb"]) > limit:
            return HoverStatus.CLIMBING
        return HoverStatus.DRIFTING if self.mean_horizontal_speed > limit else HoverStatus.HOVER

    @property
    def is_hover(self: _Orbit) -> bool:
        """True if the orbit stays in place on average (:attr:`status` is ``HOVER``).

        That is, if both cycle-mean inertial speeds (:attr:`mean_inertial_velocity`) are at most
        :attr:`hover_speed_tol`. False for an orbit that drifts horizontally (a hinge offset,
        see :class:`~flapping.errors.HoverDriftWarning`) or climbs or sinks (an orbit of
        :func:`~flapping.hover.orbit.forced_orbit` away from the hover amplitude).
        """
        return self.status == HoverStatus.HOVER

    @property
    def message(self: _Orbit) -> str:
        """What :attr:`status` means for this orbit, in words."""
        v = self.mean_inertial_velocity
        status = self.status
        if status == HoverStatus.HOVER:
            return "hover: periodic, in place on average"
        if status == HoverStatus.CLIMBING:
            return (f"not hover: {'climbs' if v['climb'] > 0 else 'sinks'} at a mean "
                    f"{abs(v['climb']):.3g} m/s")
        side = f" and sideways at {abs(v['side']):.3g} m/s" if v.get("side") else ""
        return (f"not hover: flies {'forwards' if v['forward'] > 0 else 'backwards'} at a "
                f"mean {abs(v['forward']):.3g} m/s{side}; trims=('amplitude', 'stroke_mean') "
                "finds a true hover orbit")

    @property
    def half_period_symmetry_error(self: _Orbit) -> float:
        """``max |x(t + T/2) - S x(t)| / max |x|`` over the period: 0 with the symmetry (states
        that are 0 throughout, the lateral ones of a symmetric orbit, left out)."""
        n = self.x.shape[1] - 1
        if n % 2:
            raise ValueError("needs an even number of samples per period")
        first, second = self.x[:, : n // 2], self.x[:, n // 2 : n]
        scale = np.abs(self.x).max(axis=1, keepdims=True)
        moving = scale[:, 0] > 0.0
        error = np.abs(second - self.half_period_symmetry @ first)[moving] / scale[moving]
        return float(np.max(error)) if error.size else 0.0


class StabilityViews:
    """What every hover stability derives from its multipliers and eigenvectors.

    A subclass provides ``multipliers`` (by descending modulus) and ``eigenvectors`` (column k
    for ``multipliers[k]``).
    """


    @property
    def is_stable(self: _Stability) -> bool:
        """True if every multiplier lies inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    @property
    def stable(self: _Stability) -> bool:
        """Every multiplier inside the unit circle (:attr:`is_stable`)."""
        return self.is_stable

    @property
    def unstable_mode(self: _Stability) -> np.ndarray:
        """Eigenvector of the largest multiplier scaled so its largest component is 1.

        Real (float) when that multiplier is real; complex when it belongs to a complex pair.
        """
        v = self.eigenvectors[:, 0]
        v = v / v[np.argmax(np.abs(v))]
        return np.real(v) if abs(self.multipliers[0].imag) == 0.0 else v

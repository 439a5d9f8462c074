"""The hover orbit followed as an insect parameter changes, with its Floquet multipliers.

:func:`continue_hover` continues the hover problem of :func:`flapping.hover.find_hover_orbit`
(unknowns: the initial state and the stroke amplitude Phi; equations: periodicity of
(u, w, q, theta) and zero net change of altitude over a period) in one field of
:class:`~flapping.model.morphology.Insect`, e.g. the flapping frequency or the centre-of-pressure
position, with :func:`flapping.periodic.continuation.continue_orbit`:

* the state is augmented with the descent z (z' = -u sin theta + w cos theta) and z(0) = 0 held
  (``fixed=(4,)``), the amplitude Phi is the free parameter that this costs (``free_params``), so
  the orbit *and* the amplitude are re-solved at every step;
* the multipliers are those of the (u, w, q, theta) block (``floquet_states``): z does not feed
  back, its own multiplier is exactly 1 and says nothing about stability;
* at every parameter value the insect is rebuilt (``dataclasses.replace``) and the model made as
  :func:`~flapping.hover.find_hover_orbit` makes it, with the mean angle of attack at the trim of
  eq. (40) for that insect, so that each point of the branch is the hover orbit
  ``find_hover_orbit(replace(insect, name=p))`` finds;
* the period is ``1 / frequency``: a forced system whose period may change with the parameter.
"""

from __future__ import annotations

from collections import OrderedDict
from dataclasses import fields, replace
from typing import Any

import numpy as np

from flapping import _validation
from flapping.backends import Adaptive
from flapping.hover.orbit import find_hover_orbit
from flapping.hover.problem import HoverProblem
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.morphology import Insect
from flapping.periodic.continuation import Branch, continue_orbit
from flapping.periodic.settings import SolverSettings

__all__ = ["CONTINUATION", "continue_hover", "HoverFields"]

#: Insect models kept per parameter value (the variational equations difference in p).
_CACHE = 8


class HoverFields:
    """The hover problem's right-hand sides and Jacobians as functions of one insect field.

    ``funs[k](t, y, p, params)`` and ``jacs[k](t, y, p, params)`` on half-stroke k,
    y = (u, w, q, theta, z), p the field's value (the continuation parameter), ``params = [Phi]``
    (the free parameter solved with the orbit); :meth:`period` gives the flapping period at p.
    Each value of p is a :class:`~flapping.hover.HoverProblem` (a few are kept), whose fields are
    the ones :func:`~flapping.hover.find_hover_orbit` solves.

    Parameters
    ----------
    insect : Insect
        The insect at the start of the branch.
    name : str
        The :class:`Insect` field that is the parameter.
    aerodynamics : str
        As for :class:`~flapping.model.dynamics.LongitudinalDynamics`.
    """

    def __init__(self, insect: Insect, name: str, aerodynamics: str = "linear") -> None:
        numeric = [f.name for f in fields(Insect) if f.name != "name"]
        if name not in numeric:
            raise ValueError(f"`parameter_name` must be a numeric field of Insect, one of "
                             f"{numeric}; got {name!r}")
        self.insect, self.name, self.aerodynamics = insect, name, aerodynamics
        self.problems: OrderedDict[float, tuple[HoverProblem, tuple[list[Any], ...]]] = \
            OrderedDict()
        first = self.problem(float(getattr(insect, name)))
        self.breakpoints = first.model.breakpoints
        segments = range(len(self.breakpoints) + 1)
        self.funs = [self._field(0, k) for k in segments]
        self.jacs = [self._field(1, k) for k in segments]

    def problem(self, p: float) -> HoverProblem:
        """The hover problem of the insect with the field at p (cached)."""
        return self._at(p)[0]

    def model(self, p: float) -> LongitudinalDynamics:
        """The model of the insect with the field at p (cached)."""
        return self.problem(p).model

    def _at(self, p: float) -> tuple[HoverProblem, tuple[list[Any], ...]]:
        found = self.problems.get(p)
        if found is None:
            changed: dict[str, Any] = {self.name: p}
            problem = HoverProblem(replace(self.insect, **changed), self.aerodynamics)
            found = self.problems[p] = (problem, problem.fields())
            if len(self.problems) > _CACHE:
                self.problems.popitem(last=False)
        return found

    def period(self, p: float) -> float:
        """Flapping period at p [s]."""
        return self.problem(float(p)).period

    def _field(self, which: int, k: int) -> Any:
        def f(t: float, y: np.ndarray, p: float, params: np.ndarray) -> np.ndarray:
            return self._at(p)[1][which][k](t, y, params)
        return f


#: The continuation's default path: the adaptive one, with a decade looser ``rtol`` than a single
#: solve (every branch point is corrected by Newton on the variational equations, a few hundred
#: integrations a branch) and ``tol`` the corrector's relative residual.
CONTINUATION = Adaptive(rtol=1e-10, tol=1e-9)


def continue_hover(insect: Insect, parameter_name: str, end: float, *,
                   aerodynamics: str = "linear", backend: Adaptive | str = CONTINUATION,
                   settings: SolverSettings | None = None, **options: Any) -> Branch:
    """Continue the hover orbit and its stroke amplitude in one insect field.

    Parameters
    ----------
    insect : Insect
        The insect at the start (the field's start value is ``getattr(insect, parameter_name)``).
    parameter_name : str
        An :class:`Insect` field, e.g. ``"frequency"`` [Hz] or ``"center_of_pressure"`` (x_hat,
        a fraction of the chord).
    end : float
        Where to stop.
    aerodynamics : str, optional
        Loads model (``"linear"``: eq. 29).
    backend : "adaptive" or Adaptive
        The continuation runs on the adaptive path (:func:`~flapping.periodic.continuation.
        continue_orbit`); its ``method``, ``rtol``, ``atol``, ``max_steps`` and ``tol`` (the
        corrector's, relative to the states' size) are taken from this object, by default
        :data:`CONTINUATION`. ``"adaptive"`` or ``"auto"`` mean :data:`CONTINUATION`.
    **options
        Passed to :func:`~flapping.periodic.continuation.continue_orbit` (``ds``, ``ds_max``,
        ``max_points``, tolerances, ...); a tolerance given here overrides ``backend``'s.
    settings : SolverSettings, optional
        The continuation's options as one object (:class:`~flapping.periodic.SolverSettings`,
        as :func:`~flapping.periodic.continuation.continue_orbit` reads it); a field set there
        replaces ``backend``'s, and an option given as a keyword overrides the field. The hover
        orbit at the start is found with :func:`~flapping.hover.find_hover_orbit`'s own
        defaults.

    Returns
    -------
    Branch
        ``x0`` rows are (u, w, q, theta, z=0) [m/s, m/s, rad/s, rad, m], ``params[:, 0]`` the
        hover stroke amplitude Phi [rad], ``p`` the field's values, ``multipliers`` those of the
        (u, w, q, theta) block.

    Raises
    ------
    ValueError
        For an unknown field or a bad value.
    ConvergenceError
        If the hover orbit cannot be found at the start.
    """
    path = _continuation_path(backend)
    problem = HoverFields(insect, parameter_name, aerodynamics)
    p0 = float(getattr(insect, parameter_name))
    end = _validation.real("end", end)
    try:  # the field's own range: a branch towards a value no insect has would run for ever
        insect.with_(**{parameter_name: end})
    except ValueError as exc:
        raise ValueError(f"`end` = {end!r} is outside the range of {parameter_name!r}: {exc}"
                         ) from None
    start = find_hover_orbit(problem.problem(p0))
    # The backend's options are passed as keywords (which win over settings): only those
    # settings leaves unset.
    defaults = {k: getattr(path, k) for k in ("method", "rtol", "atol", "tol", "max_steps")
                if getattr(path, k) is not None
                and (settings is None or getattr(settings, k) is None)}
    return continue_orbit(
        problem.funs, np.append(start.x0, 0.0), problem.period, p0, end, autonomous=False,
        jac=problem.jacs, breakpoints=problem.breakpoints, fixed=(4,),
        free_params=(start.amplitude,), floquet_states=(0, 1, 2, 3), settings=settings,
        **{**defaults, **options})


def _continuation_path(backend: Any) -> Adaptive:
    """The continuation's Adaptive backend (:data:`CONTINUATION` for a name)."""
    return Adaptive.required_by("continue_hover", backend, default=CONTINUATION)

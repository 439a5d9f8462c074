"""Compiled (numba) blade-element loads for the fixed-step hover path.

The fixed-step path of the blade-element hover orbit (:meth:`flapping.hover.HoverProblem.
graded_fields`) spends ~90 % of its time in the right-hand side: ~10^5 evaluations per solve of
the blade-element loads (:class:`flapping.model.aerodynamics.BladeElementModel`, a span
quadrature on ~100 stations) through three layers of Python. :class:`BladeField` evaluates the
same graded field in one compiled call (:mod:`flapping.fast._blade`), ~50 times faster per
evaluation; the period map, Newton and the error estimate are unchanged, so the results are the
Python path's to rounding.

Called from Python, a compiled evaluation still costs ~2 microseconds of dispatch, three times
its arithmetic. :class:`GradedMap` therefore integrates the whole period map of the graded field
compiled: all steps of both half-strokes of a batch of trajectories, their DOP853 stages and the
roots of the switching functions, in one call (:func:`flapping.fast._blade.graded_flow`, the
integration of :class:`flapping.periodic._fixedmap.PeriodMap` written out), offered to the
fixed-step solver on the field's callables (:meth:`BladeField.attach_map`). Python then runs
Newton and the central differences only: the hawkmoth's orbit and its multipliers in ~0.1 s of
CPU instead of ~0.4-0.6 s (``benchmarks/bench_blade_element.py map``).

One source of truth: the quadrature rules and the constants are the Python model's own arrays
(packed by :func:`pack`), and the compiled arithmetic is checked against the Python loads and
field at random states, phases and insects (``tests/fast/test_blade.py``); the wings' inertial
loads are the generated code of :mod:`flapping.model.inertia`, compiled as it is.
:data:`SUPPORTED_FIELDS` lists the :class:`~flapping.model.morphology.Insect` fields the compiled
field follows, and :meth:`BladeField.of` refuses (returns None for) an insect with another field
off its default (a field added to ``Insect`` and not yet modelled here), so that the Python path
runs then.

Importing this module does not import numba: :func:`load` compiles the numba code (or loads it
from numba's on-disk cache) the first time a field is built, under the policy of every numba
module here (:mod:`flapping.fast._jit`: one :class:`~flapping.fast.kernel.KernelCompileWarning`
per process when numba compiles, the times on the ``"flapping"`` logger; with
``FLAPPING_FIRST_CALL=uncompiled`` and a cold cache the Python loads run instead).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType, ModuleType
from typing import Any

import numpy as np

from flapping.fast import _jit
from flapping.fast._jit import KernelCompileWarning
from flapping.fast.kernel import numba_available
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.kinematics import segment_stroke_sign
from flapping.model.morphology import Insect
from flapping.periodic._fixedmap import COMPILED_MAP, NonFinite

__all__ = ["SUPPORTED_FIELDS", "BladeField", "GradedMap", "available", "load", "pack",
           "unsupported_field"]

#: The :class:`~flapping.model.morphology.Insect` fields the compiled loads follow, and how each
#: enters. An insect whose other fields differ from their defaults is refused (the Python path
#: runs), so a field added to ``Insect`` is refused until it is modelled here and listed.
SUPPORTED_FIELDS: Mapping[str, str] = MappingProxyType({
    "name": "label only",
    "semi_span": "R: the span stations and the sign-change station of U",
    "wing_area": "the quadrature weights (mean chord) and A of eq. (4)",
    "r1": "the beta chord distribution (quadrature rules, incomplete span moments)",
    "r2": "the beta chord distribution (quadrature rules, incomplete span moments)",
    "frequency": "omega = 2 pi f of eq. (39), the period and the rotational damping",
    "stroke_amplitude": "none here (the amplitude is the trim p[0])",
    "mass": "1/m of eq. (2)",
    "pitch_inertia": "1/I_y of eq. (2)",
    "air_density": "rho of the loads",
    "gravity": "g of eq. (2)",
    "a0": "the 2-D lift slope in A of eq. (4)",
    "aspect_ratio_convention": "the aspect ratio in A of eq. (4)",
    "pitch_axis": "3/4 - x0_hat of the rotational circulation (eq. 5)",
    "center_of_pressure": "x_hat of the moments (eqs. 21-23)",
    "hinge_offset": "x_h of w_eff (eq. 12) and of the moments",
    "mu1": "the rotational damping torque (mu1 f)",
    "mu2": "the rotational damping torque (mu2 |Omega|)",
    "hinge_height": "h_w of the section's forward speed and of the moment",
    "stroke_mean": "phi_bar of eq. (39) (or the trim p[1])",
    "wing_mass": "the wings' inertial loads (flapping.model.inertia, generated code)",
    "wing_mass_r1": "the wings' first mass moment A1",
    "wing_mass_r2": "the wings' second mass moment A2",
    "roll_inertia": "none: the planar model has no roll (six degrees of freedom only)",
    "yaw_inertia": "none: the planar model has no yaw (six degrees of freedom only)",
    "roll_yaw_product": "none: the planar model has no roll or yaw",
})

_LOG = logging.getLogger("flapping")

_MODULE: list[ModuleType] = []


def unsupported_field(insect: Insect) -> str:
    """Why the compiled loads cannot model this insect: its first field outside
    :data:`SUPPORTED_FIELDS` that is not at its default, in words ('' if there is none)."""
    for f in dataclasses.fields(insect):
        if not f.init or f.name in SUPPORTED_FIELDS:
            continue
        value = getattr(insect, f.name)
        if f.default is dataclasses.MISSING or value != f.default:
            default = "" if f.default is dataclasses.MISSING else f" (its default {f.default!r})"
            return (f"the compiled blade-element loads do not model the insect field "
                    f"`{f.name}` = {value!r}: they support the default only{default}")
    return ""


def load() -> ModuleType:
    """Import the numba code and compile it, or load it from numba's cache, once per process
    (with an empty cache numba compiles it here, 5-20 s of CPU, said as
    :mod:`flapping.fast._jit` says every compile).

    Returns
    -------
    module
        :mod:`flapping.fast._blade`.

    Raises
    ------
    ImportError
        If numba is not installed (``pip install flapping[fast]``).
    """
    if not _MODULE:
        start = time.perf_counter()
        from flapping.fast import _blade

        fresh = not all(_jit.ready(f) for f in (_blade.graded_rhs, _blade.graded_flow))
        with _jit.forced("compiled"):
            _touch(_blade)
        seconds = time.perf_counter() - start
        _LOG.info("blade-element loads %s in %.2f s", "compiled" if fresh else "loaded", seconds)
        _MODULE.append(_blade)
    return _MODULE[0]


def available() -> bool:
    """Whether the compiled loads run here: always once loaded; else unless
    ``FLAPPING_FIRST_CALL=uncompiled`` and numba's cache does not hold them (the Python loads
    run then, and nothing is compiled). The variable is checked on every call."""
    mode = _jit.first_call_mode()
    if _MODULE or mode == "compiled":
        return True
    from flapping.fast import _blade

    if all(_jit.ready(f) for f in (_blade.graded_rhs, _blade.graded_flow)):
        return True
    if not _UNCOMPILED_NOTED:
        _UNCOMPILED_NOTED.append(True)
        warnings.warn("flapping's compiled blade-element loads are not in numba's cache here: "
                      "with FLAPPING_FIRST_CALL=uncompiled the Python loads run (equal to "
                      "rounding); `python -m flapping compile` compiles them into the cache once",
                      KernelCompileWarning, stacklevel=3)
    return False


_UNCOMPILED_NOTED: list[bool] = []


def _touch(compiled: ModuleType) -> None:
    """Run the entry points once on the hawkmoth with the argument types of use."""
    from flapping.model.morphology import hawkmoth

    for variant in ("small-angle", "exact"):
        for insect in (hawkmoth(), hawkmoth(wing_mass=1e-5)):
            model = LongitudinalDynamics(insect, aerodynamics=variant)
            data = pack(model, 1)
            y, p = np.zeros(5), np.array([model.amplitude])
            compiled.graded_rhs(0.25, y, p, 0, -1.0, data)
            compiled.loads(0.001, 0.1, 0.0, 1.0, 1.0, model.amplitude, 0.0, data)
            compiled.graded_flow(y[None, :], p[None, :], 2, np.array([0.0, 1.0, 2.0]),
                                 np.array([-1.0, 1.0]), data)


def pack(model: LongitudinalDynamics, n_conditions: int) -> np.ndarray:
    """The model's blade-element loads as the compiled code's ``data`` array.

    The quadrature stations, weights, incomplete span moments and load constants are the
    Python model's own (``model``'s :class:`~flapping.model.aerodynamics.BladeElementModel`),
    laid out as :mod:`flapping.fast._blade` documents.

    Parameters
    ----------
    model : LongitudinalDynamics
        A blade-element model (``"small-angle"`` or ``"exact"``).
    n_conditions : {1, 2}
        Hover conditions appended to the state (z; z and x_e).
    """
    from flapping.fast import _blade

    blade = model._blade
    assert blade is not None, "only the blade-element models have compiled loads"
    insect = model.insect
    a, b, full = blade._partial_moments
    head = np.zeros(_blade.OFFSET)
    head[:13] = blade._consts
    head[_blade.I_R] = insect.semi_span
    head[_blade.I_H_W] = insect.hinge_height
    head[_blade.I_PHI_BAR] = insect.stroke_mean
    head[_blade.I_G] = insect.gravity
    head[_blade.I_MASS] = insect.mass
    head[_blade.I_IY] = insect.pitch_inertia
    head[_blade.I_HALF] = 0.5 * model.period
    head[_blade.I_VARIANT] = 0.0 if blade.variant == "small-angle" else 1.0
    head[_blade.I_N_R] = blade._r.size
    head[_blade.I_N_COND] = n_conditions
    if model._inertia is not None:
        head[_blade.I_INERTIA] = 1.0
        head[_blade.I_K:_blade.I_K + 8] = model._inertia.constants
    # Writable on purpose: numba types a read-only array as another type, and dispatching a
    # call on one costs ~2 microseconds more (as much as the loads); nothing writes to it.
    log_beta = [_blade.log_beta(float(ai), float(bi)) for ai, bi in zip(a, b, strict=True)]
    return np.concatenate([head, blade._r, np.ascontiguousarray(blade._weights).ravel(),
                           blade._weight_sums, blade._weight_moments, a, b, full, log_beta])


@dataclass(frozen=True, eq=False)
class BladeField:
    """The compiled graded hover field of a blade-element model (build with :meth:`of`).

    Attributes
    ----------
    function : callable
        ``function(s, y, p, k, sign, data)``: the graded field F(s, y, p) of half-stroke k
        (:meth:`flapping.hover.HoverProblem.graded_fields`), compiled; ``sign`` is the stroke sign
        of the half-stroke and ``data`` the packed model.
    data : ndarray
        The packed model (:func:`pack`).
    signs : tuple of float
        The stroke sign of each half-stroke.
    """

    function: Callable[..., np.ndarray]
    data: np.ndarray
    signs: tuple[float, ...]

    @classmethod
    def of(cls, model: LongitudinalDynamics, n_conditions: int) -> BladeField | None:
        """The compiled field of ``model``, or None where it does not apply (linear loads, numba
        not installed, or an insect field outside :data:`SUPPORTED_FIELDS`): then the Python
        field runs, as it does with ``FLAPPING_FIRST_CALL=uncompiled`` when numba's cache
        does not hold the compiled loads (:func:`available`). The first call in a process
        compiles or loads the numba code."""
        if (model.aerodynamics == "linear" or not numba_available()
                or unsupported_field(model.insect) or not available()):
            return None
        compiled = load()
        signs = tuple(segment_stroke_sign(k) for k in range(len(model.breakpoints) + 1))
        return cls(compiled.graded_rhs, pack(model, n_conditions), signs)

    def arguments(self, k: int) -> tuple[Any, ...]:
        """The trailing arguments of :attr:`function` on half-stroke k: (k, sign, data)."""
        return (k, self.signs[k], self.data)

    def attach_map(self, funs: Sequence[Callable[..., Any]],
                   switches: Sequence[Sequence[Callable[..., Any]]]) -> None:
        """Offer the fixed-step period map of the graded field compiled (:class:`GradedMap`).

        ``funs`` are the field's Python callables per half-stroke (``F(s, y, params)``, each
        calling :attr:`function` with :meth:`arguments`), ``switches`` their switching functions
        (those of :meth:`flapping.hover.HoverProblem.graded_fields`, in its order: U = 0 at the
        root, at the tip, q = 0). The map is set as the callables' attribute
        :data:`flapping.periodic._fixedmap.COMPILED_MAP`, where the fixed-step solver finds it.
        """
        graded = GradedMap(self, tuple(funs), tuple(tuple(g) for g in switches))
        for f in funs:
            setattr(f, COMPILED_MAP, graded)


@dataclass(frozen=True, eq=False)
class GradedMap:
    """The fixed-step period map of a graded blade-element field in one compiled call.

    :class:`flapping.periodic._fixedmap.CompiledMap` for the fields of
    :meth:`flapping.hover.HoverProblem.graded_fields`: the integration of
    :class:`~flapping.periodic._fixedmap.PeriodMap` (DOP853 steps, split at the roots of the
    switching functions) by :func:`flapping.fast._blade.graded_flow`, a batch of trajectories
    per call. Build with :meth:`BladeField.attach_map`.

    Attributes
    ----------
    field : BladeField
    funs : tuple of callables
        The Python callables of the field it integrates, per half-stroke.
    switches : tuple of tuples of callables
        Their switching functions (the compiled copies run: :func:`flapping.fast._blade.switch`).
    """

    field: BladeField
    funs: tuple[Callable[..., Any], ...]
    switches: tuple[tuple[Callable[..., Any], ...], ...]

    def flow(self, X: np.ndarray, P: np.ndarray, n: int, nodes: Sequence[float]
             ) -> tuple[np.ndarray, int]:
        """(end states, evaluations of the field) of the rows of ``X`` with the parameters the
        rows of ``P``: segment k over [nodes[k], nodes[k + 1]] at ``n`` steps.

        Raises
        ------
        ValueError
            For arrays of other shapes, or another number of segments, than the field's.
        NonFinite
            If a state becomes non-finite (as the Python map).
        DomainError
            If the field's callables refuse a parameter row (a trim out of its range).
        """
        X, P = np.ascontiguousarray(X, dtype=float), np.ascontiguousarray(P, dtype=float)
        _jit.first_call_mode()  # checked on every call, as every fast module does
        compiled = load()
        # the compiled code indexes without bounds checks: refuse other shapes here
        n_conditions = int(self.field.data[compiled.I_N_COND])
        if (X.ndim != 2 or P.ndim != 2 or X.shape[1] != 4 + n_conditions
                or P.shape != (X.shape[0], n_conditions)
                or len(nodes) != len(self.field.signs) + 1):
            raise ValueError(f"the compiled map integrates states of size {4 + n_conditions} "
                             f"with {n_conditions} parameters over {len(self.field.signs)} "
                             f"segments; got shapes {X.shape} and {P.shape}, {len(nodes)} nodes")
        # The callables check the trims (a DomainError for one the model refuses) before the
        # compiled loads run: each distinct row once, in the order the Python map meets them.
        seen: list[np.ndarray] = []
        for x, p in zip(X, P, strict=True):
            if not any(np.array_equal(p, q) for q in seen):
                self.funs[0](nodes[0], x, p)
                seen.append(p)
        ends, nfev, failed_at = compiled.graded_flow(
            X, P, int(n), np.asarray(nodes, dtype=float), np.asarray(self.field.signs, float),
            self.field.data)
        if failed_at < math.inf:
            raise NonFinite(f"the state became non-finite at t = {failed_at!r}")
        return ends, int(nfev)

"""The command line (``flapping``, ``python -m flapping``): hover orbits and their stability.

``flapping hover [--insect NAME|FILE] [--aerodynamics linear] [--json]`` (the console script), or
the same after ``python -m flapping``; ``--insect`` takes a preset name or a ``.toml``/``.json``
file (:mod:`flapping.model.insect_file`), and ``flapping species [--json]`` lists the presets.
``flapping --version`` prints the package version.
``flapping sweep --insect hawkmoth --param frequency=LO:HI:N [--param NAME=LO:HI:N] [--csv |
--json] [--workers K]`` prints hover and its multipliers over a parameter grid, one row per point
(:mod:`flapping.studies.sweep`).
``flapping compile`` compiles every numba function into numba's on-disk cache
(:func:`flapping.fast.warm_up`), for installs, clusters and CI, with a line per step.

Exit status: 0 on success; 1 if the solver fails (no convergence, a failed integration, or a result
that is not a finite number; for a sweep, if no point gave an orbit); 2 for bad arguments; 130
after Ctrl-C (a sweep has printed the rows it finished), wherever it lands: a KeyboardInterrupt
that surfaces inside compiled (numba) code as another exception, such as SystemError, is an
interrupt too. Errors and warnings are one line each on standard error, never a traceback.

The JSON report (:func:`hover_report`) is in SI units (angles in rad unless the key ends in
``_deg``), and its ``units`` member gives the unit of every key. It never contains NaN or infinity:
a non-finite result is an error (status 1), not a number a JSON parser may refuse.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import inspect
import json
import math
import os
import signal
import sys
import time
import warnings
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from flapping import __version__, _validation
from flapping.backends import Adaptive
from flapping.errors import ConvergenceError, PlausibilityWarning, caused_by_interrupt
from flapping.hover import HoverOrbit, find_hover_orbit
from flapping.hover.sixdof import find_sixdof_hover_orbit, sixdof_stability
from flapping.hover.stability import HoverStability, hover_stability
from flapping.model import presets as species
from flapping.model.dynamics import AERODYNAMIC_MODELS, STATE_NAMES
from flapping.model.insect_file import resolve_insect
from flapping.model.morphology import Insect, explain_blowup
from flapping.model.sixdof import body_inertia
from flapping.peers.fwuav import cli as fwuav_cli
from flapping.results import HoverStatus
from flapping.studies.atlas import robust_hover_orbit
from flapping.studies.sweep import SWEEPABLE, stop_process_pool, sweep_hover

__all__ = ["PRESETS", "UNITS", "NonFiniteResultError", "hover_report", "main"]

#: Preset insects selectable with ``--insect`` by name (:mod:`flapping.model.presets`).
PRESETS: dict[str, Callable[[], Insect]] = {name: entry.insect
                                           for name, entry in species.PRESETS.items()}

_STATE_UNITS = {"u": "m/s", "w": "m/s", "q": "rad/s", "theta": "rad"}
_COUNT = "1"  # a dimensionless number (a count, a ratio, a multiplier)
#: Units of the :class:`~flapping.model.morphology.Insect` fields (``None``: not a quantity).
INSECT_UNITS: dict[str, str | None] = {
    "name": None, "semi_span": "m", "wing_area": "m^2", "r1": _COUNT, "r2": _COUNT,
    "frequency": "Hz", "stroke_amplitude": "rad", "mass": "kg", "pitch_inertia": "kg m^2",
    "air_density": "kg/m^3", "gravity": "m/s^2", "a0": "1/rad", "aspect_ratio_convention": None,
    "pitch_axis": _COUNT, "center_of_pressure": _COUNT, "hinge_offset": "m", "mu1": _COUNT,
    "mu2": _COUNT, "hinge_height": "m", "stroke_mean": "rad", "wing_mass": "kg",
    "wing_mass_r1": _COUNT, "wing_mass_r2": _COUNT, "roll_inertia": "kg m^2",
    "yaw_inertia": "kg m^2", "roll_yaw_product": "kg m^2",
}
_ATOL_UNIT = "SI units of each state (m/s, rad/s, rad; m for z)"
_SHOOTING_UNITS: dict[str, str | None] = {
    "method": None, "rtol": _COUNT, "atol": _ATOL_UNIT,
    "tol": "SI units of each state (norm of the residual)", "jacobian": None, "success": None,
    "nit": _COUNT, "nfev": _COUNT, "njev": _COUNT, "backend": None, "solved_by": None,
}
_STABILITY_UNITS: dict[str, str | None] = {
    "method": None, "rtol": _COUNT, "atol": _ATOL_UNIT, "rk4_steps": _COUNT, "n_average": _COUNT,
    "backend": None,
}
#: What ran (``solver.ran``): the path, its backend object's options, its error estimates (null
#: where the path has none: the adaptive path) and the wall-clock times.
_RAN_UNITS: dict[str, str | None] = {
    "backend": None, "options": "each option's own (flapping.backends: tolerances relative, "
    "atol in SI units of the states, amplitude_tol_deg in deg)", "n_steps": _COUNT,
    "amplitude_error_deg": "deg", "x0_error": "SI units of each state",
    "multiplier_error": _COUNT, "stability_multiplier_error": _COUNT, "solve_time_s": "s",
    "stability_time_s": "s",
}
#: Unit of every key of the JSON report (nested like the report; ``None``: not a quantity;
#: ``"1"``: dimensionless). Lists of complex numbers ``{"re", "im"}`` share one unit.
UNITS: dict[str, Any] = {
    "version": None,
    "insect": None,
    "insect_parameters": INSECT_UNITS,
    "aerodynamics": None,
    "trims": None,
    "stroke_mean_deg": "deg",
    "continued_from": None,
    "amplitude_deg": "deg",
    "alpha_m_deg": "deg",
    "initial_state": _STATE_UNITS,
    "period_s": "s",
    "residual_norm": "SI units of each state (norm of the shooting residual)",
    "mean_inertial_velocity": {"forward": "m/s", "climb": "m/s"},
    "mean_horizontal_velocity": "m/s",
    "mean_vertical_velocity": "m/s",
    "is_hover": None,
    "status": None,
    "backend": None,
    "multipliers": _COUNT,
    "floquet_exponents": "1/s",
    "det_monodromy": _COUNT,
    "liouville_det": _COUNT,
    "liouville_error": _COUNT,
    "averaged_eigenvalues": "1/s",
    "stable": None,
    "solver": {"shooting": _SHOOTING_UNITS, "stability": _STABILITY_UNITS, "ran": _RAN_UNITS},
}

_DESCRIPTION = """\
Stability of hovering flapping-wing flight (Elsadek, El-Bayoumi & Taha): the periodic hover
orbit of an insect and its Floquet multipliers."""

_EXIT_CODES = """exit status:
  0  success
  1  the solver failed: no convergence, a failed integration, or a result that is not finite;
     a sweep in which no point gave an orbit (every row says why)
  2  bad command-line arguments
  130  interrupted (Ctrl-C); a sweep has printed the rows it finished"""

_EPILOG = f"""`%(prog)s hover --help` describes hover, its options and the units of its output.

{_EXIT_CODES}

Units are SI (m, s, kg, rad), except keys and labels that say deg.
example: %(prog)s hover --json"""

_HOVER_DESCRIPTION = """\
Find the hover orbit of an insect, a preset or a file (Elsadek, El-Bayoumi & Taha, Sec. IV): the
initial state u, w [m/s], q [rad/s], theta [rad] and the stroke amplitude Phi [deg] of the
periodic orbit of period T = 1/f [s] whose mean climb rate is zero. Then integrate the
variational equations over one period: the monodromy matrix, its Floquet multipliers
(dimensionless; hover is stable if all four lie inside the unit circle), the Floquet exponents
ln(mu)/T [1/s], the Liouville check det M = exp(int_0^T trace J dt), and the eigenvalues of the
cycle-averaged system [1/s]."""

_HOVER_EPILOG = f"""\
--json prints one JSON object with the keys amplitude_deg, alpha_m_deg, initial_state, period_s,
residual_norm, mean_inertial_velocity, multipliers, floquet_exponents, det_monodromy,
liouville_det, averaged_eigenvalues, stable, and version, insect, insect_parameters,
aerodynamics, mean_horizontal_velocity, mean_vertical_velocity, is_hover, liouville_error,
status (hover, drifting or climbing), backend (compiled or adaptive: the path that solved it),
solver (settings asked for, iteration counts, and under "ran" the path that ran with its options,
error estimates and times), trims (amplitude, and stroke_mean where the hinge is off
the centre of gravity), stroke_mean_deg, continued_from (null, or the insect a continuation
started from when the default guess failed); `units` gives the unit of every key. Complex
numbers are {{"re": ..., "im": ...}}. NaN and infinity are never printed: a non-finite result
exits with 1.

{_EXIT_CODES}"""


_SPECIES_DESCRIPTION = """\
List the preset insects (flapping.model.presets): name, species, body mass, wing length (the
semi-span R), flapping frequency and main source. Each works with `hover --insect NAME`. With
--json: a list of objects with the keys name, species, mass_kg, wing_length_m, frequency_hz,
source."""


class NonFiniteResultError(ValueError):
    """A number of the report is NaN or infinite, so it cannot be reported as JSON."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:  # one line, no usage dump
        self.exit(2, f"{self.prog}: error: {message}\n")


def _prog() -> str:
    """``flapping`` when run as the console script, else ``python -m flapping``."""
    return "flapping" if Path(sys.argv[0]).name == "flapping" else "python -m flapping"


def _parser() -> argparse.ArgumentParser:
    raw = argparse.RawDescriptionHelpFormatter
    parser = _Parser(prog=_prog(), description=_DESCRIPTION, epilog=_EPILOG, formatter_class=raw)
    parser.add_argument("--version", action="version", version=f"flapping {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser,
                                metavar="command")
    hover = sub.add_parser("hover", help="hover orbit and its Floquet stability",
                           description=_HOVER_DESCRIPTION, epilog=_HOVER_EPILOG,
                           formatter_class=raw)
    hover.add_argument("--insect", default="hawkmoth", metavar="NAME|FILE",
                       help="a preset (" + ", ".join(PRESETS) + "; default: %(default)s, the "
                            "paper's Manduca sexta; the species command lists them) or a .toml "
                            "or .json file of Insect fields in SI units")
    hover.add_argument("--aerodynamics", default=None, choices=AERODYNAMIC_MODELS,
                       help="loads model (default: linear, the paper's eq. 29; small-angle "
                            "and exact: the blade-element loads, the default with --dof 6)")
    hover.add_argument("--dof", type=int, default=4, choices=(4, 6),
                       help="degrees of freedom: 4, the paper's planar insect (default), or "
                            "6: also the eight multipliers of (u, v, w, p, q, r, roll, theta) "
                            "and the lateral ones (keys dof, lateral_multipliers, "
                            "lateral_stable, sixdof)")
    hover.add_argument("--geometry", default="paper",
                       choices=(*species.GEOMETRIES, *species.DEPRECATED_GEOMETRIES),
                       help="with a preset: the paper's geometry (hinge at the centre of "
                            "gravity, massless wings; the default) or 'source', the sources' "
                            "hinge position (estimated for all but the hoverfly, whose is a "
                            "second-hand model value) and wing mass (the mean stroke angle is "
                            "then trimmed too); 'measured' is the deprecated name of 'source'")
    hover.add_argument("--json", action="store_true",
                       help="print one JSON object (SI units, a `units` map) instead of text")
    listing = sub.add_parser("species", help="list the preset insects",
                             description=_SPECIES_DESCRIPTION, formatter_class=raw)
    listing.add_argument("--json", action="store_true",
                         help="print a JSON list of objects (SI units in the key names)")
    add_sweep_parser(sub, tuple(PRESETS))
    fwuav_cli.add_parser(sub)
    sub.add_parser("compile", help="compile the numba code into its on-disk cache, once",
                   description=_COMPILE_DESCRIPTION, formatter_class=raw)
    return parser


_COMPILE_DESCRIPTION = """\
Compile every numba function of flapping (the hover kernel, the blade-element loads, six degrees
of freedom) into numba's on-disk cache, printing a line per step and what was compiled, so that
later processes load the machine code instead of compiling on their first call. numba chooses
the cache directory: NUMBA_CACHE_DIR if set (a shared one serves every node of a cluster).
Needs numba (pip install flapping[fast]). Exit status 0 on success, 1 without numba, 130 after
Ctrl-C."""


def _compile(prog: str) -> int:
    """The ``compile`` subcommand: :func:`flapping.fast.warm_up` with its progress lines."""
    try:
        from flapping.fast import warm_up

        report = warm_up(progress=lambda line: _write(line))
    except ImportError as exc:
        print(f"{prog}: error: {_one_line(exc)} (numba is the `fast` extra: "
              f"pip install flapping[fast])", file=sys.stderr)
        return 1
    _raise_if_interrupted()  # a Ctrl-C that a compile deferred and something then swallowed
    return 0 if _write(str(report)) else 1


def _complex_list(values) -> list[dict[str, float]]:
    return [{"re": float(v.real), "im": float(v.imag)} for v in values]


def _defaults(function: Callable, *names: str) -> dict[str, Any]:
    """The default values of some keyword arguments of ``function``."""
    parameters = inspect.signature(function).parameters
    return {name: parameters[name].default for name in names}


def _finite_or_none(value: float) -> float | None:
    """A number, or None (JSON null) for an estimate the path does not have (NaN)."""
    return float(value) if math.isfinite(value) else None


def _ran(orbit: HoverOrbit, stab: HoverStability, stability_time: float) -> dict[str, Any]:
    """What ran: the keys of :data:`_RAN_UNITS`."""
    steps = (orbit.kernel.n_steps if orbit.kernel is not None
             else orbit.fixed_step.n_steps if orbit.fixed_step is not None else None)
    options = {} if orbit.solver is None else dataclasses.asdict(orbit.solver)
    return {"backend": orbit.backend, "options": options, "n_steps": steps,
            "amplitude_error_deg": _finite_or_none(math.degrees(orbit.amplitude_error)),
            "x0_error": _finite_or_none(orbit.x0_error),
            "multiplier_error": _finite_or_none(orbit.multiplier_error),
            "stability_multiplier_error": _finite_or_none(stab.multiplier_error),
            "solve_time_s": None if orbit.stats is None else orbit.stats.time,
            "stability_time_s": stability_time}


def _solver_report(orbit: HoverOrbit, shooting: dict, stability: dict,
                   ran: dict[str, Any]) -> dict[str, dict]:
    """The settings asked for (``shooting``, ``stability``: the adaptive path's, whatever ran)
    and what the solve did (``jacobian`` and ``njev`` are null on the compiled path, which has
    no scipy shooting result; ``solved_by`` names the path); ``ran``: the path that ran, its
    options, error estimates and times (:data:`_RAN_UNITS`)."""
    result = orbit.shooting if orbit.shooting is not None else orbit.fixed_step
    return {
        "shooting": {**shooting, "jacobian": None if result is None else result.jacobian,
                     "success": True if result is None else bool(result.success),
                     "nit": int(orbit.nit), "nfev": int(orbit.nfev),
                     "njev": None if result is None else int(result.njev),
                     "solved_by": orbit.backend},
        "stability": dict(stability),
        "ran": ran,
    }


def _insect_parameters(insect: Insect) -> dict[str, Any]:
    return {f.name: getattr(insect, f.name) for f in dataclasses.fields(insect) if f.init}


def _orbit_report(orbit: HoverOrbit) -> dict[str, Any]:
    velocity = orbit.mean_inertial_velocity
    return {
        "amplitude_deg": orbit.amplitude_deg,
        "alpha_m_deg": math.degrees(orbit.model.alpha_m),
        "initial_state": {k: float(v) for k, v in zip(STATE_NAMES, orbit.x0, strict=True)},
        "period_s": orbit.period,
        "residual_norm": orbit.residual_norm,
        "mean_inertial_velocity": velocity,
        "mean_horizontal_velocity": velocity["forward"],
        "mean_vertical_velocity": velocity["climb"],
        "is_hover": orbit.is_hover,
        "status": str(orbit.status),
        "backend": orbit.backend,
    }


def _stability_report(stab: HoverStability) -> dict[str, Any]:
    return {
        "multipliers": _complex_list(stab.multipliers),
        "floquet_exponents": _complex_list(stab.exponents),
        "det_monodromy": stab.det,
        "liouville_det": stab.liouville_det,
        "liouville_error": stab.liouville_error,
        "averaged_eigenvalues": _complex_list(stab.averaged_eigenvalues),
        "stable": stab.is_stable,
    }


#: Units of the keys ``hover --dof 6`` adds (:func:`hover_report`).
SIXDOF_UNITS: dict[str, Any] = {
    "dof": None,
    "lateral_multipliers": _COUNT,
    "lateral_stable": None,
    "sixdof": {"multipliers": _COUNT, "longitudinal_multipliers": _COUNT,
               "coupling": _COUNT, "liouville_error": _COUNT,
               "residual_norm": "SI units of each state (eight-state periodicity residual)"},
}


def _sixdof_report(insect: Insect, orbit: HoverOrbit, aerodynamics: str) -> dict[str, Any]:
    """The keys of :data:`SIXDOF_UNITS`: the planar orbit embedded, solved and analysed in six
    degrees of freedom."""
    full = find_sixdof_hover_orbit(insect, aerodynamics=aerodynamics, planar_orbit=orbit)
    stab = sixdof_stability(full)
    return {"dof": 6, "lateral_multipliers": _complex_list(stab.lateral.multipliers),
            "lateral_stable": bool(np.all(np.abs(stab.lateral.multipliers) < 1.0)),
            "sixdof": {"multipliers": _complex_list(stab.multipliers),
                       "longitudinal_multipliers": _complex_list(stab.longitudinal.multipliers),
                       "coupling": stab.coupling, "liouville_error": stab.liouville_error,
                       "residual_norm": full.residual_norm},
            "units": {**UNITS, **SIXDOF_UNITS}}


def _non_finite(value: Any, path: str = "") -> list[str]:
    """Paths (``key.sub[i].re = nan``) of every NaN or infinity in a JSON-ready object."""
    if isinstance(value, float) and not math.isfinite(value):
        return [f"{path} = {value}"]
    if isinstance(value, dict):
        return [bad for k, v in value.items()
                for bad in _non_finite(v, f"{path}.{k}" if path else k)]
    if isinstance(value, list):
        return [bad for i, v in enumerate(value) for bad in _non_finite(v, f"{path}[{i}]")]
    return []


def hover_report(insect: str | Insect = "hawkmoth", aerodynamics: str | None = None,
                 dof: int = 4) -> dict:
    """The hover orbit and its stability as a JSON-ready dict (SI units; see :data:`UNITS`).

    Parameters
    ----------
    insect : str or Insect
        A key of :data:`PRESETS`, the path of a ``.toml``/``.json`` insect file
        (:mod:`flapping.model.insect_file`), or an :class:`~flapping.model.morphology.Insect`.
    aerodynamics : {"linear", "small-angle", "exact"}, optional
        Loads model; default ``"linear"`` (eq. 29) with ``dof=4``, ``"small-angle"`` with
        ``dof=6`` (where ``"linear"`` is eq. 29 derived in six degrees of freedom, solved on the
        compiled six-degree-of-freedom path).
    dof : {4, 6}
        With 6, the orbit is also solved and analysed in six degrees of freedom
        (:mod:`flapping.hover.sixdof`): the report adds the keys of :data:`SIXDOF_UNITS`
        (``dof``, ``lateral_multipliers`` in the form of ``multipliers``, ``lateral_stable``,
        ``sixdof``); the planar keys keep their meaning (the longitudinal multipliers, equal to
        the six-degree-of-freedom ones to the integration's accuracy).

    Returns
    -------
    dict
        The keys of :data:`UNITS` and ``units`` (that map). Every number is finite.

    Raises
    ------
    ValueError
        For an unknown preset or bad arguments.
    ConvergenceError
        If the shooting or an integration fails.
    NonFiniteResultError
        If a reported number is NaN or infinite (e.g. a Floquet exponent of a multiplier that
        underflows to 0); the message lists which.
    """
    dof = _validation.choice("dof", dof, (4, 6))
    if aerodynamics is None:
        aerodynamics = "linear" if dof == 4 else "small-angle"
    if isinstance(insect, str):
        insect = PRESETS[insect]() if insect in PRESETS else resolve_insect(insect)
    if dof == 6:
        body_inertia(insect)  # refuse an insect without lateral inertia before any solve
    # The defaults are the backend objects' fields (flapping.backends): what a call runs with.
    adaptive = Adaptive()
    shooting = {"method": adaptive.method, "rtol": adaptive.rtol, "atol": adaptive.atol,
                "tol": adaptive.tol, **_defaults(find_hover_orbit, "backend")}
    stability = {"method": adaptive.method, "rtol": adaptive.analysis_rtol,
                 "atol": adaptive.analysis_atol, "rk4_steps": adaptive.rk4_steps,
                 **_defaults(hover_stability, "n_average", "backend")}
    # A hinge ahead of or behind the CG drifts unless the mean stroke angle is trimmed too.
    trims = ("amplitude",) if insect.hinge_offset == 0.0 else ("amplitude", "stroke_mean")
    # From the default guess, or by continuation from the same insect hinged at its CG with
    # massless wings (the monarch with its heavy wings needs it).
    with warnings.catch_warnings():  # the insect's own implausible values were warned already
        warnings.simplefilter("ignore", PlausibilityWarning)
        plain = insect.with_(name=f"{insect.name} hinged at its CG, massless wings",
                             hinge_offset=0.0, hinge_height=0.0, wing_mass=0.0, stroke_mean=0.0)
    orbit, homotopy = robust_hover_orbit(insect, start=plain, aerodynamics=aerodynamics,
                                         trims=trims, backend=shooting["backend"])
    started = time.perf_counter()
    stab = hover_stability(orbit, n_average=stability["n_average"],
                           backend=stability["backend"])
    ran = _ran(orbit, stab, time.perf_counter() - started)
    report = {"version": __version__, "insect": insect.name,
              "insect_parameters": _insect_parameters(insect), "aerodynamics": aerodynamics,
              "trims": list(trims), "stroke_mean_deg": math.degrees(orbit.stroke_mean),
              "continued_from": None if homotopy is None else homotopy.start,
              **_orbit_report(orbit), **_stability_report(stab),
              "solver": _solver_report(orbit, shooting, stability, ran), "units": UNITS}
    if dof == 6:
        report.update(_sixdof_report(insect, orbit, aerodynamics))
    bad = _non_finite(report)
    if bad:
        raise NonFiniteResultError(
            f"the result for {insect.name} is not finite ({', '.join(bad)}): the orbit or its "
            "stability is out of floating-point range, so it is not reported")
    return report


def _text(report: dict) -> str:
    x0 = report["initial_state"]
    lines = [
        f"{report['insect']} hover ({report['aerodynamics']} aerodynamics)",
        f"  stroke amplitude Phi = {report['amplitude_deg']:.6f} deg "
        f"(alpha_m = {report['alpha_m_deg']:.4f} deg, T = {report['period_s']:.6f} s)",
        f"  initial state: u = {x0['u']:.6g} m/s, w = {x0['w']:.6g} m/s, "
        f"q = {x0['q']:.6g} rad/s, theta = {x0['theta']:.6g} rad",
        f"  shooting residual {report['residual_norm']:.2e}",
        f"  mean inertial velocity: forward {report['mean_horizontal_velocity']:.3g} m/s, "
        f"climb {report['mean_vertical_velocity']:.3g} m/s"
        + ("" if report["is_hover"] else " (NOT hover: the orbit drifts)"),
        "  Floquet multipliers:",
    ]
    for mu in report["multipliers"]:
        lines.append(f"    {mu['re']:+.6f} {mu['im']:+.6f}i   "
                     f"|mu| = {math.hypot(mu['re'], mu['im']):.6f}")
    lines.append(f"  det M = {report['det_monodromy']:.10g}, Liouville exp(int tr J) = "
                 f"{report['liouville_det']:.10g} (relative error "
                 f"{report['liouville_error']:.1e})")
    lines.append("  averaged-system eigenvalues [1/s]: " + ", ".join(
        f"{e['re']:+.4g}{e['im']:+.4g}i" for e in report["averaged_eigenvalues"]))
    lines.append("  hover is " + ("stable" if report["stable"] else "UNSTABLE"))
    return "\n".join(lines)


def _one_line(text: object) -> str:
    return " ".join(str(text).split())


def _write(text: str) -> bool:
    """Print ``text``; False (no traceback) if the reader has gone (``flapping ... | head``)."""
    try:
        print(text, flush=True)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return False
    return True


def _insect_argument(parser: argparse.ArgumentParser, spec: str,
                     geometry: str = "paper") -> Insect:
    """``--insect`` as an Insect (a preset or a file), or exit 2 with one line saying why."""
    if spec in PRESETS:
        return PRESETS[spec]() if geometry == "paper" else species.preset(spec, geometry=geometry)
    if geometry != "paper":
        parser.error("argument --geometry: applies to a preset (" + ", ".join(PRESETS)
                     + "); an insect file gives its hinge position and wing mass itself")
    try:
        return resolve_insect(spec)
    except ValueError as exc:
        parser.error(f"argument --insect: {_one_line(exc)}")


def _species(as_json: bool) -> int:
    """The ``species`` subcommand: the presets, as a table or a JSON list."""
    rows = species.species_table()
    if as_json:
        text = json.dumps(rows, allow_nan=False)
    else:
        head = f"{'name':<10} {'species':<30} {'mass [mg]':>10} {'R [mm]':>7} {'f [Hz]':>7}  source"
        text = "\n".join([head] + [
            f"{r['name']:<10} {r['species']:<30} {r['mass_kg'] * 1e6:>10.4g} "
            f"{r['wing_length_m'] * 1e3:>7.4g} {r['frequency_hz']:>7.4g}  {r['source']}"
            for r in rows])
    return 0 if _write(text) else 1


def _hover(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """The ``hover`` subcommand: the report as text or one JSON object.

    A failure is one line, naming the insect's implausible fields, if any, as the likely cause
    (:func:`~flapping.model.morphology.explain_blowup`).
    """
    insect = _insect_argument(parser, args.insect, args.geometry)
    try:
        report = hover_report(insect, args.aerodynamics, args.dof)
        text = json.dumps(report, allow_nan=False) if args.json else _text(report)
    except (ValueError, ConvergenceError, ArithmeticError) as exc:
        if _is_interrupt(exc):
            raise KeyboardInterrupt from exc
        why = explain_blowup(insect)  # the fields to check, if some look like no insect's
        print(f"{parser.prog}: error: {_one_line(exc)}" + (f" ({why})" if why else ""),
              file=sys.stderr)
        return 1
    _raise_if_interrupted()  # a Ctrl-C that a solver caught and recovered from
    return 0 if _write(text) else 1


# =========================================================================== Ctrl-C
#: Set by the SIGINT handler of :func:`main` (a one-element list: no global statement).
_SIGINT_SEEN: list[bool] = [False]


def _on_sigint(signum: int, frame: Any) -> None:
    """Python's own Ctrl-C (raise KeyboardInterrupt), remembered: compiled code can turn the
    KeyboardInterrupt into another exception (numba: SystemError), or a solver can catch it."""
    _SIGINT_SEEN[0] = True
    raise KeyboardInterrupt


@contextlib.contextmanager
def _sigint_remembered() -> Iterator[None]:
    """Install :func:`_on_sigint` for the block (in the main thread; elsewhere, nothing)."""
    _SIGINT_SEEN[0] = False
    try:
        previous = signal.signal(signal.SIGINT, _on_sigint)
    except ValueError:  # not the main thread: signals are not ours to handle
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def _is_interrupt(exc: BaseException) -> bool:
    """True if ``exc`` is, or was caused by, a Ctrl-C (a KeyboardInterrupt in its chain, as
    numba's SystemError "returned a result with an exception set" carries it, or any exception
    raised after the SIGINT handler ran)."""
    return caused_by_interrupt(exc) or _SIGINT_SEEN[0]


def _raise_if_interrupted() -> None:
    """KeyboardInterrupt if Ctrl-C was pressed and something swallowed it."""
    if _SIGINT_SEEN[0]:
        raise KeyboardInterrupt


def _run(parser: argparse.ArgumentParser, argv: Sequence[str] | None) -> int:
    given = list(sys.argv[1:] if argv is None else argv)
    if "--version" in given and len(given) > 1:
        # argparse prints the version and exits 0 whatever follows ("--version extra").
        parser.error("argument --version: takes no other arguments; got "
                     + " ".join(a for a in given if a != "--version")[:80])
    args = parser.parse_args(given)
    if args.command == "sweep":
        return _sweep(parser, args)
    if args.command == "species":
        return _species(args.json)
    if args.command == "fwuav":
        return fwuav_cli.run(args, parser.prog)
    if args.command == "compile":
        return _compile(parser.prog)
    return _hover(parser, args)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``flapping`` and ``python -m flapping``; returns the exit status.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        0 on success, 1 if the solver fails or its result is not finite, 130 if interrupted
        (Ctrl-C; a sweep has written the rows it finished). Bad arguments exit (SystemExit)
        with status 2 and one line on standard error; ``--help`` and ``--version`` with 0.
        Warnings are printed once each, one line each, after the output.
    """
    prog = _prog()
    with warnings.catch_warnings(record=True) as caught, _sigint_remembered():
        warnings.simplefilter("always")
        try:
            status = _run(_parser(), argv)
        except KeyboardInterrupt:
            print(f"{prog}: interrupted", file=sys.stderr)
            status = _INTERRUPTED
        except Exception as exc:
            if not _is_interrupt(exc):
                raise
            print(f"{prog}: interrupted", file=sys.stderr)  # e.g. numba's SystemError
            status = _INTERRUPTED
        finally:
            for message in dict.fromkeys(_one_line(w.message) for w in caught):
                print(f"{prog}: warning: {message}", file=sys.stderr)
    return status


# =========================================================================== sweep
#: Exit status after Ctrl-C (128 + SIGINT, as shells report it).
_INTERRUPTED = 130

#: Most points a ``sweep`` grid may have (all --param sizes multiplied): about ten minutes of
#: compiled solves on one core. A larger N would allocate or run for ever before the first row.
MAX_SWEEP_POINTS = 1_000_000

#: Points solved per call of sweep_hover (per worker): the rows printed, and kept on Ctrl-C, a
#: block at a time. A multiple of the sweep's chunk of 50 warm-started points, so that a
#: one-parameter sweep is solved exactly as by a single call.
_BLOCK_POINTS = 200

#: A sweep row's status words of a point that solved (an orbit, hover or not).
_SOLVED = [str(status) for status in HoverStatus]

_CLI_HELP = """\
Evaluate the hover orbit and its Floquet multipliers (compiled kernel, eq. 29's linear loads) over
a grid of insect parameters and print one row per point: the swept parameters (SI units), the
stroke amplitude Phi [deg], the initial state u0, w0 [m/s], q0 [rad/s], theta0 [rad], the four
multipliers (real and imaginary parts, by descending modulus), max |mu|, stable, converged, the
error estimates, the Newton iterations and steps per half-stroke, and why a point failed."""

_CLI_EPILOG = f"""\
--param NAME=LO:HI:N takes N values from LO to HI inclusive (numpy.linspace) of an Insect field
(frequency [Hz], center_of_pressure [fraction of the chord], mass [kg], ...); repeat it for a
full grid of at most {MAX_SWEEP_POINTS} points. --csv (default) prints a header and one line per
point; --json one JSON object per line (JSON Lines, null for a missing or non-finite value).
--workers K runs on K local processes. Rows are printed as they are solved, in grid order; Ctrl-C
stops the sweep with the rows finished so far printed (exit status 130).
example: %(prog)s --insect hawkmoth --param frequency=20:32:1000 --csv"""


def _param(text: str) -> tuple[str, np.ndarray]:
    """Parse NAME=LO:HI:N into (name, values), or an ArgumentTypeError saying what is wrong."""
    try:
        name, spec = text.split("=", 1)
        lo_text, hi_text, n_text = spec.split(":")
        lo, hi, n = float(lo_text), float(hi_text), int(n_text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected NAME=LO:HI:N (e.g. frequency=20:32:100), got {text[:80]!r}") from None
    if name not in SWEEPABLE:
        raise argparse.ArgumentTypeError(
            f"unknown Insect field {name!r}; choose from {', '.join(SWEEPABLE)}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise argparse.ArgumentTypeError(f"LO and HI must be finite numbers in {text!r}")
    if not 1 <= n <= MAX_SWEEP_POINTS:
        raise argparse.ArgumentTypeError(
            f"N must be an integer in [1, {MAX_SWEEP_POINTS}] in {text!r}")
    return name, np.linspace(lo, hi, n)


def _max_workers() -> int:
    return 4 * (os.cpu_count() or 1)


def add_sweep_parser(subparsers: Any, presets: Sequence[str]) -> None:
    """Add the ``sweep`` subcommand to the CLI's subparsers (run by :func:`main`)."""
    parser = subparsers.add_parser("sweep", help="hover and its multipliers over a parameter grid",
                                   description=_CLI_HELP, epilog=_CLI_EPILOG,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--insect", default="hawkmoth", choices=sorted(presets),
                        help="preset insect whose fields are varied (default: %(default)s)")
    parser.add_argument("--param", action="append", type=_param, required=True,
                        metavar="NAME=LO:HI:N", help="a swept Insect field (repeatable)")
    form = parser.add_mutually_exclusive_group()
    form.add_argument("--csv", action="store_true", help="CSV with a header (default)")
    form.add_argument("--json", action="store_true", help="one JSON object per line")
    parser.add_argument("--workers", type=int, default=1, metavar="K",
                        help="local worker processes, 1 to 4 per core (default: %(default)s, "
                             "in this process)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


def _sweep_grid(parser: argparse.ArgumentParser, args: argparse.Namespace) -> dict[str, Any]:
    """The grid of the ``--param`` options, or exit 2 naming what is wrong."""
    grid = dict(args.param)
    if len(grid) != len(args.param):
        parser.error("argument --param: each NAME may be given once")
    size = math.prod(len(v) for v in grid.values())
    if size > MAX_SWEEP_POINTS:
        parser.error(f"argument --param: the grid has {size} points; at most "
                     f"{MAX_SWEEP_POINTS} are allowed")
    if not 1 <= args.workers <= _max_workers():
        parser.error(f"argument --workers: must be an integer in [1, {_max_workers()}] (4 per "
                     f"core); got {args.workers}")
    return grid


def _blocks(grid: dict[str, Any], points: int) -> Any:
    """Sub-grids of about ``points`` points, slices of the first parameter: in grid (C) order."""
    first, *rest = grid
    inner = math.prod(len(grid[name]) for name in rest)
    step = max(1, points // inner)
    for i in range(0, len(grid[first]), step):
        yield {first: grid[first][i:i + step], **{name: grid[name] for name in rest}}


def _json_value(value: Any) -> Any:
    """A table cell as JSON: null for a missing or non-finite number, Python types otherwise."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    number = float(value)
    return number if math.isfinite(number) else None


def _rows_text(table: Any, as_json: bool, header: bool) -> str:
    """A block of sweep rows as CSV (with the header if asked) or JSON Lines."""
    if as_json:
        records = table.astype(object).where(table.notna(), None).to_dict("records")
        return "\n".join(json.dumps({k: _json_value(v) for k, v in r.items()}, allow_nan=False)
                         for r in records)
    text = table.to_csv(index=False, header=header, float_format="%.17g")
    return str(text).rstrip("\n")


@contextlib.contextmanager
def _sigint_deferred() -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) until the block ends, then raise KeyboardInterrupt as usual.

    Without it a Ctrl-C during a large write cuts a row in half, or lands between writing rows
    and counting them. A handler that only records the signal, rather than a signal mask: the
    executor's threads would receive a masked SIGINT in the main thread's place.
    """
    pending: list[int] = []
    try:
        previous = signal.signal(signal.SIGINT, lambda signum, frame: pending.append(signum))
    except ValueError:  # not the main thread: signals cannot be handled here anyway
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if pending:
            raise KeyboardInterrupt


def _ignore_sigint_here() -> None:
    """Ignore SIGINT in this (main) thread; :func:`_sigint_remembered` restores the handler."""
    with contextlib.suppress(ValueError):  # not the main thread: not ours to handle
        signal.signal(signal.SIGINT, signal.SIG_IGN)


def _ignore_sigint() -> None:
    """Worker initializer: Ctrl-C is the parent's to handle (no traceback per worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _sweep(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """The ``sweep`` subcommand: rows on standard output, a block at a time (studies.sweep).

    Ctrl-C stops it after the rows finished so far (exit 130); a bad grid exits 2; a sweep that
    cannot run (pandas or tqdm missing), or in which no point gave an orbit (every row failed,
    e.g. every value of the grid is refused by Insect), exits 1 with a one-line summary.
    """
    grid = _sweep_grid(parser, args)
    insect = PRESETS[args.insect]()
    total, done, solved, first_failure = math.prod(len(v) for v in grid.values()), 0, 0, ""
    pool = None
    try:
        from concurrent.futures import ProcessPoolExecutor

        from tqdm import tqdm

        if args.workers > 1:
            pool = ProcessPoolExecutor(args.workers, initializer=_ignore_sigint)
        show = not args.quiet and sys.stderr.isatty()
        with tqdm(total=total, disable=not show, unit="orbit", desc="hover sweep") as bar:
            for block in _blocks(grid, _BLOCK_POINTS * args.workers):
                table = sweep_hover(insect, block, progress=False, executor=pool)
                _raise_if_interrupted()  # a Ctrl-C that a solver caught: this block is not kept
                with _sigint_deferred():  # a row is written whole, and counted, or not at all
                    if not _write(_rows_text(table, args.json, header=done == 0 and not args.json)):
                        return 1
                    done += len(table)
                bar.update(len(table))
                solved += int(table["status"].isin(_SOLVED).sum())
                if not first_failure and solved == 0 and len(table):
                    first_failure = str(table["message"].iloc[0])
    except KeyboardInterrupt:
        return _sweep_interrupted(parser.prog, done, total)
    except (ValueError, ImportError) as exc:
        if _is_interrupt(exc):
            return _sweep_interrupted(parser.prog, done, total)
        print(f"{parser.prog}: error: {_one_line(exc)}", file=sys.stderr)
        return 1
    except Exception as exc:  # numba turns a Ctrl-C in compiled code into a SystemError
        if not _is_interrupt(exc):
            raise
        return _sweep_interrupted(parser.prog, done, total)
    finally:
        if pool is not None:
            stop_process_pool(pool)  # running chunks too: nothing waits for them at exit
    if solved == 0 and total > 0:
        print(f"{parser.prog}: error: no point of the sweep gave an orbit ({total} of {total} "
              f"rows failed; the first: {_one_line(first_failure)[:300]})", file=sys.stderr)
        return 1
    return 0


def _sweep_interrupted(prog: str, done: int, total: int) -> int:
    """The one line after Ctrl-C in a sweep, and the exit status.

    A further Ctrl-C while the sweep stops (a pool's workers ended) is ignored until
    :func:`main` returns, so that one line is printed and the exit is 130 however often the
    user presses it (a second one used to land in the pool's shutdown or the interpreter's
    exit, with a traceback, and the process never ended).
    """
    _ignore_sigint_here()
    print(f"{prog}: interrupted: {done} of {total} points written", file=sys.stderr)
    return _INTERRUPTED

"""``python -m flapping fwuav``: FWUAV's hover exponents reproduced, as text or JSON."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

import numpy as np

from flapping.errors import ConvergenceError
from flapping.peers.fwuav.data import species
from flapping.peers.fwuav.floquet import NAMES, hover_floquet

__all__ = ["add_parser", "run", "report"]

_DESCRIPTION = """\
FWUAV's hover (fdcl-gwu/FWUAV at 1a25d41: body attitude, wing and abdomen motion prescribed,
Sane & Dickinson's quasi-steady force, wing inertia) rebuilt in flapping.peers.fwuav: the
periodic orbit of the thorax velocity by shooting, its six Floquet exponents [1/s] from the
variational equations (three zero for the position, two longitudinal, one lateral), and FWUAV's
own stored exponents with the relative difference."""

_EPILOG = """\
--json prints one JSON object with the keys name, period_s, frequency_hz, initial_state,
exponents, longitudinal, lateral, fwuav_exponents, fwuav_longitudinal, fwuav_lateral,
relative_difference (longitudinal pair, lateral), residual_norm, closure_error,
mean_velocity, liouville_error, provenance, units. Complex numbers are {"re": ..., "im": ...}.
exit status: 0 success, 1 the solver failed, 2 bad arguments."""

_UNITS = {"period_s": "s", "frequency_hz": "Hz", "initial_state": "m, m, m, m/s, m/s, m/s",
          "exponents": "1/s", "longitudinal": "1/s", "lateral": "1/s",
          "fwuav_exponents": "1/s", "fwuav_longitudinal": "1/s", "fwuav_lateral": "1/s",
          "relative_difference": "1", "residual_norm": "m/s", "closure_error": "m, m/s",
          "mean_velocity": "m/s", "liouville_error": "1"}


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``fwuav`` subcommand to the CLI's subparsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    parser = subparsers.add_parser(
        "fwuav", help="FWUAV's hover Floquet exponents, reproduced", description=_DESCRIPTION,
        epilog=_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--insect", default="hawkmoth", choices=NAMES, metavar="NAME",
                        help="one of " + ", ".join(NAMES) + " (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    return parser


def _complex(values: Any) -> list[dict[str, float]]:
    return [{"re": float(np.real(v)), "im": float(np.imag(v))} for v in np.atleast_1d(values)]


def report(name: str) -> dict[str, Any]:
    """The ``fwuav`` report of one insect as a JSON-ready dict (see the subcommand's help).

    Parameters
    ----------
    name : str
        One of :data:`flapping.peers.fwuav.floquet.NAMES`.

    Returns
    -------
    dict
    """
    r = hover_floquet(name)
    sp = species(name)
    return {
        "name": name, "period_s": r.period, "frequency_hz": 1.0 / r.period,
        "initial_state": [float(v) for v in r.x0], "exponents": _complex(r.exponents),
        "longitudinal": _complex(r.longitudinal), "lateral": _complex(r.lateral)[0],
        "fwuav_exponents": list(sp.stored_exponents),
        "fwuav_longitudinal": [float(v) for v in r.stored_longitudinal],
        "fwuav_lateral": r.stored_lateral,
        "relative_difference": {"longitudinal": [float(v) for v in r.relative_difference[:2]],
                                "lateral": float(r.relative_difference[2])},
        "residual_norm": r.residual_norm, "closure_error": r.closure_error,
        "mean_velocity": [float(v) for v in r.mean_velocity],
        "liouville_error": r.liouville_error, "provenance": sp.provenance, "units": _UNITS,
    }


def _text(rep: dict[str, Any]) -> str:
    ours = [e["re"] for e in rep["longitudinal"]] + [rep["lateral"]["re"]]
    theirs = rep["fwuav_longitudinal"] + [rep["fwuav_lateral"]]
    diff = rep["relative_difference"]["longitudinal"] + [rep["relative_difference"]["lateral"]]
    lines = [f"FWUAV hover of the {rep['name']}: f = {rep['frequency_hz']:.6g} Hz, "
             f"shooting residual {rep['residual_norm']:.2e} m/s",
             f"{'exponent [1/s]':<16}{'ours':>12}{'FWUAV':>12}{'difference':>12}"]
    for label, a, b, d in zip(("longitudinal 1", "longitudinal 2", "lateral"), ours, theirs,
                              diff, strict=True):
        lines.append(f"{label:<16}{a:>12.5f}{b:>12.5f}{d:>11.3%}")
    return "\n".join(lines)


def run(args: argparse.Namespace, prog: str = "flapping") -> int:
    """Run the ``fwuav`` subcommand; the exit status (0, or 1 if the solver fails).

    Parameters
    ----------
    args : argparse.Namespace
        Parsed arguments (``insect``, ``json``).
    prog : str, optional
        Program name for the one-line error message.

    Returns
    -------
    int
    """
    try:
        rep = report(args.insect)
        text = json.dumps(rep, allow_nan=False) if args.json else _text(rep)
    except (ValueError, ConvergenceError, ArithmeticError) as exc:
        print(f"{prog}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 1
    print(text, flush=True)
    return 0

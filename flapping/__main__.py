"""Command line: ``python -m flapping hover [--insect hawkmoth] [--aerodynamics linear] [--json]``.

Prints the hovering periodic orbit of a preset insect and its Floquet stability. Bad arguments exit
with status 2 and a one-line message; a solver failure exits with status 1 and a one-line message.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Sequence

from flapping.model.dynamics import AERODYNAMIC_MODELS, STATE_NAMES
from flapping.errors import ConvergenceError
from flapping.model.morphology import hawkmoth

PRESETS = {"hawkmoth": hawkmoth}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # one line, no usage dump
        self.exit(2, f"{self.prog}: error: {message}\n")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="python -m flapping", description=__doc__.splitlines()[0])
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    hover = sub.add_parser("hover", help="hovering orbit and its Floquet multipliers")
    hover.add_argument("--insect", default="hawkmoth", choices=sorted(PRESETS),
                       help="preset insect (default: hawkmoth)")
    hover.add_argument("--aerodynamics", default="linear", choices=AERODYNAMIC_MODELS,
                       help="aerodynamic model (default: linear, the paper's eq. 29)")
    hover.add_argument("--json", action="store_true", help="print one JSON object")
    return parser


def _complex_list(values) -> list[dict[str, float]]:
    return [{"re": float(v.real), "im": float(v.imag)} for v in values]


def hover_report(insect_name: str, aerodynamics: str) -> dict:
    """The hover orbit and its stability as a JSON-ready dict (SI units, theta in rad)."""
    from flapping.hover import find_hover_orbit
    from flapping.stability import hover_stability

    insect = PRESETS[insect_name]()
    orbit = find_hover_orbit(insect, aerodynamics=aerodynamics)
    stab = hover_stability(orbit)
    return {
        "insect": insect.name,
        "aerodynamics": aerodynamics,
        "amplitude_deg": orbit.amplitude_deg,
        "alpha_m_deg": math.degrees(orbit.model.alpha_m),
        "initial_state": {k: float(v) for k, v in zip(STATE_NAMES, orbit.x0)},
        "period_s": orbit.period,
        "residual_norm": orbit.residual_norm,
        "mean_inertial_velocity": orbit.mean_inertial_velocity,
        "multipliers": _complex_list(stab.multipliers),
        "floquet_exponents": _complex_list(stab.exponents),
        "det_monodromy": stab.det,
        "liouville_det": stab.liouville_det,
        "averaged_eigenvalues": _complex_list(stab.averaged_eigenvalues),
        "stable": stab.is_stable,
    }


def _text(report: dict) -> str:
    x0 = report["initial_state"]
    lines = [
        f"{report['insect']} hover ({report['aerodynamics']} aerodynamics)",
        f"  stroke amplitude Phi = {report['amplitude_deg']:.6f} deg "
        f"(alpha_m = {report['alpha_m_deg']:.4f} deg, T = {report['period_s']:.6f} s)",
        f"  initial state: u = {x0['u']:.6g} m/s, w = {x0['w']:.6g} m/s, "
        f"q = {x0['q']:.6g} rad/s, theta = {x0['theta']:.6g} rad",
        f"  shooting residual {report['residual_norm']:.2e}",
        "  Floquet multipliers:",
    ]
    for mu in report["multipliers"]:
        lines.append(f"    {mu['re']:+.6f} {mu['im']:+.6f}i   |mu| = {math.hypot(mu['re'], mu['im']):.6f}")
    lines.append(f"  det M = {report['det_monodromy']:.10g}, Liouville exp(int tr J) = "
                 f"{report['liouville_det']:.10g}")
    lines.append("  averaged-system eigenvalues [1/s]: " + ", ".join(
        f"{e['re']:+.4g}{e['im']:+.4g}i" for e in report["averaged_eigenvalues"]))
    lines.append("  hover is " + ("stable" if report["stable"] else "UNSTABLE"))
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point; returns the exit status."""
    args = _parser().parse_args(argv)
    try:
        report = hover_report(args.insect, args.aerodynamics)
    except (ValueError, ConvergenceError) as exc:
        print(f"python -m flapping: error: {exc}", file=sys.stderr)
        return 1
    print(json.dumps(report) if args.json else _text(report))
    return 0


if __name__ == "__main__":
    sys.exit(main())

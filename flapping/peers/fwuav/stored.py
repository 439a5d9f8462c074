"""The hawkmoth's pitch-free results of the chapter "A second model", computed once and stored.

The chapter's pitch-free study (:func:`~flapping.peers.fwuav.attitude.pitch_free_floquet` on
FWUAV's kinematics and re-trimmed, with both body-rate terms, and the re-trimmed hover at a
tenfold tighter tolerance) is about 90 % of the chapter's execution: a minute and a half of CPU
on the central-difference Jacobians of the pitch-free model. It is computed once by::

    python -m flapping.peers.fwuav.stored book/data/fwuav_pitch_free.json

and the chapter loads the file. JSON keeps every float exactly (Python writes the shortest
repr that reads back to the same double), so what the chapter computes from a loaded result is
bit for bit what it computes from a fresh one. ``tests/peers/test_fwuav_stored.py`` checks the
versioned file: its cases are the ones listed here, and recomputed entries agree with it to the
study's tolerance.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from flapping.peers.fwuav.attitude import PitchFreeFloquet, pitch_free_floquet

__all__ = ["CASES", "compute", "to_json", "from_json", "write", "load"]

#: What the chapter uses: key -> keyword arguments of ``pitch_free_floquet("hawkmoth", ...)``.
CASES: dict[str, dict[str, Any]] = {
    "free fwuav": {"body_rate_term": "fwuav", "rtol": 1e-8, "trim": False},
    "free rotated": {"body_rate_term": "rotated", "rtol": 1e-8, "trim": False},
    "trimmed fwuav": {"body_rate_term": "fwuav", "rtol": 1e-8, "trim": True},
    "trimmed rotated": {"body_rate_term": "rotated", "rtol": 1e-8, "trim": True},
    "trimmed fwuav rtol 1e-9": {"body_rate_term": "fwuav", "rtol": 1e-9, "trim": True},
}
NAME = "hawkmoth"


def compute(key: str) -> PitchFreeFloquet:
    """The result of case ``key`` of :data:`CASES`, computed now."""
    return pitch_free_floquet(NAME, **CASES[key])


def _array(a: np.ndarray) -> dict[str, Any]:
    a = np.asarray(a)
    if np.iscomplexobj(a):
        return {"real": a.real.tolist(), "imag": a.imag.tolist()}
    return {"real": a.tolist()}


def _unarray(d: dict[str, Any]) -> np.ndarray:
    real = np.array(d["real"], dtype=float)
    return real + 1j * np.array(d["imag"], dtype=float) if "imag" in d else real


_ARRAYS = ("y0", "multipliers", "exponents", "mean_velocity", "monodromy")
_FLOATS = ("period", "mean_pitch", "pitch_amplitude", "residual_norm", "liouville_error")


def to_json(result: PitchFreeFloquet) -> dict[str, Any]:
    """Every field of ``result`` as JSON types (complex arrays as real and imaginary parts)."""
    out: dict[str, Any] = {"name": result.name, "body_rate_term": result.body_rate_term}
    out.update({k: _array(getattr(result, k)) for k in _ARRAYS})
    out.update({k: float(getattr(result, k)) for k in _FLOATS})
    out.update(trim_parameters=list(result.trim_parameters),
               trim_values=[float(v) for v in result.trim_values],
               trim_nfev=int(result.trim_nfev))
    return out


def from_json(d: dict[str, Any]) -> PitchFreeFloquet:
    """The :class:`PitchFreeFloquet` that :func:`to_json` wrote."""
    fields: dict[str, Any] = {k: _unarray(d[k]) for k in _ARRAYS}
    fields.update({k: float(d[k]) for k in _FLOATS})
    return PitchFreeFloquet(
        name=d["name"], body_rate_term=d["body_rate_term"], **fields,
        trim_parameters=tuple(d["trim_parameters"]),
        trim_values=tuple(float(v) for v in d["trim_values"]), trim_nfev=int(d["trim_nfev"]))


def write(path: str | Path) -> None:
    """Compute every case of :data:`CASES` and write them to ``path`` (JSON)."""
    data = {"what": "pitch_free_floquet('hawkmoth', **case) of flapping.peers.fwuav.stored",
            "cases": {key: {"arguments": CASES[key], "result": to_json(compute(key))}
                      for key in CASES}}
    Path(path).write_text(json.dumps(data, indent=1) + "\n")


def load(path: str | Path) -> dict[str, PitchFreeFloquet]:
    """The stored results by case key.

    Raises
    ------
    ValueError
        If the file's cases or their arguments are not :data:`CASES` (a stale file).
    """
    data = json.loads(Path(path).read_text())
    cases = data["cases"]
    given = {key: case["arguments"] for key, case in cases.items()}
    if given != CASES:
        raise ValueError(f"`path` {path} holds other cases than CASES: rewrite it with "
                         "`python -m flapping.peers.fwuav.stored PATH`")
    return {key: from_json(case["result"]) for key, case in cases.items()}


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python -m flapping.peers.fwuav.stored PATH.json")
    write(sys.argv[1])

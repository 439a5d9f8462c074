"""Studies computed once and stored: the explorer's grid, the robustness appendix's global study,
the control chapter's stable windows.

Some of the book's studies take minutes and do not change unless the model does: the explorer's
grid (:func:`~flapping.studies.explorer.explore_hover`, 450 blade-element orbits), the global
sensitivity study's sample (:func:`~flapping.studies.sensitivity.global_sensitivity`, six
species at 256 base samples, 13 824 orbits) and its check against the full model
(:func:`~flapping.studies.sensitivity.reduction_check` and
:func:`~flapping.studies.sensitivity.nominal_reduction`, fixed-step solves with two trims), and
the control chapter's stable windows (:func:`~flapping.studies.control.stable_window` of five
species, each crossing located by brentq and checked by a second route on the adaptive path).
``python scripts/book_data.py`` runs them with the current code and writes their results with
the ``save_*`` functions here (``book/_data/``, versioned); the chapters read them back with the
``load_*`` ones, and ``tests/book/test_stored.py`` solves sampled points again and compares them
with the files, so a model change that moves them fails the tests until the files are written
again.

What is stored is what the solves produced, bit for bit (NumPy's ``.npz``, float64): the
explorer's tables, and the sensitivity sweep's per-point outputs (the largest multiplier, whether
the point converged, was retried, its message and backend). The Saltelli sample, the Sobol
indices and the bootstrap intervals are cheap and deterministic: :func:`load_global_sensitivity`
computes them again from the stored outputs exactly as :func:`~flapping.studies.sensitivity.
global_sensitivity` does, so a loaded study equals a computed one.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from flapping.studies import sensitivity as _gs
from flapping.studies.control import PassiveCrossing
from flapping.studies.explorer import AXES, Exploration, ExplorerGrid

if TYPE_CHECKING:  # pragma: no cover
    import pandas

__all__ = ["save_exploration", "load_exploration", "save_global_sensitivity",
           "load_global_sensitivity", "study_from_outputs", "save_reduction_checks",
           "load_reduction_checks", "save_windows", "load_windows", "SWEEP_COLUMNS"]

#: The sensitivity sweep's outputs a stored study keeps per point (the rest is recomputed).
SWEEP_COLUMNS = ("mu1_real", "mu1_imag", "converged", "message", "backend", "retried")
_STATES = ("u", "w", "q", "theta")


# =========================================================================== tables
def _columns(prefix: str, frame: pandas.DataFrame) -> dict[str, np.ndarray]:
    """Each column of ``frame`` as a plain array (text as fixed-width unicode, no pickles)."""
    out = {}
    for name in frame.columns:
        values = frame[name].to_numpy()
        if values.dtype == object or values.dtype.kind in "OUT":
            if not all(isinstance(v, str) for v in values):  # a NaN would come back as "nan"
                raise ValueError(f"column {name!r}: text with a missing value cannot be stored")
            values = np.asarray(values.tolist(), dtype=str)
        out[f"{prefix}{name}"] = values
    return out


def _frame(data: Any, prefix: str, names: list[str]) -> pandas.DataFrame:
    import pandas

    return pandas.DataFrame({name: data[f"{prefix}{name}"] for name in names})


def _meta(data: Any) -> dict[str, Any]:
    return dict(json.loads(str(data["meta"])))


def _write(path: str | Path, meta: dict[str, Any], arrays: dict[str, np.ndarray]) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    arrays = {"meta": np.asarray(json.dumps(meta, sort_keys=True)), **arrays}
    np.savez_compressed(path, **arrays)  # type: ignore[arg-type]  # numpy's stub: allow_pickle
    return path


# =========================================================================== the explorer
def save_exploration(exploration: Exploration, path: str | Path,
                     **meta: Any) -> Path:
    """Write an explorer's grid, solved, to ``path`` (``.npz``).

    Parameters
    ----------
    exploration : Exploration
        From :func:`~flapping.studies.explorer.explore_hover`.
    path : str or Path
    **meta
        JSON-serialisable facts of the run, kept beside the tables (e.g. its wall and CPU time).

    Returns
    -------
    Path
        The file written.
    """
    points, orbits = exploration.points, exploration.orbits
    n = exploration.n_samples
    # The orbits table is n + 1 phases x 4 states per converged point (explore_hover's order):
    # kept as one array, rebuilt exactly on load.
    index = np.unique(orbits["point"].to_numpy()) if len(orbits) else np.zeros(0, dtype=int)
    values = orbits["value"].to_numpy(dtype=float).reshape(index.size, len(_STATES), n + 1)
    grid = exploration.grid
    meta = {**meta, "n_samples": n, "point_columns": list(points.columns),
            "grid": {"species": list(grid.species), "frequency_ratio": list(grid.frequency_ratio),
                     "hinge_height_ratio": list(grid.hinge_height_ratio),
                     "wing_mass_percent": list(grid.wing_mass_percent)}}
    return _write(path, meta, {**_columns("points/", points), "orbits/point": index,
                               "orbits/value": values})


def load_exploration(path: str | Path) -> tuple[Exploration, dict[str, Any]]:
    """Read an explorer's grid written by :func:`save_exploration`.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    exploration : Exploration
        Equal to the one saved (the same tables, bit for bit).
    meta : dict
        The facts of the run saved with it.
    """
    import pandas

    with np.load(path, allow_pickle=False) as data:
        meta = _meta(data)
        points = _frame(data, "points/", meta["point_columns"])
        index, values = data["orbits/point"], data["orbits/value"]
    n = int(meta["n_samples"])
    phase = np.linspace(0.0, 1.0, n + 1)
    blocks = [pandas.DataFrame({"point": np.repeat(i, x.size), "phase": np.tile(phase, 4),
                                "state": np.repeat(_STATES, phase.size), "value": x.ravel()})
              for i, x in zip(index.tolist(), values, strict=True)]
    orbits = (pandas.concat(blocks, ignore_index=True) if blocks
              else pandas.DataFrame(columns=["point", "phase", "state", "value"]))
    grid = ExplorerGrid(**{k: tuple(v) for k, v in meta["grid"].items()})
    assert list(points.columns[:len(AXES)]) == list(AXES)
    return Exploration(grid, points, orbits, n), meta


# =========================================================================== global sensitivity
def save_global_sensitivity(studies: dict[str, _gs.GlobalSensitivity], path: str | Path, *,
                            n_base: int, seed: int, num_resamples: int = 200,
                            **meta: Any) -> Path:
    """Write the per-point outputs of global sensitivity studies (one per species) to ``path``.

    Parameters
    ----------
    studies : dict of str to GlobalSensitivity
        From :func:`~flapping.studies.sensitivity.global_sensitivity`, by species.
    path : str or Path
    n_base, seed, num_resamples : int
        The arguments the studies were run with (a load recomputes the sample and the indices
        from them).
    **meta
        JSON-serialisable facts of the run (e.g. the command).

    Returns
    -------
    Path
    """
    arrays: dict[str, np.ndarray] = {}
    for species, study in studies.items():
        arrays.update(_columns(f"{species}/", study.samples[list(SWEEP_COLUMNS)]))
    meta = {**meta, "species": list(studies), "n_base": n_base, "seed": seed,
            "num_resamples": num_resamples,
            "wall_time_s": {s: study.wall_time_s for s, study in studies.items()}}
    return _write(path, meta, arrays)


def load_global_sensitivity(path: str | Path) -> tuple[dict[str, _gs.GlobalSensitivity],
                                                       dict[str, Any]]:
    """Read studies written by :func:`save_global_sensitivity`: the sample, the indices and the
    probabilities computed again from the stored outputs, as
    :func:`~flapping.studies.sensitivity.global_sensitivity` computes them.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    studies : dict of str to GlobalSensitivity
        By species, in the order saved; each equal to the one computed.
    meta : dict
        The facts of the run saved with them.
    """
    with np.load(path, allow_pickle=False) as data:
        meta = _meta(data)
        outputs = {s: _frame(data, f"{s}/", list(SWEEP_COLUMNS)) for s in meta["species"]}
    studies = {s: study_from_outputs(s, outputs[s], n_base=meta["n_base"], seed=meta["seed"],
                                     num_resamples=meta["num_resamples"],
                                     wall_time_s=meta["wall_time_s"][s])
               for s in meta["species"]}
    return studies, meta


def study_from_outputs(species: str, outputs: pandas.DataFrame, *, n_base: int, seed: int,
                       num_resamples: int, wall_time_s: float) -> _gs.GlobalSensitivity:
    """A :class:`~flapping.studies.sensitivity.GlobalSensitivity` from its sweep's outputs
    (:data:`SWEEP_COLUMNS`, one row per point of the Saltelli sample, in order): the part of
    :func:`~flapping.studies.sensitivity.global_sensitivity` after its sweep, step for step."""
    import pandas

    ranges = _gs.input_ranges(species)
    problem = _gs._problem({r.name: (r.low, r.high) for r in ranges})
    x = _gs._sample(problem, n_base, seed)
    if len(outputs) != len(x):
        raise ValueError(f"{species}: {len(outputs)} stored points, the sample of n_base = "
                         f"{n_base} has {len(x)}")
    points = [dict(zip(_gs.INPUTS, row, strict=True)) for row in x.tolist()]
    insects = [_gs._insect(species, point, full_model=False) for point in points]
    converged = outputs["converged"].to_numpy(dtype=bool)
    mu = outputs["mu1_real"].to_numpy(float) + 1j * outputs["mu1_imag"].to_numpy(float)
    modulus = np.where(converged, np.abs(mu), np.nan)
    samples = pandas.DataFrame(x, columns=list(_gs.INPUTS))
    samples["h_stroke"] = [i.hinge_height for i in insects]
    samples["mu1_real"], samples["mu1_imag"] = mu.real, mu.imag
    samples["abs_mu1"] = modulus
    samples["converged"] = converged
    samples["mode"] = [_gs._mode(complex(m)) if ok else ""
                       for m, ok in zip(mu, converged, strict=True)]
    samples["message"] = outputs["message"].to_numpy()
    samples["backend"] = outputs["backend"].to_numpy()
    retried = outputs["retried"].to_numpy(dtype=bool)
    samples["retried"] = retried
    indices, _ = _gs._analyse(problem, np.log(modulus), n_base, seed, num_resamples, 0.95)
    unstable = converged & (modulus > 1.0)
    oscillatory = unstable & (samples["mode"].to_numpy() == "oscillatory")
    n_ok = int(converged.sum())
    p_u = float(unstable.sum() / n_ok)
    p_o = float(oscillatory.sum() / n_ok)
    ci_u, ci_o = _gs._bootstrap(converged, (unstable, oscillatory), n_base, len(_gs.INPUTS) + 2,
                                num_resamples, seed)
    return _gs.GlobalSensitivity(species, ranges, indices, samples, p_u, p_o, p_u - p_o, ci_u,
                                 ci_o, len(points), len(points) - n_ok, int(retried.sum()),
                                 float(wall_time_s))


# =========================================================================== the reduction
def save_reduction_checks(checks: dict[str, _gs.ReductionCheck],
                          terms: dict[str, dict[str, complex]], path: str | Path, *,
                          n_points: int, seed: int, **meta: Any) -> Path:
    """Write reduction checks (one per species) and nominal reductions to ``path``.

    Parameters
    ----------
    checks : dict of str to ReductionCheck
        From :func:`~flapping.studies.sensitivity.reduction_check`, by species.
    terms : dict of str to dict
        From :func:`~flapping.studies.sensitivity.nominal_reduction`, by species.
    path : str or Path
    n_points, seed : int
        The arguments the checks were run with.
    **meta
        JSON-serialisable facts of the run.

    Returns
    -------
    Path
    """
    arrays: dict[str, np.ndarray] = {}
    for species, check in checks.items():
        arrays.update(_columns(f"check/{species}/", check.table))
    for species, models in terms.items():
        arrays[f"terms/{species}"] = np.array(list(models.values()), dtype=complex)
    first = next(iter(checks.values())).table
    meta = {**meta, "species": list(checks), "n_points": n_points, "seed": seed,
            "columns": list(first.columns),
            "terms": {species: list(models) for species, models in terms.items()}}
    return _write(path, meta, arrays)


def load_reduction_checks(path: str | Path) -> tuple[dict[str, _gs.ReductionCheck],
                                                     dict[str, dict[str, complex]],
                                                     dict[str, Any]]:
    """Read what :func:`save_reduction_checks` wrote.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    checks : dict of str to ReductionCheck
        By species; each table equal to the one saved.
    terms : dict of str to dict of str to complex
        The nominal reductions, by species and model.
    meta : dict
        The facts of the run saved with them.
    """
    with np.load(path, allow_pickle=False) as data:
        meta = _meta(data)
        checks = {s: _gs.ReductionCheck(s, _frame(data, f"check/{s}/", meta["columns"]))
                  for s in meta["species"]}
        terms = {s: dict(zip(models, (complex(v) for v in data[f"terms/{s}"]), strict=True))
                 for s, models in meta["terms"].items()}
    return checks, terms, meta


# =========================================================================== stable windows
def save_windows(windows: dict[str, tuple[PassiveCrossing, PassiveCrossing]],
                 path: str | Path, **meta: Any) -> Path:
    """Write the stable windows of passive sweeps (one per species) to ``path``.

    Parameters
    ----------
    windows : dict of str to (PassiveCrossing, PassiveCrossing)
        From :func:`~flapping.studies.control.stable_window`, by species (none may be None).
    path : str or Path
    **meta
        JSON-serialisable facts of the run.

    Returns
    -------
    Path
    """
    arrays: dict[str, np.ndarray] = {}
    for species, pair in windows.items():
        arrays[f"{species}/hinge_height"] = np.array([c.hinge_height for c in pair])
        arrays[f"{species}/kind"] = np.array([c.kind for c in pair], dtype=str)
        arrays[f"{species}/multipliers"] = np.stack([c.multipliers for c in pair])
        arrays[f"{species}/stabilising"] = np.array([c.stabilising for c in pair])
        arrays[f"{species}/check_height"] = np.array([c.check_height for c in pair])
    return _write(path, {**meta, "species": list(windows)}, arrays)


def load_windows(path: str | Path) -> tuple[dict[str, tuple[PassiveCrossing, PassiveCrossing]],
                                            dict[str, Any]]:
    """Read what :func:`save_windows` wrote.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    windows : dict of str to (PassiveCrossing, PassiveCrossing)
        By species, equal to those saved.
    meta : dict
        The facts of the run saved with them.
    """
    with np.load(path, allow_pickle=False) as data:
        meta = _meta(data)
        windows = {}
        for s in meta["species"]:
            fields = [data[f"{s}/{k}"] for k in ("hinge_height", "kind", "multipliers",
                                                 "stabilising", "check_height")]
            entry, leave = (PassiveCrossing(float(h), str(k), np.array(m), bool(b), float(c))
                            for h, k, m, b, c in zip(*fields, strict=True))
            windows[s] = (entry, leave)
    return windows, meta

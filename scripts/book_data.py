"""Compute the book's stored studies once and write them to book/_data/ (versioned).

These studies take minutes and change only when the model does, so the book reads them from files
(:mod:`flapping_book.stored`) instead of solving them at every build:

- ``explorer``: the explorer chapter's grid, ``explore_hover(DEFAULT_GRID)`` on two worker
  processes -> ``book/_data/explorer.npz`` (with the run's wall and CPU time);
- ``sensitivity``: the robustness appendix's global study, ``global_sensitivity(name, 256,
  seed=0)`` for the six presets -> ``book/_data/global_sensitivity.npz``;
- ``reduction``: its check against the full model, ``reduction_check(name, 2, seed=0)`` for the
  six presets and ``nominal_reduction`` of the hawkmoth and the monarch ->
  ``book/_data/reduction_check.npz``;
- ``windows``: the control chapter's stable windows, ``stable_window(passive_sweep(preset(name),
  linspace(0, body length, 25)), check=True)`` for its five species ->
  ``book/_data/passive_windows.npz``;
- ``fwuav``: the second model's pitch-free cases, ``pitch_free_floquet("hawkmoth", ...)`` for
  ``flapping.studies.fwuav.PITCH_FREE_CASES`` -> ``book/_data/fwuav_pitch_free.json`` (checked
  by ``tests/test_fwuav_ours.py``).

Each file is read back and compared with what was just computed before the script ends.
``tests/book/test_stored.py`` solves sampled points again and compares them with the files:
after a change that moves them, run this script again and commit the files.

    python scripts/book_data.py [explorer] [sensitivity] [reduction] [windows] [fwuav]   # all
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from pandas.testing import assert_frame_equal

from flapping.errors import PlausibilityWarning
from flapping.model.presets import PRESETS, preset
from flapping.studies import control
from flapping.studies import sensitivity as gs
from flapping.studies.explorer import DEFAULT_GRID, explore_hover
from flapping_book import stored

DATA = Path(__file__).resolve().parents[1] / "book" / "_data"
EXPLORER = DATA / "explorer.npz"
SENSITIVITY = DATA / "global_sensitivity.npz"
REDUCTION = DATA / "reduction_check.npz"
WINDOWS = DATA / "passive_windows.npz"
FWUAV_PITCH_FREE = DATA / "fwuav_pitch_free.json"
#: The control chapter's species (the monarch left out: its hover leaves the linear loads' range).
CONTROL_SPECIES = ("hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly")
#: The book's sample of the global study: 9 x 256 orbits a species (the full study,
#: scripts/global_sensitivity.py, runs 2048).
N_BOOK, SEED = 256, 0
#: Points of the reduction check per species, and the species of the nominal reduction.
N_CHECK, NOMINAL = 2, ("hawkmoth", "monarch")


def _machine() -> dict[str, object]:
    return {"command": "python scripts/book_data.py", "python": platform.python_version(),
            "cpu_count": os.cpu_count(), "load_average": list(os.getloadavg()),
            "date": time.strftime("%Y-%m-%d", time.gmtime())}


def explorer(path: Path = EXPLORER) -> None:
    """The explorer's grid on two worker processes, as the chapter ran it."""
    workers = min(2, os.cpu_count() or 1)
    t0, cpu0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    with ProcessPoolExecutor(workers) as pool:
        exploration = explore_hover(DEFAULT_GRID, executor=pool)
    wall = time.perf_counter() - t0
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    stored.save_exploration(exploration, path, wall_time_s=wall, cpu_time_s=cpu,
                            workers=workers, **_machine())
    again, _ = stored.load_exploration(path)
    assert_frame_equal(again.points, exploration.points, check_exact=True)
    assert_frame_equal(again.orbits, exploration.orbits, check_exact=True)
    print(f"explorer: {len(exploration.points)} points in {wall:.0f} s ({cpu:.0f} s CPU) "
          f"-> {path} ({path.stat().st_size / 1e3:.0f} kB)", flush=True)


def sensitivity(path: Path = SENSITIVITY) -> None:
    """The global study of every preset at the book's sample, as the appendix ran it."""
    started = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        studies = {name: gs.global_sensitivity(name, N_BOOK, seed=SEED) for name in PRESETS}
    wall = time.perf_counter() - started
    stored.save_global_sensitivity(studies, path, n_base=N_BOOK, seed=SEED,
                                   total_wall_time_s=wall, **_machine())
    again, _ = stored.load_global_sensitivity(path)
    for name, study in studies.items():
        assert_frame_equal(again[name].samples, study.samples, check_exact=True)
        assert_frame_equal(again[name].table(), study.table(), check_exact=True)
        assert np.array_equal(again[name].indices.total_conf, study.indices.total_conf)
        assert (again[name].p_unstable_ci, again[name].p_oscillatory_ci) == (
            study.p_unstable_ci, study.p_oscillatory_ci)
    print(f"sensitivity: {sum(s.n_orbits for s in studies.values())} orbits in {wall:.0f} s "
          f"-> {path} ({path.stat().st_size / 1e3:.0f} kB)", flush=True)


def reduction(path: Path = REDUCTION) -> None:
    """The reduced model against the full one, as the appendix ran it."""
    started = time.perf_counter()
    checks = {name: gs.reduction_check(name, N_CHECK, seed=SEED) for name in PRESETS}
    terms = {name: gs.nominal_reduction(name) for name in NOMINAL}
    wall = time.perf_counter() - started
    stored.save_reduction_checks(checks, terms, path, n_points=N_CHECK, seed=SEED,
                                 wall_time_s=wall, **_machine())
    again, again_terms, _ = stored.load_reduction_checks(path)
    for name, check in checks.items():
        assert_frame_equal(again[name].table, check.table, check_exact=True)
    assert again_terms == terms
    print(f"reduction: {N_CHECK} points x {len(checks)} species and {len(terms)} nominal "
          f"in {wall:.0f} s -> {path} ({path.stat().st_size / 1e3:.0f} kB)", flush=True)


def windows(path: Path = WINDOWS) -> None:
    """The stable windows of the control chapter's passive sweeps, as the chapter ran them."""
    found, walls = {}, {}
    for name in CONTROL_SPECIES:
        started = time.perf_counter()
        sweep = control.passive_sweep(preset(name),
                                      np.linspace(0.0, control.BODY_LENGTHS[name], 25))
        window = control.stable_window(sweep, check=True)
        assert window is not None, name
        found[name], walls[name] = window, time.perf_counter() - started
    stored.save_windows(found, path, wall_time_s=walls, **_machine())
    again, _ = stored.load_windows(path)
    for name, pair in found.items():
        for a, b in zip(again[name], pair, strict=True):
            assert (a.hinge_height, a.kind, a.stabilising, a.check_height) == (
                b.hinge_height, b.kind, b.stabilising, b.check_height)
            assert np.array_equal(a.multipliers, b.multipliers)
    print(f"windows: {len(found)} species in {sum(walls.values()):.0f} s -> {path} "
          f"({path.stat().st_size / 1e3:.0f} kB)", flush=True)


def fwuav(path: Path = FWUAV_PITCH_FREE) -> None:
    """The hawkmoth's pitch-free FWUAV cases of the chapter "A second model"."""
    from flapping.studies.fwuav import write_pitch_free_study

    started = time.perf_counter()
    write_pitch_free_study(path)
    print(f"fwuav: pitch-free cases in {time.perf_counter() - started:.0f} s -> {path} "
          f"({path.stat().st_size / 1e3:.0f} kB)", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    studies = {"explorer": explorer, "sensitivity": sensitivity, "reduction": reduction,
               "windows": windows, "fwuav": fwuav}
    parser.add_argument("study", nargs="*", help=f"of {sorted(studies)} (default: all)")
    names = parser.parse_args().study or list(studies)
    for name in names:
        if name not in studies:
            parser.error(f"unknown study {name!r}: choose from {sorted(studies)}")
    for name in names:
        studies[name]()


if __name__ == "__main__":
    main()

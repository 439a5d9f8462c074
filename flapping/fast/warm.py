"""Compile every numba entry point of :mod:`flapping.fast` ahead of use: :func:`warm_up`.

For installs, clusters and CI (``python -m flapping compile`` runs it): afterwards every process
loads the machine code from numba's on-disk cache (~0.1 s) instead of compiling it on a first
call (seconds). Where the cache is is numba's choice, ``NUMBA_CACHE_DIR`` if set (see
:mod:`flapping.fast._jit`); a shared, writable ``NUMBA_CACHE_DIR`` lets every node of a cluster
load what one compiled.
"""

from __future__ import annotations

import importlib
import pkgutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

__all__ = ["WarmUp", "warm_up"]


@dataclass(frozen=True)
class WarmUp:
    """What :func:`warm_up` did.

    Attributes
    ----------
    compiled : tuple of str
        The entry points numba compiled (``module.function``).
    loaded : tuple of str
        The entry points loaded from numba's cache.
    ready : tuple of str
        The entry points this process had compiled or loaded before.
    missed : tuple of str
        Modules none of whose entry points a warm-up reached (a compiled module without a
        warm-up: it compiles on first use). The entry points that only compiled code calls
        (linked into their callers' machine code) are in none of the lists.
    seconds : float
        Wall time of the warm-up [s].
    cache_dir : pathlib.Path or None
        numba's cache directory of the hover kernel (None: numba found no writable place, and
        nothing persists).
    """

    compiled: tuple[str, ...]
    loaded: tuple[str, ...]
    ready: tuple[str, ...]
    missed: tuple[str, ...]
    seconds: float
    cache_dir: Path | None

    def __str__(self) -> str:
        where = self.cache_dir if self.cache_dir is not None else "no disk cache (not writable)"
        lines = [f"{len(self.compiled)} compiled, {len(self.loaded)} loaded from the cache, "
                 f"{len(self.ready)} ready in {self.seconds:.1f} s; numba's cache: {where}"]
        lines += [f"  not warmed up (compiles on first use): {name}" for name in self.missed]
        return "\n".join(lines)


def _sixdof() -> None:
    """The six-degree-of-freedom linear path's entry points on the hawkmoth (plain, variational
    and per-segment integrations, the argument types of :mod:`flapping.hover.sixdof`)."""
    import numpy as np

    from flapping.fast import _sixdof
    from flapping.model.morphology import hawkmoth
    from flapping.model.sixdof import SixDofDynamics

    insect = hawkmoth()
    model = SixDofDynamics(insect, insect.stroke_amplitude, None, "linear")
    x0 = np.zeros(8)
    for variational in (False, True):
        _sixdof.flow(model, x0, insect.stroke_amplitude, 4, variational)
    _sixdof.monodromy_factors(model, x0, insect.stroke_amplitude, _sixdof.FACTORS_PER_HALF_STROKE)


def _steps() -> list[tuple[str, Callable[[], object]]]:
    """The warm-ups, in order: the default path's kernel first; then every module of
    :mod:`flapping.fast` that defines its own ``warm_up()`` (a new compiled module adds one)."""
    from flapping.fast import blade, kernel

    steps: list[tuple[str, Callable[[], object]]] = [
        ("hover kernel (flapping.fast.kernel)", kernel.warm_up),
        ("blade-element loads (flapping.fast.blade)", blade.load),
        ("six degrees of freedom, linear loads (flapping.fast._sixdof)", _sixdof),
    ]
    package = __name__.rpartition(".")[0]  # flapping.fast, found by path (no import of it)
    for info in pkgutil.iter_modules([str(Path(__file__).parent)]):
        name = f"{package}.{info.name}"
        if name in (kernel.__name__, __name__):
            continue
        module = importlib.import_module(name)  # registers its entry points
        hook = getattr(module, "warm_up", None)
        if callable(hook) and getattr(hook, "__module__", None) == name:
            steps.append((name, hook))
    return steps


def warm_up(progress: Callable[[str], object] | None = None) -> WarmUp:
    """Compile (or load from numba's cache) every numba entry point of every fast module.

    Each runs once on the hawkmoth with the argument types the package uses, whatever
    ``FLAPPING_FIRST_CALL`` says; numba writes what it compiles to its on-disk cache, so later
    processes load it. With a warm cache it only loads (about a second in all).

    Parameters
    ----------
    progress : callable, optional
        Called with one line per step (e.g. ``print``).

    Returns
    -------
    WarmUp
        What was compiled, loaded or missed, and the time.

    Raises
    ------
    ImportError
        If numba is not installed (``pip install flapping[fast]``).
    """
    import numba  # noqa: F401 - the ImportError, before any work

    from flapping.fast import _jit, kernel

    say = progress if progress is not None else (lambda line: None)
    _jit.announce_quietly()  # asked for: no note that numba compiles (the lines say it)
    start = time.perf_counter()
    steps = _steps()
    before = _counts(_jit.entry_points())
    with _jit.forced("compiled"):
        for label, step in steps:
            t = time.perf_counter()
            say(f"compiling {label} ...")
            step()
            say(f"  done in {time.perf_counter() - t:.1f} s")
    after = _jit.entry_points()
    compiled, loaded, ready, missed = [], [], [], []
    for module, functions in sorted(after.items()):
        reached = False
        for name, dispatcher in sorted(functions.items()):
            key = f"{module}.{name}"
            hits, misses = before.get(key, (0, 0))
            if sum(dispatcher._cache_misses.values()) > misses:
                compiled.append(key)
            elif sum(dispatcher._cache_hits.values()) > hits:
                loaded.append(key)
            elif dispatcher.signatures:
                ready.append(key)
            else:
                continue
            reached = True
        if not reached:
            missed.append(module)
    return WarmUp(tuple(compiled), tuple(loaded), tuple(ready), tuple(missed),
                  time.perf_counter() - start, kernel.cache_dir())


def _counts(entry_points: dict) -> dict[str, tuple[int, int]]:
    """(cache hits, cache misses) of each entry point, by ``module.function``."""
    return {f"{module}.{name}": (sum(d._cache_hits.values()), sum(d._cache_misses.values()))
            for module, functions in entry_points.items() for name, d in functions.items()}

"""How flapping compiles with numba: one policy for every numba module of :mod:`flapping.fast`.

Every compiled module decorates its functions with :func:`entry_point` (a function called from
Python: ``numba.njit(cache=True)``, machine code kept in numba's on-disk cache) or :func:`helper`
(a function called from compiled code only: its code is linked into each entry point's, which is
cached, so it has no cache of its own). Nothing else decides how numba compiles, and nothing
writes to numba's cache but numba.

The cache. numba chooses where (``NUMBA_CACHE_DIR`` if set, else ``__pycache__`` beside the
module if writable, else its user-wide cache directory); if no place is writable the functions
are compiled without a disk cache (:func:`cached` is then False) and every process compiles
again. Two things are added to numba's own cache (:mod:`flapping.fast._cache`), inside numba's
key and files, never beside them: the key also holds the SHA-256 of the sources a function
inlines (``depends``; numba keys an entry on the function's own file only), and an unreadable
(corrupt) index or data file is said once and compiled again instead of raising on every run.

The first call. A function whose machine code is in the cache loads it (~0.1 s). Otherwise the
call compiles it in this process, and says so: one :class:`KernelCompileWarning` per process
before the first compile (numba takes seconds), and one INFO line on the ``"flapping"`` logger
per compiled function, with the time. ``FLAPPING_FIRST_CALL`` (:func:`first_call_mode`, read and
checked on every call of a fast module) chooses the first call:

- ``compiled`` (the default, also when the variable is unset or empty): as above;
- ``uncompiled``: a module with a Python twin runs it where numba's cache holds no machine code
  (the hover kernel: its own functions uncompiled, the same numbers bit for bit; the
  blade-element loads: the model's Python loads), and nothing is compiled by those calls; the
  cache is filled only by :func:`flapping.fast.warm_up` or ``python -m flapping compile``. The
  six-degree-of-freedom module has no twin and compiles as in ``compiled``.

Ctrl-C during a compile. numba compiles through llvmlite, which calls back into Python; a
KeyboardInterrupt raised in such a callback is printed ("Exception ignored ...") and lost, or
leaves LLVM in a broken state. So while a function compiles (in the main thread), SIGINT is only
recorded; when the compile returns, the previous handler is restored and the signal raised
again, so it acts as if it had come then (a KeyboardInterrupt, or the handler the program set).
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import logging
import os
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

__all__ = ["ENV", "FIRST_CALL_MODES", "KernelCompileWarning", "announce", "cache_dir", "cached",
           "announce_quietly", "entry_point", "entry_points", "first_call_mode", "forced", "helper",
           "in_cache", "ready"]

_LOG = logging.getLogger("flapping")

#: The environment variable choosing the first call, and its values (the first is the default).
ENV = "FLAPPING_FIRST_CALL"
FIRST_CALL_MODES = ("compiled", "uncompiled")


class KernelCompileWarning(UserWarning):
    """numba compiles flapping's compiled code in this process (said once per process), a
    first call runs uncompiled (``FLAPPING_FIRST_CALL=uncompiled``), or a file of numba's cache
    could not be read and is compiled again.

    A warning, not a log record: Python shows it by default (once) in scripts, notebooks and
    pytest's summary, whereas a log record below WARNING is dropped without a configured
    handler; and its own category lets a user or a test silence it alone
    (``warnings.simplefilter("ignore", KernelCompileWarning)``).
    """


# --------------------------------------------------------------------------- FLAPPING_FIRST_CALL
_FORCED: list[str] = []


@functools.lru_cache(maxsize=8)
def _parse(raw: str) -> str:
    mode = raw.strip().lower() or FIRST_CALL_MODES[0]
    if mode not in FIRST_CALL_MODES:
        raise ValueError(f"the environment variable {ENV} must be one of "
                         f"{', '.join(FIRST_CALL_MODES)} (or unset); got {raw!r}")
    return mode


def first_call_mode() -> str:
    """``FLAPPING_FIRST_CALL``, checked: ``"compiled"`` (the default) or ``"uncompiled"``.

    Read on every call (it is cheap), so a bad value is refused by every call alike, not only by
    the first one.

    Raises
    ------
    ValueError
        If the variable holds another value than :data:`FIRST_CALL_MODES` (or empty).
    """
    mode = _parse(os.environ.get(ENV, ""))  # checked even when a mode is forced
    return _FORCED[-1] if _FORCED else mode


@contextlib.contextmanager
def forced(mode: str) -> Iterator[None]:
    """Run the block as if ``FLAPPING_FIRST_CALL`` were ``mode`` (:func:`flapping.fast.warm_up`
    compiles whatever the variable says)."""
    _FORCED.append(_parse(mode))
    try:
        yield
    finally:
        _FORCED.pop()


# --------------------------------------------------------------------------- compiling
_STATE = {"cached": True}

#: The entry points, by module name then function name (for warm_up's report and the tests).
_ENTRY_POINTS: dict[str, dict[str, Any]] = {}

_NOTED: list[bool] = []
_DEPTH = threading.local()


def cached() -> bool:
    """Whether numba found a writable place for its on-disk cache (False: every process
    compiles again; set ``NUMBA_CACHE_DIR`` to a writable directory)."""
    return _STATE["cached"]


def _digest(modules: tuple[ModuleType, ...]) -> str:
    """SHA-256 of the modules' source files, in order ('' for none)."""
    if not modules:
        return ""
    h = hashlib.sha256()
    for module in modules:
        h.update(Path(module.__file__ or "").read_bytes())
    return h.hexdigest()


def entry_points() -> dict[str, dict[str, Any]]:
    """Every entry point decorated so far, ``{module: {name: dispatcher}}`` (a copy)."""
    return {module: dict(names) for module, names in _ENTRY_POINTS.items()}


def _our_cache(dispatcher: Any) -> Any:
    """The dispatcher's :class:`flapping.fast._cache.Cache`, or None (not numba's, no cache)."""
    cache = getattr(dispatcher, "_cache", None)
    return cache if hasattr(cache, "holds_any") else None


def in_cache(dispatcher: Any) -> bool:
    """Whether numba's on-disk cache holds machine code of ``dispatcher`` (for some signature):
    its first call then loads rather than compiles. False without a cache; True for something
    that is not a numba dispatcher (a wrapper a benchmark put in its place)."""
    if getattr(dispatcher, "py_func", None) is None:
        return True
    cache = _our_cache(dispatcher)
    return cache is not None and cache.holds_any()


def ready(dispatcher: Any) -> bool:
    """Whether a call of ``dispatcher`` runs machine code without compiling it: compiled (or
    loaded) in this process already, or in numba's on-disk cache (:func:`in_cache`)."""
    return bool(getattr(dispatcher, "signatures", None)) or in_cache(dispatcher)


def cache_dir(dispatcher: Any) -> Path | None:
    """The directory of numba's on-disk cache of ``dispatcher`` (None: not cached)."""
    cache = _our_cache(dispatcher)
    return Path(cache.cache_path) if cache is not None else None


def _cache_text(path: str | Path | None) -> str:
    return (f"cached in {path} (NUMBA_CACHE_DIR moves it)" if path else
            "numba found no writable cache directory, so every process compiles again "
            "(set NUMBA_CACHE_DIR to a writable directory)")


def announce(name: str, path: str | Path | None) -> None:
    """The one note per process before numba compiles (``name``: the function it starts with;
    ``path``: the cache directory, None for none)."""
    if _NOTED:
        return
    _NOTED.append(True)
    _LOG.info("numba compiles flapping's %s (and what it calls); %s", name, _cache_text(path))
    warnings.warn(f"compiling flapping's numba code ({name} first; seconds of CPU, once per "
                  f"environment); {_cache_text(path)}; `python -m flapping compile` compiles "
                  f"it all ahead", KernelCompileWarning, stacklevel=2)


def announce_quietly() -> None:
    """No note from now on that numba compiles (a caller that asked for the compile says it)."""
    if not _NOTED:
        _NOTED.append(True)


def _held(pending: list[int]) -> Callable[[int, Any], None]:
    """The SIGINT handler during a compile: record, and say once why nothing stops yet."""
    def handler(signum: int, frame: Any) -> None:
        if not pending:
            with contextlib.suppress(Exception):  # no stderr: nothing to say it on
                sys.stderr.write("flapping: Ctrl-C: stopping when numba's compile in progress "
                                 "returns (it cannot be interrupted safely)\n")
                sys.stderr.flush()
        pending.append(signum)
    return handler


_WARNED_FILES: set[str] = set()


def _unreadable(path: str, error: BaseException) -> None:
    """Say once per file that a file of numba's cache could not be read (numba compiles the
    function again and rewrites the file)."""
    if path in _WARNED_FILES:
        return
    _WARNED_FILES.add(path)
    warnings.warn(f"numba's cache file {path} could not be read ({type(error).__name__}: "
                  f"{error}); flapping recompiles that function and numba rewrites the file",
                  KernelCompileWarning, stacklevel=2)


@contextlib.contextmanager
def _sigint_deferred() -> Iterator[None]:
    """SIGINT recorded, not raised, during the block (main thread, outermost compile only);
    raised again after it, to the handler that was in place."""
    depth = getattr(_DEPTH, "value", 0)
    if depth or threading.current_thread() is not threading.main_thread():
        _DEPTH.value = depth + 1
        try:
            yield
        finally:
            _DEPTH.value = depth
        return
    pending: list[int] = []
    try:
        previous = signal.signal(signal.SIGINT, _held(pending))
    except (ValueError, TypeError):  # no signal handling here (an embedded interpreter)
        previous = None
    _DEPTH.value = 1
    try:
        yield
    finally:
        _DEPTH.value = 0
        if previous is not None:
            signal.signal(signal.SIGINT, previous)
            if pending:
                signal.raise_signal(signal.SIGINT)  # to the previous handler, now


def _compiling(dispatcher: Any, announced: bool) -> Callable[..., Any]:
    """``dispatcher.compile`` under the policy: Ctrl-C deferred, each compile logged with its
    time; announced here unless the cache announces it (``announced``)."""
    compile_ = dispatcher.compile
    name = f"{dispatcher.py_func.__module__}.{dispatcher.py_func.__name__}"

    def compile(sig: Any) -> Any:  # noqa: A001 - numba calls it by this name
        outermost = not getattr(_DEPTH, "value", 0)  # the functions it calls are in its time
        with _sigint_deferred():
            misses = sum(dispatcher._cache_misses.values())
            if not announced and tuple(sig) not in dispatcher.overloads:
                announce(dispatcher.py_func.__name__, None)
            start = time.perf_counter()
            out = compile_(sig)
            seconds = time.perf_counter() - start
        if outermost and sum(dispatcher._cache_misses.values()) != misses:
            _LOG.info("numba compiled %s in %.2f s", name, seconds)
        return out

    return compile


def entry_point(*depends: ModuleType, **options: Any) -> Callable[[Callable[..., Any]], Any]:
    """The decorator of a function called from Python: ``numba.njit(cache=True, **options)``
    with the policy of this module.

    Parameters
    ----------
    *depends : module
        The modules whose code or constants the function inlines (generated formulas, a
        tableau): their sources are part of the cache key.
    **options
        numba's ``njit`` options (e.g. ``fastmath``).
    """
    digest = _digest(depends)
    # registered under the module that decorates (a generated function is compiled there)
    owner = str(sys._getframe(1).f_globals.get("__name__", ""))

    def decorate(fn: Callable[..., Any]) -> Any:
        import numba

        from flapping.fast._cache import Cache

        dispatcher = numba.njit(**options)(fn)
        if getattr(dispatcher, "py_func", None) is None:  # NUMBA_DISABLE_JIT: the function
            return dispatcher
        try:
            # as numba's Dispatcher.enable_caching (njit(cache=True)), with this cache
            dispatcher._cache = Cache(dispatcher.py_func, digest, announce, _unreadable)
            announced = True
        except RuntimeError as error:  # numba found no writable place ("cannot cache")
            if "cannot cache" not in str(error):
                raise
            _STATE["cached"] = False
            announced = False
        dispatcher.compile = _compiling(dispatcher, announced)
        _ENTRY_POINTS.setdefault(owner, {})[fn.__name__] = dispatcher
        return dispatcher

    return decorate


# numba's own option (its internal functions use it), absent from the stubs of njit's keywords.
_NO_C_WRAPPER: dict[str, Any] = {"no_cfunc_wrapper": True}


def helper(fn: Callable[..., Any]) -> Any:
    """The decorator of a function called from compiled code (and from the tests):
    ``numba.njit`` without numba's disk cache (its machine code is linked into each entry
    point's, which is cached) and without the C wrapper numba would also compile, for calls
    through a function pointer (none are made). Its CPython wrapper stays: without it, a call
    from Python crashes. Called from Python, it compiles with Ctrl-C deferred."""
    import numba

    dispatcher = numba.njit(**_NO_C_WRAPPER)(fn)
    if getattr(dispatcher, "py_func", None) is not None:
        dispatcher.compile = _compiling(dispatcher, announced=True)  # no note for the tests'
    return dispatcher

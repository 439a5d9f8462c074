"""numba's on-disk function cache as :mod:`flapping.fast._jit` uses it (imported with numba).

:class:`Cache` is numba's ``FunctionCache`` (the one ``numba.njit(cache=True)`` installs), with
two changes inside numba's own key and files, never beside them:

- the key of an entry also holds the SHA-256 of the sources the function inlines (``depends``):
  numba keys an entry on the function's own file only, so after a regeneration that changed only
  ``_generated.py`` it would load the old arithmetic; another digest is another key, which numba
  compiles and adds;
- an index or data file that cannot be read (truncated, corrupt: numba raised
  ``UnpicklingError`` on every run until it was deleted) reads as a missing one, said by the
  ``on_unreadable`` callback (:mod:`flapping.fast._jit`: a warning naming the file); numba then
  compiles and writes the entry again, as for a missing one.

The callbacks come from :mod:`flapping.fast._jit`, which imports this module (and not the other
way round).

Checked for numba 0.60-0.68 (``numba.core.caching``: ``FunctionCache``, ``IndexDataCacheFile``,
``_index_key``, ``_load_index``, ``_load_data``).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

from numba.core import caching

#: ``on_unreadable(path, error)``: a cache file could not be read.
Unreadable = Callable[[str, BaseException], None]


class _CacheFile(caching.IndexDataCacheFile):
    """numba's index and data files, an unreadable one read as a missing one (and said)."""

    def __init__(self, cache_path: str, filename_base: str, source_stamp: Any,
                 on_unreadable: Unreadable) -> None:
        super().__init__(cache_path, filename_base, source_stamp)
        self._on_unreadable = on_unreadable

    def _load_index(self) -> dict:
        try:
            return super()._load_index()
        except Exception as error:  # noqa: BLE001 - any unpickling failure: a corrupt file
            self._on_unreadable(self._index_path, error)
            return {}

    def load(self, key: Any) -> Any:
        name = self._load_index().get(key)
        if name is None:
            return None
        try:
            return self._load_data(name)
        except OSError:  # removed while the index still refers to it (as numba's load)
            return None
        except Exception as error:  # noqa: BLE001 - a corrupt data file
            self._on_unreadable(self._data_path(name), error)
            return None


class _NoCodegen:
    """A stand-in codegen: the parts of the key that do not depend on it."""

    @staticmethod
    def magic_tuple() -> tuple:
        return ()


class Cache(caching.FunctionCache):
    """numba's function cache, keyed also on ``depends`` (a digest of the sources the function
    inlines), reading an unreadable file as a missing one (``on_unreadable(path, error)``), and
    calling ``on_miss(function name, cache directory)`` when it has nothing to load (numba
    compiles next)."""

    def __init__(self, py_func: Callable[..., Any], depends: str,
                 on_miss: Callable[[str, str], None], on_unreadable: Unreadable) -> None:
        super().__init__(py_func)
        self._depends = depends
        self._on_miss = on_miss
        self._cache_file = _CacheFile(self._cache_path, self._impl.filename_base,
                                      self._impl.locator.get_source_stamp(), on_unreadable)

    def _index_key(self, sig: Any, codegen: Any) -> Any:
        return (*super()._index_key(sig, codegen), self._depends)

    def load_overload(self, sig: Any, target_context: Any) -> Any:
        out = super().load_overload(sig, target_context)
        if out is None and self._enabled:
            self._on_miss(self._py_func.__name__, self._cache_path)
        return out

    def holds_any(self) -> bool:
        """Whether the index holds an entry of this function (its code and dependencies as they
        are now, this numba, this source file) for some signature, with its data file."""
        ours = self._index_key(None, _NoCodegen())[2:]
        return any(tuple(key[2:]) == ours and os.path.isfile(self._cache_file._data_path(name))
                   for key, name in self._cache_file._load_index().items())

"""Deprecated module path: the code is :mod:`flapping.studies.control`; import from there.

Importing this module warns (``DeprecationWarning``), and so does every name taken from it; each
name is the object of :mod:`flapping.studies.control` itself.
"""

from typing import Any

from flapping import _moved

_moved.warn_import(__name__)


def __getattr__(name: str) -> Any:
    return _moved.forward(__name__, name)


def __dir__() -> list[str]:
    return _moved.names(__name__)

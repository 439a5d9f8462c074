"""A user's own insect from a TOML or JSON file, checked as the presets are.

The file holds the :class:`~.morphology.Insect` fields as top-level keys, in SI units (metres,
kilograms, seconds, radians), e.g. ``my_bee.toml``::

    name = "my_bee"
    semi_span = 0.0132          # wing length R [m]
    wing_area = 5.306e-5        # one wing [m^2]
    r1 = 0.489
    r2 = 0.55
    frequency = 156.25          # [Hz]
    stroke_amplitude = 1.0123   # nominal Phi [rad]
    mass = 1.75e-4              # [kg]
    pitch_inertia = 3.26e-9     # [kg m^2]

or the same as a JSON object. Optional fields (``air_density``, ``mu1``, ...) take the class
defaults. With ``preset = "bumblebee"`` the file starts from a preset (:mod:`.presets`) and
changes only the fields it gives; ``name`` then defaults to the preset's.

Every value goes through :class:`~.morphology.Insect`'s validation; an unknown key, a missing
field, or a value out of range is a :class:`ValueError` whose message names the file and the key.

Module order: imports :mod:`.morphology`, :mod:`.presets` and :mod:`flapping.errors` only.
"""

from __future__ import annotations

import dataclasses
import json
import tomllib
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from flapping.errors import PlausibilityWarning
from flapping.model.morphology import Insect, _implausible, implausible_fields
from flapping.model.presets import PRESETS

__all__ = ["FILE_SUFFIXES", "INSECT_FIELDS", "MAX_FILE_BYTES", "REQUIRED_FIELDS",
           "insect_from_mapping", "load_insect", "resolve_insect"]

#: File suffixes :func:`load_insect` reads.
FILE_SUFFIXES = (".toml", ".json")

#: Largest insect file read [bytes]: the fields take a few hundred.
MAX_FILE_BYTES = 1_000_000

#: The fields of :class:`Insect` a file may set.
INSECT_FIELDS: tuple[str, ...] = tuple(f.name for f in dataclasses.fields(Insect) if f.init)

#: The fields a file must set when it does not start from a preset.
REQUIRED_FIELDS: tuple[str, ...] = tuple(
    f.name for f in dataclasses.fields(Insect)
    if f.init and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING)


def insect_from_mapping(data: Mapping[str, Any], *, where: str = "insect") -> Insect:
    """An :class:`Insect` from a mapping of its fields (optionally ``preset = NAME`` as a base).

    Parameters
    ----------
    data : mapping
        Field name -> value (SI units), as read from a file.
    where : str
        What to call the data in messages (the file name).

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        If ``data`` is not a mapping, has a key that is not a field (the message names it and
        lists the accepted ones), lacks a required field, names an unknown preset, or a value is
        out of its field's range (the message names the field).

    Warns
    -----
    PlausibilityWarning
        If a field the data gives makes the insect implausible (e.g. its wings cannot lift
        its weight: a mass in grams typed as kilograms); the message names the field.
    """
    if not isinstance(data, Mapping):
        raise ValueError(f"{where}: must hold a table of insect fields; got {type(data).__name__}")
    values = dict(data)
    base = values.pop("preset", None)
    unknown = sorted(set(values) - set(INSECT_FIELDS))
    if unknown:
        raise ValueError(f"{where}: unknown field {', '.join(map(repr, unknown))}; accepted: "
                         f"{', '.join(INSECT_FIELDS)} and 'preset'")
    if base is not None:
        if not isinstance(base, str) or base not in PRESETS:
            raise ValueError(f"{where}: `preset` must be one of {tuple(PRESETS)}; got {base!r}")
        try:
            insect = PRESETS[base].insect(**values)
        except ValueError as exc:
            raise ValueError(f"{where}: {exc}") from None
        _warn_implausible(insect, values, where)
        return insect
    missing = [k for k in REQUIRED_FIELDS if k not in values]
    if missing:
        raise ValueError(f"{where}: missing field {', '.join(map(repr, missing))} (required: "
                         f"{', '.join(REQUIRED_FIELDS)}; or start from a preset with "
                         "preset = NAME)")
    try:
        insect = Insect(**values)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
    _warn_implausible(insect, values, where)
    return insect


def _warn_implausible(insect: Insect, given: Mapping[str, Any], where: str) -> None:
    """A :class:`~flapping.errors.PlausibilityWarning` naming the file's fields that make the
    insect none (:func:`~.morphology.implausible_fields`), with the likeliest slip: a value in
    grams (or mm, or g cm^2) typed where the file wants SI. A 1.648 (g, a hawkmoth) typed as kg
    is valid for the model and plausible alone (a 1.6 kg flapping vehicle), but its wings
    cannot lift it: the hover solve would fail later with no word about the file."""
    if _implausible(insect):
        return  # the Insect has warned (a value outside PLAUSIBLE_RANGES): once is enough
    blamed = {name: why for name, why in implausible_fields(insect).items() if name in given}
    if blamed:
        fields = "; ".join(f"`{name}` = {given[name]!r} ({why})" for name, why in blamed.items())
        warnings.warn(f"{where}: this insect looks like none: {fields}. The file's values are SI "
                      "(kg, m, s, rad, kg m^2): grams typed as kg are 1000 times too large, "
                      "g cm^2 as kg m^2 1e7 times", PlausibilityWarning, stacklevel=4)


def load_insect(path: str | Path) -> Insect:
    """Read an insect from a ``.toml`` or ``.json`` file (module docstring for the format).

    Parameters
    ----------
    path : str or Path
        The file; its suffix chooses the format.

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        If the suffix is not ``.toml`` or ``.json``, the file cannot be read or parsed (or is
        larger than :data:`MAX_FILE_BYTES`, or nested too deeply to parse), or its content is not
        a valid insect (:func:`insect_from_mapping`); the message names the file.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in FILE_SUFFIXES:
        raise ValueError(f"{path}: an insect file must end in {' or '.join(FILE_SUFFIXES)}")
    try:
        with path.open("rb") as file:
            raw = file.read(MAX_FILE_BYTES + 1)  # bounded: a device or a huge file is refused
        text = raw.decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the insect file ({exc})") from None
    if len(raw) > MAX_FILE_BYTES:
        raise ValueError(f"{path}: an insect file holds a few fields; this one is larger than "
                         f"{MAX_FILE_BYTES} bytes")
    try:
        data = tomllib.loads(text) if suffix == ".toml" else json.loads(text)
    except (ValueError, RecursionError) as exc:  # decode errors, too-long integers, deep nesting
        reason = "nested too deeply" if isinstance(exc, RecursionError) else str(exc)
        raise ValueError(f"{path}: not valid {suffix[1:].upper()} ({reason})") from None
    return insect_from_mapping(data, where=str(path))


def resolve_insect(spec: str) -> Insect:
    """The insect a user names: a preset name, or the path of a ``.toml``/``.json`` file.

    Parameters
    ----------
    spec : str
        A key of :data:`~.presets.PRESETS`, or a file path ending in ``.toml`` or ``.json``.

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        If ``spec`` is neither a preset nor a readable, valid insect file (one line, naming it).
    """
    if not isinstance(spec, str):
        raise ValueError(f"`insect` must be a preset name or a file path; got {spec!r}")
    if spec in PRESETS:
        return PRESETS[spec].insect()
    if Path(spec).suffix.lower() in FILE_SUFFIXES:
        return load_insect(spec)
    raise ValueError(f"unknown insect {spec!r}: give a preset ({', '.join(PRESETS)}) or a "
                     f"{' or '.join(FILE_SUFFIXES)} file")

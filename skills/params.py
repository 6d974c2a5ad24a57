"""Parameter files in the UT Austin Villa style.

One parameter a line, ``name<TAB>value`` (any run of spaces or tabs separates
the two words); ``#`` and ``//`` start comments; blank lines are ignored.
Several files may be given: a later file overrides the values of an earlier
one. Example::

    // walk parameters (millimeters and radians, as UT writes them)
    walk_height         175      # mm
    max_step_size_angle 1.22     # rad
    sprint_walk_height  180

The consumer declares every name it knows with its unit in a *schema*
(``{"walk_height": "mm", "max_step_size_angle": "rad"}``); values are converted
to SI once, here, so the rest of the code only sees meters, radians and
seconds. A prefixed set (``sprint_walk_height``) reuses the same schema: pass
the prefixes the files may hold and get one dict per prefix.

Errors raise `ParamError` whose message starts with ``file:line:`` and quotes
the offending word.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

# Unit name -> factor to SI.
UNITS: dict[str, float] = {
    "mm": 1e-3,  # -> m
    "m": 1.0,
    "deg": math.pi / 180.0,  # -> rad
    "rad": 1.0,
    "s": 1.0,
    "1": 1.0,  # dimensionless
}

Schema = Mapping[str, str]  # parameter name -> unit (a key of UNITS)
PathLike = str | os.PathLike


def with_type_file(path: PathLike, robot_type: int | None) -> list[str]:
    """A shipped parameter file, then its robot type's own overrides beside it
    (``<stem>_type<T><suffix>``) when that file exists: the load order of every
    skill with per-type values."""
    base = os.fspath(path)
    stem, suffix = os.path.splitext(base)
    typed = f"{stem}_type{robot_type}{suffix}"
    return [base, typed] if robot_type is not None and os.path.exists(typed) else [base]


class ParamError(ValueError):
    """A malformed or unknown entry of a parameter (or skill) file, with its place."""

    def __init__(self, path: PathLike | None, line: int, message: str, word: str = "") -> None:
        self.path, self.line, self.word = path, line, word
        where = f"{os.fspath(path) if path is not None else '<string>'}:{line}: "
        super().__init__(where + message + (f" {word!r}" if word else ""))


@dataclass(frozen=True)
class Entry:
    """One raw ``name value`` line of a parameter file (value in the file's units)."""

    name: str
    value: float
    path: PathLike | None
    line: int


def strip_comment(line: str) -> str:
    """The line without its ``#`` or ``//`` comment."""
    for mark in ("#", "//"):
        k = line.find(mark)
        if k >= 0:
            line = line[:k]
    return line


def parse_params(text: str, path: PathLike | None = None) -> list[Entry]:
    """The entries of one parameter file's text, in file order, values unconverted."""
    out = []
    for n, raw in enumerate(text.splitlines(), start=1):
        words = strip_comment(raw).split()
        if not words:
            continue
        if len(words) != 2:
            bad = words[0] if len(words) == 1 else words[2]
            what = "missing value after" if len(words) == 1 else "expected 'name<TAB>value', extra word"
            raise ParamError(path, n, what, bad)
        name, value = words
        try:
            v = float(value)
        except ValueError:
            raise ParamError(path, n, f"value of {name} is not a number:", value) from None
        if not math.isfinite(v):
            raise ParamError(path, n, f"value of {name} is not finite:", value)
        out.append(Entry(name, v, path, n))
    return out


def read_entries(paths: Iterable[PathLike] | PathLike) -> dict[str, Entry]:
    """Every entry of the files in order, later files overriding earlier ones."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    merged: dict[str, Entry] = {}
    for p in paths:
        with open(p, encoding="utf-8") as f:
            for e in parse_params(f.read(), p):
                merged[e.name] = e
    return merged


def convert(entries: Mapping[str, Entry] | Iterable[Entry], schema: Schema,
            prefixes: Iterable[str] = ("",)) -> dict[str, dict[str, float]]:
    """SI values per prefix: ``{prefix: {name: value}}``; unknown names raise.

    A file name ``prefix + name`` belongs to the set `prefix` when `name` is in
    the schema; the longest matching prefix wins.
    """
    for unit in schema.values():
        if unit not in UNITS:
            raise ValueError(f"unknown unit {unit!r}; units are {', '.join(UNITS)}")
    prefixes = sorted(set(prefixes), key=len, reverse=True)
    out: dict[str, dict[str, float]] = {p: {} for p in prefixes}
    items = entries.values() if isinstance(entries, Mapping) else entries
    for e in items:
        for p in prefixes:
            if e.name.startswith(p) and e.name[len(p):] in schema:
                name = e.name[len(p):]
                out[p][name] = e.value * UNITS[schema[name]]
                break
        else:
            raise ParamError(e.path, e.line, "unknown parameter", e.name)
    return out


def load_param_sets(paths: Iterable[PathLike] | PathLike, schema: Schema,
                    prefixes: Iterable[str]) -> dict[str, dict[str, float]]:
    """Load files holding several prefixed sets of one schema, in SI: ``{prefix: {name: value}}``."""
    return convert(read_entries(paths), schema, prefixes)


def load_params(paths: Iterable[PathLike] | PathLike, schema: Schema, prefix: str = "",
                defaults: Mapping[str, float] | None = None) -> dict[str, float]:
    """Load parameter files into SI values ``{name: value}`` (names without `prefix`).

    `defaults` (already SI) fill the names no file sets. Every name in the
    files must be ``prefix + name`` with `name` in `schema`.
    """
    values = dict(defaults or {})
    values.update(convert(read_entries(paths), schema, (prefix,))[prefix])
    return values


def require(values: Mapping[str, float], schema: Schema) -> None:
    """Raise a ValueError naming every schema name missing from `values`."""
    missing = [n for n in schema if n not in values]
    if missing:
        raise ValueError(f"parameters not set: {', '.join(missing)}")

"""Checked argparse types for the `soccer` subcommands: a bad value becomes one
clear error line (argparse then exits with code 2)."""

from __future__ import annotations

import argparse
import math
import os
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

T = TypeVar("T", int, float)


def checked(convert: Callable[[str], T], malformed: str, ok: Callable[[T], bool],
            out_of_range: str) -> Callable[[str], T]:
    """An argparse type: `convert` the text, then require `ok`. The messages read
    "<malformed>, not 'text'" and "<out_of_range>, not text". Infinities and NaN
    are always refused."""
    def parse(value: str) -> T:
        try:
            v = convert(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{malformed}, not {value!r}") from None
        if isinstance(v, float) and not math.isfinite(v):
            raise argparse.ArgumentTypeError(f"{malformed} (a finite number), not {value!r}")
        if not ok(v):
            raise argparse.ArgumentTypeError(f"{out_of_range}, not {value}")
        return v
    return parse


def robot_type(value: str) -> int:
    """A robot type, 0 to 4."""
    if value not in {"0", "1", "2", "3", "4"}:
        raise argparse.ArgumentTypeError(f"robot type must be 0, 1, 2, 3 or 4, not {value!r}")
    return int(value)


MAX_SEED = 2**32 - 1
seed = checked(int, "seed must be a whole number", lambda n: 0 <= n <= MAX_SEED,
               f"seed must be 0 to {MAX_SEED}")
MAX_HALF_TIME = 3600.0  # s; the league's half is 300 s
half_time = checked(float, "expected a number of seconds", lambda v: 0 < v <= MAX_HALF_TIME,
                    f"half time must be positive and at most {MAX_HALF_TIME:g} s")


class OutputError(ValueError):
    """An output path that cannot be written (one line, exit code 2)."""


def check_writable(path: str | os.PathLike, what: str = "output", directory: bool = False) -> None:
    """Raise OutputError unless `path` can be written: an existing file (or directory,
    with `directory`) must be writable; otherwise its nearest existing ancestor must be
    a writable directory (the missing ones are created when written)."""
    p = Path(path)
    if p.exists():
        if directory and not p.is_dir():
            raise OutputError(f"{what} {p} is not a directory")
        if not directory and p.is_dir():
            raise OutputError(f"{what} {p} is a directory, not a file")
        if not os.access(p, os.W_OK | (os.X_OK if directory else 0)):
            raise OutputError(f"{what} {p} is not writable")
        return
    parent = p.absolute().parent
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise OutputError(f"cannot write {what} {p}: {parent} is not a directory")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise OutputError(f"cannot write {what} {p}: {parent} is not writable")


def scheduler(value: str) -> str:
    """A Dask scheduler address (tcp://HOST:PORT) for --scheduler."""
    if "://" not in value:
        raise argparse.ArgumentTypeError(f"expected an address like tcp://HOST:8786, not {value!r}")
    return value

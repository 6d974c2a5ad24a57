"""Checked argparse types for the `soccer` subcommands: a bad value becomes one
clear error line (argparse then exits with code 2)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import TypeVar

T = TypeVar("T", int, float)


def checked(convert: Callable[[str], T], malformed: str, ok: Callable[[T], bool],
            out_of_range: str) -> Callable[[str], T]:
    """An argparse type: `convert` the text, then require `ok`. The messages read
    "<malformed>, not 'text'" and "<out_of_range>, not text"."""
    def parse(value: str) -> T:
        try:
            v = convert(value)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{malformed}, not {value!r}") from None
        if not ok(v):
            raise argparse.ArgumentTypeError(f"{out_of_range}, not {value}")
        return v
    return parse


def robot_type(value: str) -> int:
    """A robot type, 0 to 4."""
    if value not in {"0", "1", "2", "3", "4"}:
        raise argparse.ArgumentTypeError(f"robot type must be 0, 1, 2, 3 or 4, not {value!r}")
    return int(value)

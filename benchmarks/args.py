"""Command-line arguments the benchmarks share."""

from __future__ import annotations

import argparse

from agent.teamconfig import VILLA, TeamConfig, UnknownVariant, variant, variant_name


def robot_types(ap: argparse.ArgumentParser, text: str) -> list[int]:
    """The robot types of a `--types` value ("0,1,2,3,4"); a usage error naming the
    value for anything else."""
    try:
        types = [int(t) for t in text.split(",") if t.strip()]
    except ValueError:
        ap.error(f"--types: whole numbers 0-4, comma-separated, got {text!r}")
    if not types or any(t not in range(5) for t in types):
        ap.error(f"--types: robot types are 0-4, got {text!r}")
    return types


def villa_config(ap: argparse.ArgumentParser, text: str) -> tuple[str, TeamConfig]:
    """The name and config of a `--variant` value (empty: villa itself); a usage error
    naming the value for an unknown variant."""
    if not text:
        return "villa", VILLA
    try:
        name = variant_name(text)
        return name, variant(name)
    except UnknownVariant as e:
        ap.error(str(e))

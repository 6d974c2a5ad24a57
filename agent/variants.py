"""The villa team's variants as agent factories (`villa:NAME` in `cli.teams`).

Each variant is a `TeamConfig` in `agent.teamconfig.VARIANTS`; this module turns
one into a picklable factory (side, unum, robot_type, seed) -> Player.
"""

from __future__ import annotations

from agent.player import Player
from agent.teamconfig import VILLA, TeamConfig, variant, variant_name


class VillaFactory:
    """The agent factory of a villa team playing with `config`."""

    def __init__(self, config: TeamConfig = VILLA, name: str = "villa") -> None:
        self.config = config
        self.name = name

    @property
    def robot_types(self) -> tuple[int, ...] | None:
        """The robot types the team chooses (uniform numbers 1-11), or None for the default."""
        return self.config.robot_types

    def __call__(self, side: str, unum: int, robot_type: int, seed: int = 0) -> Player:
        return Player(side, unum, robot_type, seed, self.config)

    def __repr__(self) -> str:
        return f"VillaFactory({self.name!r})"


def villa_variant(name: str) -> VillaFactory:
    """The factory of variant `name` (case-insensitive); UnknownVariant for none."""
    canonical = variant_name(name)
    return VillaFactory(variant(canonical), f"villa:{canonical}")


__all__ = ["VillaFactory", "villa_variant"]

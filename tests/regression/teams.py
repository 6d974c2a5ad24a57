"""Test-only teams for the regression tests, as specs `tests.regression.teams:NAME`."""

from __future__ import annotations

from agent.player import Player
from agent.teamconfig import TeamConfig


def broken(side: str, unum: int, robot_type: int, seed: int = 0) -> Player:
    """The villa team broken: its on-ball player never kicks nor dribbles (it stands)."""
    return Player(side, unum, robot_type, seed, TeamConfig(kicks=False, dribble=False))

"""Test-only teams for the regression tests, as specs `tests.regression.teams:NAME`."""

from __future__ import annotations

from agent.player import Player
from agent.requests import Stand
from agent.teamconfig import TeamConfig


class _NeverOnTheBall(Player):
    """A villa player that stands still whenever it should play the ball: it never
    kicks nor dribbles. (TeamConfig(kicks=False, dribble=False) would still kick:
    the player falls back to kicking when it may not dribble.)"""

    def _on_ball_request(self, view):
        self.on_ball_since = view.time if self.on_ball_since is None else self.on_ball_since
        return Stand()


def broken(side: str, unum: int, robot_type: int, seed: int = 0) -> Player:
    """The villa team broken: it never kicks nor dribbles."""
    return _NeverOnTheBall(side, unum, robot_type, seed, TeamConfig(kicks=False, dribble=False))

"""Villa's kickoffs in physics: where the ball goes after our kickoff (seeded matches)."""

from __future__ import annotations

import numpy as np
import pytest

from cli import teams
from models.rules import PlayMode
from server.match import Match, lineup_for


def _kickoff(home: str, seed: int, seconds: float) -> tuple[np.ndarray, float | None]:
    """Ball (x, y) (world frame, m; the home team attacks +x) `seconds` after the home
    team's kickoff of a 4 vs 4 match against villa, and when the kickoff was taken (s)."""
    left, right = teams.factory(home), teams.factory("villa")
    m = Match(left, right, lineup_for(left, right, 4, 4), half_time=300.0, seed=seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    taken = None
    for c in range(round(seconds / 0.02)):
        m.step()
        if taken is None and m.referee.mode != PlayMode.KICK_OFF_LEFT:
            taken = (c + 1) * 0.02
    return m.world.ball_position()[:2].copy(), taken


@pytest.mark.parametrize("seed", [0, 1])
def test_the_deep_kickoff_sends_the_ball_toward_their_goal(seed):
    ball, taken = _kickoff("villa:DeepKickoff", seed, 18.0)
    assert taken is not None and taken < 12.0  # kicked within the rules' 15 s
    assert ball[0] > 7.0 and abs(ball[1]) < 6.0

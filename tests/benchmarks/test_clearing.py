"""benchmarks.clearing: the team's play on a ball at its own goal line."""

from __future__ import annotations

import numpy as np
import pytest

from agent.teamconfig import TeamConfig
from benchmarks import clearing
from models import field as fld


def test_roller_rests_in_the_mouth():
    for seed in range(20):
        (bx, by), (vx, vy), _, _ = clearing.placement("roller", np.random.default_rng(seed))
        speed = float(np.hypot(vx, vy))
        rest = np.array([bx, by]) + fld.rolling_distance(speed) * np.array([vx, vy]) / speed
        assert 0.1 - 1e-6 <= rest[0] + fld.HALF_LENGTH <= 0.8 + 1e-6 and abs(rest[1]) <= 0.8 + 1e-6


def test_a_ball_at_the_goal_line_is_cleared_or_scored_by_the_attacker():
    # seeds 0 and 3 of the 100 tries in the module's docstring (type 0)
    cleared = clearing.clear_stats(TeamConfig(), tries=1, types=[0], seed=0, attacker=True)
    assert cleared["cleared"] == 1 and cleared["clear_median_s"] < 30.0
    scored = clearing.clear_stats(TeamConfig(), tries=1, types=[0], seed=3, attacker=True)
    assert scored["goals_against"] == 1 and scored["cleared"] == 0


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        clearing.main(["--spot", "corner"])
    assert "invalid choice: 'corner'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        clearing.main(["--types", "7"])
    assert "robot types are 0-4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        clearing.main(["--tries", "0"])
    assert "need --tries >= 1" in capsys.readouterr().err

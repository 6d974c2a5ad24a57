"""benchmarks.finishing: the team's play on a ball near their goal, against a standing goalie."""

from __future__ import annotations

import pytest

from agent.teamconfig import variant
from benchmarks import finishing


def test_a_ball_beside_the_goal_is_centered_and_scored_where_a_straight_push_puts_it_out():
    # seed 9 (type 0 on the fast walk; on the shipped walk seed 5 showed the same)
    straight = finishing.finish_stats("beside", variant("NoFinish"), tries=1, types=[0], seed=9)
    assert straight["outs"] == 1 and straight["goals"] == 0
    centered = finishing.finish_stats("beside", variant("Finish"), tries=1, types=[0], seed=9)
    assert centered["goals"] == 1 and centered["outs"] == 0 and centered["falls"] == 0
    assert centered["goal_median_s"] > 10.0  # centering takes a while


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        finishing.main(["--spot", "corner"])
    assert "--spot: one or more of goal-kick, beside, got 'corner'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        finishing.main(["--types", "7"])
    assert "robot types are 0-4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        finishing.main(["--tries", "0"])
    assert "need --tries >= 1" in capsys.readouterr().err

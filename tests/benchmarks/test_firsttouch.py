"""benchmarks.firsttouch: the team's own play on a free ball from a few steps away."""

from __future__ import annotations

import pytest

from agent.teamconfig import VILLA
from benchmarks import firsttouch


def test_a_player_behind_the_ball_touches_it_and_moves_it_toward_the_goal():
    # seeds 0 and 4 start 1.0-1.1 m from the ball, on its own side (bearings -165 and 171 deg)
    rows = [firsttouch.touch_stats(0, VILLA, tries=1, seed=s, seconds=8.0) for s in (0, 4)]
    for row in rows:
        assert row["no_touch"] == 0 and row["falls"] == 0
        assert 1.0 < row["touch_median_s"] < 6.0
        assert row["progress_mean_m"] > 1.0


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        firsttouch.main(["--types", "5"])
    assert "robot types are 0-4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        firsttouch.main(["--variant", "nope"])
    assert "unknown villa variant 'nope'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        firsttouch.main(["--near", "2", "--far", "1"])
    assert "--near <= --far" in capsys.readouterr().err


def test_a_rolling_ball_is_touched_when_the_player_touches_it_not_when_it_moves():
    row = firsttouch.touch_stats(0, VILLA, tries=1, seed=0, seconds=6.0, roll=0.8)
    assert row["roll_m_s"] == 0.8 and row["falls"] == 0
    assert row["touch_median_s"] > 1.0  # the ball moved 5 cm within 0.1 s

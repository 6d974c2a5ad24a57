"""benchmarks.dribble: the team's dribble pushes the ball along the target line."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks import dribble


def test_the_dribble_drives_the_ball_to_the_distance():
    row = dribble.trial(0, np.random.default_rng(3), seed=3, distance=4.0, limit=30.0)
    assert row["done"] and row["falls"] == 0
    assert row["progress"] >= 4.0
    assert 0.1 < row["speed"] < 2.0  # m/s from the first touch (a push rolls the ball ~2 m)
    assert row["touch_s"] < 5.0  # it starts 0.5 m behind the ball, facing it
    assert row["gap"] > 0.2  # the robot and ball apart: read from the truth, not the start


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        dribble.main(["--types", "7"])
    assert "robot types are 0-4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        dribble.main(["--distance", "20"])
    assert "--distance <= 12" in capsys.readouterr().err

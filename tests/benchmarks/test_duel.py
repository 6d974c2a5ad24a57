"""benchmarks.duel: one field player a side for a free ball."""

from __future__ import annotations

import math

import pytest

from agent.teamconfig import VILLA, TeamConfig
from benchmarks import duel
from optimization.trials import Duel

STANDS = TeamConfig(kicks=False, dribble=False)  # never plays the ball


def test_villa_wins_its_duels_against_a_player_that_never_plays_the_ball():
    first, second = duel.pair(VILLA, STANDS, (0,), seed=1, seconds=12.0)
    for d in (first, second):
        assert d.first == "L" and d.possession["R"] == 0.0
        assert d.falls == {"L": 0, "R": 0}
    row = duel.summary([(first, second)] * 2)
    assert row["progress_m"] > 0.5 and row["possession_a"] == 1.0 and row["first_touch_a"] == 1.0


def test_summary_gives_the_mean_progress_a_pair_and_its_standard_error():
    def d(progress: float, first: str | None) -> Duel:
        return Duel(progress, {"L": 3.0, "R": 1.0}, first, {"L": 1, "R": 0})

    row = duel.summary([(d(1.0, "L"), d(3.0, "R")), (d(-1.0, "L"), d(1.0, None))])
    assert row["pairs"] == 2 and row["progress_m"] == 1.0  # pair means 2 and 0
    assert row["se"] == pytest.approx(1.0) and row["ci95"][0] < 0 < row["ci95"][1]
    assert row["possession_a"] == 0.75 and row["first_touch_a"] == pytest.approx(2 / 3, abs=1e-3)
    assert row["falls_a"] == 1.0 and row["falls_b"] == 0.0
    assert math.isfinite(row["ci95"][1])


def test_cli_errors(capsys):
    for argv, message in ((["--home", "posture"], "duels are between villa variants"),
                          (["--away", "villa:nope"], "unknown villa variant 'nope'"),
                          (["--pairs", "1"], "--pairs >= 2"),
                          (["--types", "7"], "robot types are 0-4")):
        with pytest.raises(SystemExit):
            duel.main(argv)
        assert message in capsys.readouterr().err

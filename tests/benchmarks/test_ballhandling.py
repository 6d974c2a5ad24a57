"""benchmarks.ballhandling: the time from a walking start to the first touch, and where it goes."""

from __future__ import annotations

import pytest

from benchmarks import ballhandling


def test_a_walking_start_reaches_and_kicks_the_ball():
    row = ballhandling.handling_stats(0, tries=2, seed=3)
    assert row["no_contact"] == 0 and row["falls"] == 0
    assert 1.0 < row["contact_median_s"] < ballhandling.APPROACH_LIMIT
    # the time to the touch is spent in the kicker's states, walking first
    spent = sum(row["seconds_by_phase"].values())
    assert spent == pytest.approx(row["contact_median_s"], rel=0.5)
    assert row["seconds_by_phase"]["approach:walk"] > 0.5 and "kick" in row["seconds_by_phase"]
    assert sum(row["kicks"].values()) == 2


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        ballhandling.main(["--types", "5"])
    assert "robot types are 0-4" in capsys.readouterr().err
    assert ballhandling.main(["--types", "0", "--tries", "1", "--kicks", "no_such_kick"]) == 2
    assert "type 0 has no kick no_such_kick" in capsys.readouterr().err

"""benchmarks.kickoff: where the ball is after a team's own kickoff, paired by seed."""

from __future__ import annotations

import numpy as np
import pytest

from benchmarks import kickoff


@pytest.mark.parametrize("seed", [0, 1])
def test_the_deep_kickoff_sends_the_ball_toward_their_goal(seed):
    row = kickoff.kickoff_try("villa:DeepKickoff", "villa", seed, seconds=15.0, size=4)
    assert row["taken"] is not None and row["taken"] < 12.0  # kicked within the rules' 15 s
    assert row["x"][15.0] > 7.0 and row["goals"] == (0, 0)


def test_summary_pairs_the_seeds_with_the_base():
    rng = np.random.default_rng(2)
    rows = [{"team": t, "seed": s, "x": {10.0: float(rng.normal(3 if t == "b" else 0, 1))},
             "taken": 1.0, "goals": (0, 1)} for t in ("a", "b") for s in range(6)]
    rows.append({"team": "b", "seed": 9, "x": {10.0: 50.0}, "taken": None, "goals": (1, 0)})  # unpaired
    a, b = kickoff.summary(rows, ["a", "b"])
    d = [rb["x"][10.0] - ra["x"][10.0] for ra, rb in zip(rows[:6], rows[6:12])]
    assert b["minus_base"]["10"] == [round(np.mean(d), 2), round(np.std(d, ddof=1) / np.sqrt(6), 2)]
    assert "minus_base" not in a and b["tries"] == 7 and b["not_taken"] == 1 and b["goals"] == [1, 6]


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        kickoff.main(["--teams", "villa:nope"])
    assert "unknown villa variant 'nope'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        kickoff.main(["--size", "1"])
    assert "--size 2-11" in capsys.readouterr().err

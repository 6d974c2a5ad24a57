"""The kick benchmark's rows (benchmarks/kick.py)."""

import pytest

from benchmarks.kick import OUTCOMES, kick_stats, main, outcome
from skills.kicks import all_kicks


@pytest.mark.parametrize("kicked, fell, success, expected", [
    (True, False, True, "success"),
    (False, False, False, "timeout"),
    (False, True, False, "approach_fall"),
    (True, True, False, "kick_fall"),
    (True, False, False, "short"),
])
def test_each_trial_has_one_outcome(kicked, fell, success, expected):
    assert outcome({"kicked": kicked, "fell": fell, "success": success}) == expected


def test_a_row_counts_its_tries_by_outcome():
    row = kick_stats(0, all_kicks(0)["ik_forward_left"], "standing", tries=3, seed=4)
    assert set(row["outcomes"]) == set(OUTCOMES)
    assert sum(row["outcomes"].values()) == 3
    assert row["outcomes"]["success"] == round(row["success_rate"] * 3)
    assert row["outcomes"]["timeout"] + row["outcomes"]["approach_fall"] == 3 - row["kicks_started"]


def test_bad_options_are_refused(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--tries", "0"])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        main(["--kicks", "no_such_kick", "--tries", "1"])
    assert e.value.code == 2
    assert "unknown kick" in capsys.readouterr().err

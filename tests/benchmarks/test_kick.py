"""The kick benchmark's rows (benchmarks/kick.py)."""

import json

import pytest

import benchmarks.kick as bench
from benchmarks.kick import BUMP, OUTCOMES, kick_stats, main, outcome
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


def test_direction_error_counts_kicks_played_and_bumps_are_counted(monkeypatch):
    """A ball the approach pushed off (no kick played) has a direction, but not the kick's."""
    rows = iter([
        {"kicked": True, "fell": False, "success": True, "distance": 4.0, "direction": -4.0,
         "direction_error": 4.0, "contact_s": 9.0, "bumped": 0.0},
        {"kicked": True, "fell": False, "success": True, "distance": 3.0, "direction": 8.0,
         "direction_error": 8.0, "contact_s": 11.0, "bumped": 2 * BUMP},  # nudged on the way, then kicked
        {"kicked": False, "fell": False, "success": False, "distance": 0.6, "direction": 95.0,
         "direction_error": 95.0, "contact_s": None, "bumped": 0.6},  # run into: a timeout
    ])
    monkeypatch.setattr(bench, "kick_trial", lambda *a, **k: next(rows))
    row = kick_stats(0, all_kicks(0)["ik_forward_left"], "walking", tries=3, seed=0)
    assert row["direction_error_mean_deg"] == 6.0
    assert row["direction_bias_deg"] == 2.0  # the signed mean of -4 and +8
    assert row["direction_sd_deg"] == 6.0
    assert row["approach_bumps"] == 2
    assert row["outcomes"]["timeout"] == 1


def test_bad_options_are_refused(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--tries", "0"])
    assert e.value.code == 2
    with pytest.raises(SystemExit) as e:
        main(["--kicks", "no_such_kick", "--tries", "1"])
    assert e.value.code == 2
    assert "unknown kick" in capsys.readouterr().err


def test_parameter_files_are_loaded_after_the_shipped_ones(tmp_path, capsys):
    """A CMA-ES result is benchmarked without swapping the shipped files; the row names it."""
    kicks = tmp_path / "best.txt"
    kicks.write_text("# a kick_distance job's best\nkick_distance\t9.9\n")
    approach = tmp_path / "approach.txt"
    approach.write_text("approach_near\t0.3\n")
    assert main(["--kicks", "kick_left", "--modes", "standing", "--tries", "1",
                 "--params", str(kicks), "--approach-params", str(approach)]) == 0
    rows = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    row = rows[-1]
    assert row["kick"] == "kick_left" and row["nominal_distance_m"] == 9.9
    assert row["params"] == [str(kicks)] and row["approach_params"] == [str(approach)]
    assert all_kicks(0)["kick_left"].spec.distance != 9.9  # the shipped value is left alone


@pytest.mark.parametrize("option, text", [
    ("--params", "long_kick_k4_hip\t70\nlong_kick_no_such\t3\n"),
    ("--walk-params", "walk_height\t180\nmax_step_size_x\tabc\n"),
])
def test_a_bad_parameter_file_names_its_line(tmp_path, capsys, option, text):
    bad = tmp_path / "best.txt"
    bad.write_text(text)
    with pytest.raises(SystemExit) as e:
        main([option, str(bad), "--tries", "1"])
    assert e.value.code == 2
    assert f"{bad}:2" in capsys.readouterr().err


def test_a_walk_file_is_named_in_the_row(tmp_path, capsys):
    good = tmp_path / "stand.txt"
    good.write_text("walk_height\t185.5\n")
    assert main(["--kicks", "ik_forward_left", "--modes", "standing", "--tries", "1",
                 "--walk-params", str(good)]) == 0
    assert json.loads(capsys.readouterr().out.splitlines()[-1])["walk_params"] == [str(good)]

"""soccer batch --save-baseline and --against, with posture teams (draws) in this process."""

from __future__ import annotations

import json

from cli.main import main
from server.batch import BASELINE_KIND


def test_save_baseline_then_against_exits_3_only_when_worse(tmp_path, capsys):
    base = tmp_path / "base" / "b.json"
    args = ["batch", "--home", "posture", "--away", "posture", "--games", "2", "--half-time", "0.2",
            "--home-size", "1", "--away-size", "1", "--workers", "0", "--quiet"]
    assert main([*args, "--out", str(tmp_path / "b0"), "--save-baseline", str(base)]) == 0
    saved = json.loads(base.read_text())
    assert saved["kind"] == BASELINE_KIND and saved["goal_difference"]["n"] == 2
    assert saved["goal_difference"]["mean"] == 0 and saved["teams"] == {"A": "posture", "B": "posture"}
    capsys.readouterr()

    better = dict(saved, goal_difference={"n": 20, "mean": 2.0, "sd": 1.0, "se": 0.2236})
    (tmp_path / "better.json").write_text(json.dumps(better))
    assert main([*args, "--out", str(tmp_path / "b1"), "--against", str(tmp_path / "better.json")]) == 3
    out = capsys.readouterr().out
    assert "Welch's two-sample t-test, one-sided" in out and "WORSE than the baseline" in out

    worse = dict(saved, goal_difference={"n": 20, "mean": -2.0, "sd": 1.0, "se": 0.2236}, half_time=300.0)
    (tmp_path / "worse.json").write_text(json.dumps(worse))
    assert main([*args, "--out", str(tmp_path / "b2"), "--against", str(tmp_path / "worse.json")]) == 0
    out = capsys.readouterr().out
    assert "not significantly worse" in out and "warning: half_time" in out


def test_a_bad_baseline_is_refused_before_any_game(tmp_path, capsys):
    (tmp_path / "x.json").write_text("{}")
    code = main(["batch", "--games", "2", "--half-time", "0.2", "--out", str(tmp_path / "b"),
                 "--against", str(tmp_path / "x.json")])
    assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a batch baseline" in err[0]
    assert not (tmp_path / "b" / "games.jsonl").exists()

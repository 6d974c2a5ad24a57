"""Batches of matches (server.batch): statistics, alternating sides, error rows,
and a killed batch resumed to the same summary."""

import json
import math

import numpy as np
import pytest
from scipy import stats as st

from cli.teams import factory as resolve
from optimization.executor import InlineExecutor
from server.batch import (
    GAMES,
    SUMMARY,
    BatchError,
    BatchSettings,
    compare,
    describe,
    game_row,
    read_games,
    run_batch,
    summarize,
)

TINY = dict(half_time=0.2, home_size=1, away_size=1)


def batch(tmp_path, games=4, home="posture", away="posture", resume=False, seed=5, **kw):
    settings = BatchSettings(home, away, seed=seed, **{**TINY, **kw})
    played = []
    summary = run_batch(settings, games, tmp_path, resolve, InlineExecutor, resume=resume, inflight=1,
                        progress=None, on_row=played.append)
    return summary, played


# ---------------------------------------------------------------- statistics

def test_describe_matches_scipy():
    x = np.array([2, -1, 0, 3, 1, 1, -2, 0, 4])
    s = describe(x)
    assert s.n == 9 and s.mean == pytest.approx(x.mean())
    assert s.sd == pytest.approx(x.std(ddof=1))
    assert s.se == pytest.approx(st.sem(x))
    lo, hi = st.t.interval(0.95, len(x) - 1, loc=x.mean(), scale=st.sem(x))
    assert s.ci95 == pytest.approx((lo, hi))


def test_describe_small_samples():
    assert describe([]).mean is None
    one = describe([3])
    assert one.mean == 3 and one.se is None and one.ci95 is None
    same = describe([1, 1, 1])
    assert same.se == 0 and same.ci95 == (1, 1)


def test_compare_is_welch_as_scipy():
    rng = np.random.default_rng(1)
    a, b = rng.normal(0.3, 1.0, 40), rng.normal(0.0, 2.0, 25)
    c = compare(describe(a), describe(b))
    t, p = c  # unpacks as (t, p)
    ref = st.ttest_ind(a, b, equal_var=False)
    assert t == pytest.approx(ref.statistic) and p == pytest.approx(ref.pvalue)
    if hasattr(ref, "df"):
        assert c.df == pytest.approx(ref.df)
    assert "Welch" in c.test
    with pytest.raises(ValueError):
        compare(describe([1]), describe(b))


# --------------------------------------------------------------------- games

def test_seeds_and_alternating_sides(tmp_path):
    summary, played = batch(tmp_path, games=4)
    rows = sorted(played, key=lambda r: r["game"])
    assert [(r["game"], r["seed"], r["a_side"]) for r in rows] == [
        (0, 5, "L"), (1, 6, "R"), (2, 7, "L"), (3, 8, "R")]
    r = rows[0]
    assert r["teams"] == {"A": "posture", "B": "posture"} and r["game_time"] == pytest.approx(0.4, abs=0.03)
    assert {"score", "goal_difference", "goals", "events", "falls", "possession", "touches", "territory",
            "wall_time", "version"} <= set(r)
    assert summary["games"] == 4 and summary["errors"] == 0
    assert summary["wins"] + summary["draws"] + summary["losses"] == 4
    assert json.loads((tmp_path / SUMMARY).read_text()) == summary


def test_game_row_seen_from_team_a():
    result = {
        "score": {"L": 1, "R": 2}, "wall_time": 3.0, "game_time": 600.0,
        "events": [{"time": 12.5, "kind": "goal", "team": "R", "player": 7, "detail": "0:1"},
                   {"time": 40.0, "kind": "goal", "team": "L", "player": None, "detail": "1:1 (own goal)"},
                   {"time": 599.0, "kind": "goal", "team": "R", "player": 3, "detail": "1:2"}],
        "stats": {s: {"falls": f, "possession_share": 0.5, "ball_touches": 9}
                  for s, f in (("L", 4), ("R", 6))},
    }
    result["stats"]["L"]["territory"], result["stats"]["R"]["territory"] = -1.5, 1.5
    row = game_row(result, "R")  # team A played right
    assert row["score"] == {"A": 2, "B": 1} and row["goal_difference"] == 1
    assert row["territory"] == 1.5
    assert row["goals"] == {"A": 2, "B": 1} and row["falls"] == {"A": 6, "B": 4}
    assert [(g["team"], g["time"], g["player"]) for g in row["goal_times"]] == [
        ("A", 12.5, 7), ("B", 40.0, None), ("A", 599.0, 3)]


def test_crashing_agent_is_an_event_and_broken_factory_an_error_row(tmp_path):
    _, played = batch(tmp_path / "a", games=2, home="tests.batch_teams:raising_agent", home_size=2)
    for r in played:  # team A's agents crash on either side; the games finish
        assert "error" not in r
        assert r["events"]["agent_crashed"] == 2
        assert {c["team"] for c in r["crashes"]} == {"A"}
        assert r["crashes"][0]["reason"] == "act raised RuntimeError: agent gave up"
    summary, played = batch(tmp_path / "b", games=2, away="tests.batch_teams:broken_factory")
    assert [r["error"] for r in played] == ["RuntimeError: no agent for you"] * 2
    assert [r["seed"] for r in sorted(played, key=lambda r: r["game"])] == [5, 6]
    assert summary["errors"] == 2 and summary["error_games"] == [0, 1]
    assert summary["goal_difference"]["mean"] is None


def test_resume_plays_only_missing_games_and_gives_the_same_summary(tmp_path):
    full, _ = batch(tmp_path / "full", games=4)
    lines = (tmp_path / "full" / GAMES).read_bytes().splitlines(keepends=True)
    killed = tmp_path / "killed"
    killed.mkdir()
    (killed / "batch.json").write_bytes((tmp_path / "full" / "batch.json").read_bytes())
    (killed / GAMES).write_bytes(lines[0] + lines[1] + lines[2][:40])  # torn third line
    rows, good = read_games(killed / GAMES)
    assert sorted(rows) == [0, 1] and good == len(lines[0] + lines[1])
    with pytest.raises(BatchError, match="already holds a batch"):
        batch(killed, games=4)
    with pytest.raises(BatchError, match="different batch"):
        batch(killed, games=4, resume=True, seed=6)
    resumed, played = batch(killed, games=4, resume=True)
    assert sorted(r["game"] for r in played) == [2, 3]
    assert resumed == full
    assert json.loads((killed / SUMMARY).read_text()) == full
    assert len((killed / GAMES).read_text().splitlines()) == 4  # the torn line is gone
    _, played = batch(killed, games=4, resume=True)  # nothing left to play
    assert played == []


def test_summary_counts():
    s = BatchSettings("a", "b", 1.0)
    rows = [{"game": i, "seed": i, "a_side": "L" if i % 2 == 0 else "R", "goal_difference": gd,
             "score": {"A": max(gd, 0), "B": max(-gd, 0)}, "falls": {"A": 1, "B": 0},
             "possession": {"A": 0.5, "B": 0.5}, **({"territory": 0.5 * i} if i else {})}
            for i, gd in enumerate([1, 0, -2, 3])]
    rows.append({"game": 4, "seed": 4, "a_side": "L", "error": "boom"})
    out = summarize(s, rows[::-1])
    assert (out["wins"], out["draws"], out["losses"]) == (2, 1, 1)
    assert out["goals_for"] == 4 and out["goals_against"] == 2
    assert out["goal_difference"]["mean"] == 0.5 and out["errors"] == 1
    assert math.isclose(out["goal_difference"]["se"], np.std([1, 0, -2, 3], ddof=1) / 2, rel_tol=1e-5)
    assert out["goal_difference_by_a_side"] == {"L": -0.5, "R": 1.5}
    assert out["territory"]["n"] == 3 and out["territory"]["mean"] == 1.0  # game 0 has none

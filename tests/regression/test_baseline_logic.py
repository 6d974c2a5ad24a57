"""The comparison of a batch with a stored baseline (server.batch), on synthetic rows:
no matches are played."""

from __future__ import annotations

import json
import math

import pytest
from scipy import stats as sst

from server.batch import (
    BASELINE_KIND,
    BatchError,
    BatchSettings,
    Stats,
    against,
    baseline_stats,
    describe,
    describe_dict,
    read_baseline,
    save_baseline,
    settings_mismatch,
    summarize,
)

SETTINGS = BatchSettings("villa", "posture", 30.0, 0, 3, 3)


def rows(diffs: list[int]) -> list[dict]:
    out = []
    for i, d in enumerate(diffs):
        a, b = max(d, 0), max(-d, 0)
        out.append({"game": i, "seed": i, "a_side": "LR"[i % 2], "score": {"A": a, "B": b},
                    "goal_difference": d, "falls": {"A": 0, "B": 0}, "possession": {"A": 0.5, "B": 0.5}})
    return out


def test_baseline_round_trip_keeps_n_mean_sd(tmp_path):
    summary = summarize(SETTINGS, rows([2, 1, 3, 0, 2]))
    path = tmp_path / "b" / "base.json"
    saved = save_baseline(path, summary, note="synthetic")
    assert not list(path.parent.glob(".*tmp*"))  # written atomically: no temporary left
    base = read_baseline(path)
    assert base == json.loads(path.read_text()) == saved
    assert base["kind"] == BASELINE_KIND and base["note"] == "synthetic"
    s = baseline_stats(base)
    want = describe([2, 1, 3, 0, 2])
    assert (s.n, s.mean) == (5, pytest.approx(want.mean))
    assert s.sd == pytest.approx(want.sd) and s.se == pytest.approx(want.se, abs=1e-5)
    assert base["teams"] == {"A": "villa", "B": "posture"} and base["sizes"] == {"A": 3, "B": 3}


def test_a_clearly_worse_batch_is_worse_and_a_same_or_better_one_is_not():
    base = describe([2, 1, 3, 0, 2, 1, 2, 3, 1, 2])
    worse = against(describe([0, -1, 0, 1, 0, -1, 0, 0, 1, 0]), base)
    assert worse.worse and worse.p < 0.05 and worse.t < 0
    same = against(describe([2, 1, 3, 0, 2, 1, 2, 3, 1, 2]), base)
    assert not same.worse and same.p == pytest.approx(0.5)
    better = against(describe([4, 3, 5, 2, 4, 3, 4, 5, 3, 4]), base)
    assert not better.worse and better.p > 0.99
    assert "Welch" in worse.test and "one-sided" in worse.test
    assert "WORSE" in worse.text() and "not significantly worse" in better.text()


def test_the_one_sided_p_is_half_the_two_sided_welch_p_below_the_baseline():
    new, base = [0, 1, 2, 1, 0, 1], [1, 2, 2, 1, 3, 2, 1]
    two = sst.ttest_ind(new, base, equal_var=False)
    r = against(describe(new), describe(base))
    assert r.t == pytest.approx(two.statistic)
    assert r.p == pytest.approx(two.pvalue / 2)


def test_a_small_dip_within_the_noise_is_not_worse():
    base = describe([1, 0, 2, -1, 1, 3, 0, 1])
    r = against(describe([0, 1, 1, -1, 2, 0, 1, 0]), base)
    assert r.new.mean < r.base.mean
    assert not r.worse and 0.05 < r.p < 0.5


def test_samples_without_spread_compare_their_means():
    assert against(describe([1, 1, 1]), describe([2, 2, 2])).worse
    r = against(describe([2, 2]), describe([2, 2, 2]))
    assert not r.worse and r.p == 1.0 and "no spread" in r.text()


def test_too_few_games_is_an_error_not_a_verdict():
    with pytest.raises(ValueError, match="at least 2 games"):
        against(describe([1]), describe([1, 2, 3]))
    with pytest.raises(ValueError):
        against(describe([1, 2]), Stats(1, 1.0, None, None, None))


def test_stats_from_a_summary_dict_match_describe():
    summary = summarize(SETTINGS, rows([1, -1, 2, 0]))
    assert describe_dict(summary["goal_difference"]).mean == pytest.approx(0.5)
    sd = describe_dict(summary["goal_difference"]).sd
    assert math.isclose(sd, describe([1, -1, 2, 0]).sd, rel_tol=1e-5)


def test_bad_baselines_are_one_line_errors(tmp_path):
    missing = tmp_path / "none.json"
    with pytest.raises(BatchError, match="cannot read baseline"):
        read_baseline(missing)
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    with pytest.raises(BatchError, match="not valid JSON"):
        read_baseline(bad)
    other = tmp_path / "other.json"
    other.write_text(json.dumps({"goal_difference": {"n": 3, "mean": 1, "sd": 1}}))
    with pytest.raises(BatchError, match="not a batch baseline"):
        read_baseline(other)
    broken = tmp_path / "broken.json"
    broken.write_text(json.dumps({"kind": BASELINE_KIND, "goal_difference": {"mean": 1}}))
    with pytest.raises(BatchError, match="no goal_difference"):
        read_baseline(broken)


def test_settings_mismatch_names_what_differs():
    base = {"teams": {"A": "villa", "B": "posture"}, "half_time": 30.0, "sizes": {"A": 3, "B": 3}}
    summary = summarize(SETTINGS, rows([1, 2]))
    assert settings_mismatch(base, summary) == []
    other = summarize(BatchSettings("villa", "posture", 60.0, 0, 3, 3), rows([1, 2]))
    assert [d.split()[0] for d in settings_mismatch(base, other)] == ["half_time"]

"""The benchmarks' confidence intervals: Wilson's formula, and the rows that carry them."""

import math

import pytest

from benchmarks.getup import getup_stats
from benchmarks.stats import rate_ci


def wilson(k: int, n: int, z: float = 1.959964) -> tuple[float, float]:
    """Wilson's score interval written out (Wilson 1927)."""
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return centre - half, centre + half


@pytest.mark.parametrize("k, n", [(0, 20), (18, 20), (20, 20), (96, 100), (309, 400)])
def test_rate_ci_is_wilsons_interval(k, n):
    lo, hi = rate_ci(k, n)
    assert (lo, hi) == pytest.approx(wilson(k, n), abs=1e-3)
    assert lo <= k / n <= hi


def test_more_tries_narrow_the_interval_and_20_tries_cannot_tell_90_from_96_percent():
    lo20, hi20 = rate_ci(18, 20)
    lo400, hi400 = rate_ci(360, 400)
    assert hi400 - lo400 < 0.5 * (hi20 - lo20)
    assert hi20 > 0.96


def test_bad_counts_are_refused():
    for k, n in [(3, 2), (-1, 5), (0, 0)]:
        with pytest.raises(ValueError, match="successes"):
            rate_ci(k, n)


def test_the_getup_benchmark_row_carries_an_interval_around_each_rate():
    row = getup_stats(1, tries=2, seed=0)
    for side in ("front", "back"):
        lo, hi = row[f"{side}_success_ci95"]
        assert lo <= row[f"{side}_success"] <= hi and hi - lo > 0.3  # two tries say little


def test_the_getup_benchmark_plays_a_match_start_through_motion():
    """--start walk: the walk's stand pose, Motion in charge. Type 0 stands from the front
    in 99 of 100 such tries (seed 1); before the front getup lay flat first, in 24."""
    row = getup_stats(0, tries=2, seed=0, start="walk")
    assert row["start"] == "walk" and row["front_success"] >= 0.5
    with pytest.raises(ValueError, match="start must be one of flat, walk"):
        getup_stats(0, tries=1, start="lying")

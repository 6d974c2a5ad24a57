"""Confidence intervals for the benchmarks' success rates.

A rate over 20 tries is coarse: a skill that succeeds 96% of the time shows 90%
or less in one run of 20 about one time in five. Each rate is printed with its
95% Wilson score interval (scipy's `binomtest(...).proportion_ci`), so that a
reader can tell a change from noise.
"""

from __future__ import annotations

from scipy.stats import binomtest


def rate_ci(successes: int, tries: int, level: float = 0.95) -> list[float]:
    """The Wilson score interval [low, high] (fractions, 3 digits) of `successes` in `tries`."""
    if tries < 1 or not 0 <= successes <= tries:
        raise ValueError(f"need 0 <= successes <= tries and tries >= 1, not {successes} of {tries}")
    ci = binomtest(int(successes), int(tries)).proportion_ci(confidence_level=level, method="wilson")
    return [round(float(ci.low), 3), round(float(ci.high), 3)]

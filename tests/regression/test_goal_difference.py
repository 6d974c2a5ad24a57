"""Regression tests on goal difference.

CI (always): a short seeded batch of villa against posture must show villa winning
by at least MARGIN goals a game on average; the same check must fail for a broken
villa that never kicks nor dribbles (`tests.regression.teams:broken`), so the test
can fail at all. Measured (2 x 150 s, 3 vs 3, seeds 0-1, villa left then right):
villa vs posture 3:0 and 4:0 (the dribbling villa of December 5, 2026: 2:0 and 3:0; with
the dribble cone: 2:0 and 2:0), the broken team 0:0 and 0:0. Halves of 60 s were too
short for two games to tell: villa scored 2 goals in 6 such games once its particle
filter drew its noise once a frame (it had scored 1 a game in the first two).

Full (with --baseline FILE, see conftest.py): a batch with the baseline's settings
compared with it by Welch's one-sided t-test.
"""

from __future__ import annotations

import pytest

from cli import teams
from optimization.executor import ExecutorFactory
from server.batch import BatchSettings, against, baseline_stats, describe_dict, read_baseline, run_batch

CI_GAMES = 2  # game 0: villa left, seed 0; game 1: villa right, seed 1
CI_HALF_TIME = 150.0  # s
CI_SIZE = 3  # players a side (goalie and two field players)
MARGIN = 1.0  # goals a game villa must win by, on average over the CI games
BROKEN = "tests.regression.teams:broken"


def play(tmp_path, home: str, away: str = "posture", games: int = CI_GAMES, half_time: float = CI_HALF_TIME,
         sizes: tuple[int, int] = (CI_SIZE, CI_SIZE), seed: int = 0, workers: int | None = 2) -> dict:
    settings = BatchSettings(home, away, half_time, seed, *sizes)
    factory = ExecutorFactory(workers=workers)
    try:
        return run_batch(settings, games, tmp_path / home.replace(":", "_"), teams.factory, factory,
                         progress=None)
    finally:
        factory.close()


def check_wins(summary: dict, margin: float = MARGIN) -> None:
    """Team A won by at least `margin` goals a game on average, and every game was played."""
    assert summary["errors"] == 0, f"games failed: {summary['error_games']}"
    gd = summary["goal_difference"]["mean"]
    a, b = summary["teams"]["A"], summary["teams"]["B"]
    assert gd is not None and gd >= margin, (
        f"{a} vs {b}: mean goal difference {gd:+.2f} over {summary['played']} games "
        f"(goals {summary['goals_for']}:{summary['goals_against']}), below the margin {margin:+.2f}")


def test_villa_beats_posture_by_the_margin(tmp_path):
    check_wins(play(tmp_path, "villa"))


def test_the_check_fails_for_a_team_that_never_kicks_nor_dribbles(tmp_path):
    summary = play(tmp_path, BROKEN)
    with pytest.raises(AssertionError, match="below the margin"):
        check_wins(summary)


def test_against_baseline(tmp_path, request, baseline_file):
    if baseline_file is None:
        pytest.skip("no --baseline FILE given (pytest tests/regression --baseline FILE [--games N])")
    base = read_baseline(baseline_file)
    opt = request.config.getoption
    games = opt("games", default=None) or base["goal_difference"]["n"]
    half_time = opt("half_time", default=None) or base["half_time"]
    summary = play(tmp_path, base["teams"]["A"], base["teams"]["B"], games, half_time,
                   (base["sizes"]["A"], base["sizes"]["B"]), base["seed"], opt("workers", default=None))
    assert summary["errors"] == 0, f"games failed: {summary['error_games']}"
    result = against(describe_dict(summary["goal_difference"]), baseline_stats(base))
    print(f"\n{baseline_file}:\n{result.text()}")
    assert not result.worse, result.text()

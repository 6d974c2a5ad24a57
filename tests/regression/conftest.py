"""Options of the goal-difference regression tests (run `pytest tests/regression ...`
so that pytest reads them):

    pytest tests/regression --baseline tests/regression/baselines/villa-posture.json \\
        [--baseline ...] [--games N] [--half-time S] [--workers W]

plays a batch with each baseline's teams, team sizes, half time and first seed
(`--games`/`--half-time` override its n and half time) and fails when the mean goal
difference is significantly worse than the baseline's (Welch, one-sided, p < 0.05).
Without --baseline only the short CI check and the logic tests run.
"""

from __future__ import annotations


def pytest_addoption(parser):
    group = parser.getgroup("regression", "goal-difference regression against a stored baseline")
    group.addoption("--baseline", action="append", default=[], metavar="FILE",
                    help="compare a new batch with this baseline (repeatable)")
    group.addoption("--games", type=int, default=None, metavar="N",
                    help="games of the new batch (default: the baseline's)")
    group.addoption("--half-time", type=float, default=None, metavar="S",
                    help="half time of the new batch (default: the baseline's)")
    group.addoption("--workers", type=int, default=None, metavar="W",
                    help="local worker processes (default: one per core)")


def pytest_generate_tests(metafunc):
    if "baseline_file" in metafunc.fixturenames:
        files = metafunc.config.getoption("baseline", default=[]) or []
        metafunc.parametrize("baseline_file", files or [None], ids=[str(f) for f in files] or ["none"])

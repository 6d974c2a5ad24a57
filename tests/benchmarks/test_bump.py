"""benchmarks.bump: two robots walk into each other."""

from __future__ import annotations

import math

import numpy as np
import pytest

from benchmarks import bump


def test_the_meetings_make_contact():
    """Head-on and side by side, the two walking robots' torsos come within touching
    distance (a torso is about 0.1 m deep, the arms stand out 0.1 m each side)."""
    for seed, meeting in ((0, "head-on"), (1, "side by side")):
        row = bump.bump(seed, [], [], [0], 4.0)
        assert row["meeting"] == meeting and row["type"] == 0
        assert row["closest"] < 0.3, row


def test_starts_face_each_other_head_on_and_converge_side_by_side():
    rng = np.random.default_rng(3)
    (ax, ay, ah), (bx, by, bh) = bump.starts("head-on", rng)
    assert ax < 0 < bx and ah == 0.0 and bh == math.pi and abs(by - ay) <= 0.25
    for _ in range(10):
        (ax, ay, ah), (bx, by, bh) = bump.starts("side by side", rng)
        assert 0.5 <= abs(ay - by) <= 0.9 and abs(ax - bx) <= 0.2
        assert ah == -bh and math.copysign(1, ah) == math.copysign(1, by - ay)  # each turned toward the other


def test_summary_pairs_a_with_b_in_each_trial():
    def row(meeting: str, a: bool, b: bool) -> dict:
        return {"meeting": meeting, "fell": [a, b]}

    s = bump.summary([row("head-on", True, False), row("head-on", True, True),
                      row("side by side", False, True), row("side by side", False, False)])
    assert s["all"]["falls_a"] == 0.5 and s["all"]["falls_b"] == 0.5 and s["all"]["a_minus_b"] == 0.0
    assert s["all"]["se"] == pytest.approx(0.408, abs=1e-3)  # differences 1, 0, -1, 0
    assert s["head-on"]["a_minus_b"] == 0.5 and s["side by side"]["a_minus_b"] == -0.5


def test_cli_errors(capsys, tmp_path):
    bad = tmp_path / "walk.txt"
    bad.write_text("balance_step_x\tabc\n")
    for argv, message in ((["--params", str(bad)], f"{bad}:1"), (["--trials", "1"], "--trials"),
                          (["--types", "7"], "robot types are 0-4")):
        with pytest.raises(SystemExit):
            bump.main(argv)
        assert message in capsys.readouterr().err

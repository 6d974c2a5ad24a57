"""benchmarks.playstats: where and how the ball is played in a match log."""

from __future__ import annotations

import json
from types import SimpleNamespace

import numpy as np
import pytest

from agent.posture import PostureAgent
from benchmarks import playstats
from models import field as fld
from models.rules import PLAY_MODES, PlayMode
from models.scene import Lineup
from server.log import write_log
from server.match import Match


def _replay(ball: np.ndarray, players: np.ndarray, sides: list[str],
            modes: list[PlayMode]) -> SimpleNamespace:
    """A stand-in for replay.poses.Replay over given ball (T, 3) and torso (T, n, 3) positions."""
    log = SimpleNamespace(play_mode=np.array([PLAY_MODES.index(m) for m in modes]))
    return SimpleNamespace(log=log, sides=np.array(sides), ball=lambda f: ball[f],
                           positions=lambda f: players[f])


def test_shares_count_the_frames_in_play_only():
    t = 101  # frame 0 is before the kickoff; 100 frames in play
    ball = np.zeros((t, 3))
    ball[1:41, 1] = fld.HALF_WIDTH - 1.0  # 40 frames wide, the other 60 on the long axis
    ball[0, 1] = fld.HALF_WIDTH - 0.5  # not in play: not counted
    ball[81:, 0] = fld.HALF_LENGTH - 1.0  # the last 20 near a goal
    players = np.full((t, 2, 3), 50.0)
    players[1:31, 0, :2] = ball[1:31, :2] + [0.3, 0.0]  # 30 frames contested: one of each within 0.6 m
    players[1:31, 1, :2] = ball[1:31, :2] + [0.0, -0.5]
    players[31:51, 0, :2] = ball[31:51, :2] + [0.2, 0.0]  # 20 with only L near
    modes = [PlayMode.BEFORE_KICK_OFF] + [PlayMode.PLAY_ON] * 100
    s = playstats.play_stats(_replay(ball, players, ["L", "R"], modes))
    assert s["contested"] == pytest.approx(0.3) and s["free"] == pytest.approx(0.5)
    assert s["wide"] == pytest.approx(0.4) and s["central"] == pytest.approx(0.6)
    assert s["near_goal"] == pytest.approx(0.2)
    assert s["spell_s"] == pytest.approx(30 * 0.02)
    assert s["crowd"] == pytest.approx((30 * 2 + 20) / 100 / 2)
    # still: 99 frame pairs in play, of which the ball jumps at 40->41 and 80->81 only
    assert s["still"] == pytest.approx(97 / 99)


def test_a_log_without_play_is_an_error():
    r = _replay(np.zeros((3, 3)), np.zeros((3, 2, 3)), ["L", "R"], [PlayMode.BEFORE_KICK_OFF] * 3)
    with pytest.raises(playstats.LogError, match="no play"):
        playstats.play_stats(r)


def test_cli_reads_recorded_logs_and_names_a_bad_one(tmp_path, capsys):
    m = Match(PostureAgent, PostureAgent, Lineup.default(2, 2), half_time=10.0, seed=3, record=True)
    for _ in range(10):
        m.step()
    m.referee.set_play_mode(PlayMode.PLAY_ON)  # trainer: posture players never kick off
    m.world.place_ball((0.0, fld.HALF_WIDTH - 1.0), velocity=(0.0, 0.0, 0.0))
    for _ in range(50):
        m.step()
    path = tmp_path / "m.npz"
    write_log(m.match_log(), path)
    assert playstats.main([str(path), str(path)]) == 0
    lines = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert lines[0]["players"] == 4 and lines[0]["wide"] == 1.0 and lines[0]["central"] == 0.0
    assert lines[2]["logs"] == 2 and lines[2]["mean_se"]["wide"] == {"mean": 1.0, "se": 0.0}
    assert playstats.main([str(tmp_path / "none.npz")]) == 2
    assert "none.npz: no such match log" in capsys.readouterr().err

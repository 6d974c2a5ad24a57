"""The top-down picture shows players, ball and role targets where the log puts them
(needs no OpenGL, always runs)."""

from __future__ import annotations

import numpy as np
from PIL import Image

from cli.main import main
from replay import load
from replay.topdown import BALL_COLOR, TEAM_COLORS, TopDown, save_topdown

from .conftest import MOVE_AT, target_of

TOL = 40  # per channel, of 255: anti-aliasing and PNG round trip


def _rgb(color) -> np.ndarray:
    return np.round(np.array(color) * 255)


def _pixel(img: np.ndarray, td: TopDown, xy) -> np.ndarray:
    col, row = np.round(td.pixel(*xy)).astype(int)
    return img[row, col, :3].astype(float)


def test_players_ball_and_targets_are_where_the_log_puts_them(recorded, tmp_path):
    r = load(recorded.path)
    at = float(r.log.game_time[MOVE_AT + 30])
    out = tmp_path / "field.png"
    i = save_topdown(r, out, at, width=900)
    img = np.asarray(Image.open(out).convert("RGB"))
    td = TopDown(900)
    assert img.shape == (td.height, td.width, 3)
    pos = r.positions(i)[:, :2]
    fallen = r.fallen(i)
    assert fallen.sum() == 1
    for k, name in enumerate(r.players):
        team = _rgb(TEAM_COLORS[name[0]])
        if fallen[k]:
            # A black cross over the disc's center; the disc shows beside it.
            assert np.all(_pixel(img, td, pos[k]) < 60), name
            assert np.all(np.abs(_pixel(img, td, pos[k] + (0.22, 0.0)) - team) < TOL), name
        else:
            assert np.all(np.abs(_pixel(img, td, pos[k]) - team) < TOL), name
    assert np.all(np.abs(_pixel(img, td, r.ball(i)[:2]) - _rgb(BALL_COLOR)) < TOL)
    # Role targets of the left team: a cross in the team's color at each target.
    for u in (1, 2, 3):
        assert np.all(np.abs(_pixel(img, td, target_of(u)) - _rgb(TEAM_COLORS["L"])) < TOL + 30), u
    # Grass where nobody stands.
    grass = _pixel(img, td, (-6.0, 8.0))
    assert grass[1] > grass[0] + 40 and grass[1] > grass[2] + 40


def test_picture_moves_with_the_log(recorded):
    """L2 is elsewhere before the trainer moves it: the picture follows the frame."""
    r = load(recorded.path)
    td = TopDown(600)
    k = r.players.index("L2")
    blue = _rgb(TEAM_COLORS["L"])
    before, after = r.positions(MOVE_AT - 10)[k, :2], r.positions(MOVE_AT + 10)[k, :2]
    assert np.hypot(*(after - before)) > 3
    img = td.draw(r, MOVE_AT - 10)
    assert np.all(np.abs(_pixel(img, td, before) - blue) < TOL)
    assert not np.all(np.abs(_pixel(img, td, after) - blue) < TOL)
    img = td.draw(r, MOVE_AT + 10)  # the same figure, redrawn
    assert np.all(np.abs(_pixel(img, td, after) - blue) < TOL)
    assert not np.all(np.abs(_pixel(img, td, before) - blue) < TOL)


def test_render_command_writes_a_picture_with_trails(recorded, tmp_path, capsys):
    out = tmp_path / "sub" / "trail.png"
    assert main(["render", str(recorded.path), "--out", str(out), "--at", "3", "--trail", "2",
                 "--size", "600x400"]) == 0
    img = Image.open(out)
    assert img.size[0] == 600
    assert "top-down picture" in capsys.readouterr().out
    # The ball's dashed path is drawn between where it was 2 s earlier and now.
    r = load(recorded.path)
    td = TopDown(600)
    a = np.asarray(img.convert("RGB"))
    i0, i1 = r.frame_at(1.0), r.frame_at(3.0)
    mid = r.ball((i0 + i1) // 2)[:2]
    assert np.hypot(*(r.ball(i1)[:2] - mid)) > 0.3  # off the drawn ball (0.2 m)
    near = [_pixel(a, td, mid + d) for d in ((0, 0), (0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05))]
    assert any(np.all(np.abs(p - _rgb(BALL_COLOR)) < TOL + 20) for p in near)


def test_picture_usage_errors(recorded, tmp_path, capsys):
    log = str(recorded.path)
    assert main(["render", log, "--out", str(tmp_path / "a.png")]) == 2
    assert "--at" in capsys.readouterr().err
    assert main(["render", log, "--out", str(tmp_path / "a.gif"), "--at", "1"]) == 2
    assert main(["render", log, "--out", str(tmp_path / "a.txt"), "--at", "1"]) == 2
    assert "unknown output" in capsys.readouterr().err

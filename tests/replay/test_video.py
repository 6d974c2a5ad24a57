"""3D rendering of a logged match: frames show the players where the log puts them,
videos are written as MP4, GIF and PNG frames, and missing OpenGL is reported clearly.

The rendering tests need offscreen OpenGL (EGL or OSMesa; `.ci/system-deps.sh`
installs Mesa's EGL) and skip, saying why, when none can be had.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest
from PIL import Image

from cli.main import main
from replay import gl, load
from replay.video import CameraRig, render_video
from replay.viewer import KEY_END, KEY_LEFT, KEY_RIGHT, KEY_SPACE, Playback

from .conftest import MOVE_AT

SIZE = (320, 240)


@pytest.fixture(scope="module")
def need_gl():
    ok, why = gl.available()
    if not ok:
        pytest.skip(f"no offscreen OpenGL on this machine: {why}")


def _team_dominant(pixels: np.ndarray, side: str) -> bool:
    """Whether any pixel is clearly blue (left team) or red (right team)."""
    p = pixels.reshape(-1, 3).astype(int)
    r, b = p[:, 0], p[:, 2]
    return bool(np.any(b > r + 60) if side == "L" else np.any(r > b + 60))


def _patch(img: np.ndarray, uv: np.ndarray, half: int = 2) -> np.ndarray:
    c, r = np.round(uv).astype(int)
    return img[max(r - half, 0):r + half + 1, max(c - half, 0):c + half + 1]


def test_frames_show_players_where_the_log_puts_them(recorded, tmp_path, need_gl):
    r = load(recorded.path)
    start = float(r.log.game_time[MOVE_AT + 20])
    out = tmp_path / "frames"
    n = render_video(r, out, camera="top", start=start, end=start + 0.4, fps=5, size=SIZE)
    files = sorted(out.glob("frame_*.png"))
    assert n == len(files) == 3
    frames = r.frames(start, start + 0.4, 5)
    # The top camera does not move: project with a renderer set up the same way.
    rig = CameraRig(r, "top", SIZE[0] / SIZE[1])
    with gl.OffscreenRenderer(r.model, *SIZE) as ren:
        ren.update(r.set_frame(int(frames[0])), rig.update(int(frames[0])))
        for f, path in zip(frames, files):
            img = np.asarray(Image.open(path).convert("RGB"))
            assert img.shape == (SIZE[1], SIZE[0], 3)
            heads = r.set_frame(int(f)).xpos[[r.model.body(f"{p}/head").id for p in r.players]]
            uv = ren.project(heads)
            for k, name in enumerate(r.players):
                assert _team_dominant(_patch(img, uv[k]), name[0]), (name, uv[k])
            # Where nobody stands the field is grass, not a team color.
            empty = ren.project(np.array([[-8.0, -6.0, 0.0]]))[0]
            assert not _team_dominant(_patch(img, empty), "L") and not _team_dominant(_patch(img, empty), "R")
    # L2 was moved by the trainer: in an earlier frame it is not at its later place.
    k = r.players.index("L2")
    early = np.asarray(Image.open(files[0]).convert("RGB"))
    later_uv = uv[k]
    assert _team_dominant(_patch(early, later_uv), "L")  # frames after the move
    old = render_video(r, tmp_path / "old", camera="top", start=float(r.log.game_time[MOVE_AT - 10]),
                       end=float(r.log.game_time[MOVE_AT - 10]), fps=5, size=SIZE)
    assert old == 1
    before = np.asarray(Image.open(tmp_path / "old" / "frame_00000.png").convert("RGB"))
    assert not _team_dominant(_patch(before, later_uv), "L")


def test_gif_and_overlay(recorded, tmp_path, need_gl):
    out = tmp_path / "clip.gif"
    assert main(["render", str(recorded.path), "--out", str(out), "--from", "1", "--to", "1.5",
                 "--fps", "10", "--size", "160x120", "--camera", "ball", "--quiet"]) == 0
    with Image.open(out) as im:
        assert im.size == (160, 120) and im.n_frames == 6
        band = np.asarray(im.convert("RGB"))[:5]
    assert band.mean() < 80  # the dark overlay band with the clock, score and play mode


@pytest.mark.skipif(importlib.util.find_spec("imageio_ffmpeg") is None,
                    reason="imageio-ffmpeg is not installed (pip install imageio-ffmpeg)")
def test_mp4(recorded, tmp_path, need_gl, capsys):
    import imageio_ffmpeg
    out = tmp_path / "clip.mp4"
    assert main(["render", str(recorded.path), "--out", str(out), "--from", "2", "--to", "2.5",
                 "--fps", "20", "--size", "320x240", "--camera", "follow:L2", "--quiet"]) == 0
    assert "wrote 11 frames" in capsys.readouterr().out
    reader = imageio_ffmpeg.read_frames(str(out))
    meta = next(reader)
    assert tuple(meta["size"]) == (320, 240)
    assert sum(1 for _ in reader) == 11
    assert not list(tmp_path.glob(".*tmp*"))


def test_missing_gl_is_reported_with_what_to_install(recorded, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(gl, "backends", lambda: ["egl", "osmesa"])
    monkeypatch.setattr(gl, "_library_missing", lambda b: f"lib{b} not found")
    monkeypatch.setattr(gl, "_working", None)
    with pytest.raises(gl.GLUnavailable, match="apt-get install"):
        gl.gl_context(64, 64)
    out = tmp_path / "x.gif"
    assert main(["render", str(recorded.path), "--out", str(out), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert "no offscreen OpenGL" in err and "libegl1" in err and "libosmesa6" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()


def test_a_mujoco_gl_without_its_library_is_reported(recorded, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("MUJOCO_GL", "osmesa")
    monkeypatch.setattr("ctypes.util.find_library", lambda name: None)
    assert main(["render", str(recorded.path), "--out", str(tmp_path / "x.gif")]) == 1
    err = capsys.readouterr().err
    assert "MUJOCO_GL=osmesa" in err and "libosmesa6" in err


def test_view_without_a_display_fails_in_one_line(recorded, monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr("sys.platform", "linux")
    assert main(["view", str(recorded.path)]) == 2
    err = capsys.readouterr().err
    assert "no display" in err and len(err.strip().splitlines()) == 1


def test_playback_play_pause_seek():
    p = Playback(n_frames=501, frame_rate=50.0)  # 10 s
    assert p.tick(100.0) == 0
    assert p.tick(101.0) == 50  # plays at real speed
    p.key(KEY_SPACE)
    assert p.tick(105.0) == 50  # paused
    p.key(KEY_RIGHT)
    assert p.frame == 100
    p.key(KEY_LEFT)
    p.key(KEY_LEFT)
    assert p.frame == 0
    p.key(KEY_LEFT)
    assert p.frame == 0  # clamped at the start
    p.key(KEY_END)
    assert p.frame == 500
    assert p.tick(106.0) == 500
    p.key(KEY_SPACE)  # at the end, play starts over
    assert p.playing and p.tick(106.0) == 0 and p.tick(106.5) == 25

"""Match logs round-trip exactly and bad logs are refused with a clear error."""

from __future__ import annotations

import dataclasses
import zipfile

import numpy as np
import pytest

from cli.main import main
from replay import Replay, load
from server.log import QPOS_STEP, LogError, read_log, write_log

from .conftest import MOVE_AT, R3_PLACE, target_of


def test_log_round_trips(recorded, tmp_path):
    back = read_log(recorded.path)
    log = recorded.log
    assert back.xml == log.xml and back.players == log.players and back.events == log.events
    for k in ("time", "game_time", "play_mode", "score", "targets"):
        np.testing.assert_array_equal(getattr(back, k), getattr(log, k), err_msg=k)
    # qpos is stored quantized (QPOS_STEP); rewriting a read log changes nothing more.
    np.testing.assert_allclose(back.qpos, log.qpos, atol=QPOS_STEP)
    again = tmp_path / "again.npz"
    write_log(back, again)
    np.testing.assert_array_equal(read_log(again).qpos, back.qpos)


def test_replay_poses_match_the_recorded_world(recorded):
    r = load(recorded.path)
    frames = np.arange(len(r))
    # Forward kinematics from the logged (float32) qpos puts every torso where it was.
    for i in (0, MOVE_AT - 1, MOVE_AT + 5, len(r) - 1):
        d = r.set_frame(i)
        np.testing.assert_allclose(d.xpos[r.torso_bodies], recorded.torso_xpos[i], atol=2e-4)
    # Vectorized poses straight from qpos agree with MuJoCo's rotation matrices.
    np.testing.assert_allclose(r.positions(frames), recorded.torso_xpos, atol=2e-4)
    xm = recorded.torso_xmat
    heading = np.arctan2(xm[..., 3], xm[..., 0])
    dh = np.angle(np.exp(1j * (r.headings(frames) - heading)))
    assert np.abs(dh).max() < 1e-3
    np.testing.assert_allclose(r.up_z(frames), xm[..., 8], atol=1e-4)
    r3 = r.players.index("R3")
    assert r.fallen(len(r) - 1)[r3] and not r.fallen(len(r) - 1)[r.players.index("R1")]
    np.testing.assert_allclose(r.positions(MOVE_AT + 2)[r3, :2], R3_PLACE, atol=0.05)
    np.testing.assert_allclose(r.targets(10)[r.players.index("L2")], target_of(2))
    assert np.isnan(r.targets(10)[r.players.index("R2")]).all()


def test_frames_by_game_time(recorded):
    r = load(recorded.path)
    g = r.log.game_time
    i = r.frame_at(2.0)
    assert g[i] >= 2.0 - 1e-6 and (i == 0 or g[i - 1] < 2.0 - 1e-6)
    f = r.frames(1.0, 2.0, fps=10)
    assert np.all(np.diff(f) > 0) and g[f[0]] >= 1.0 - 1e-6 and g[f[-1]] <= 2.0 + 1e-6
    assert abs(len(f) - 11) <= 1  # 10 frames a second of server time, both ends
    with pytest.raises(ValueError):
        r.frames(2.0, 1.0, fps=10)


def _truncated(src, dst, fraction=0.5):
    data = src.read_bytes()
    dst.write_bytes(data[: int(len(data) * fraction)])
    return dst


def test_corrupt_or_truncated_logs_are_refused(recorded, tmp_path):
    trunc = _truncated(recorded.path, tmp_path / "trunc.npz")
    with pytest.raises(LogError, match="corrupt or truncated"):
        load(trunc)
    garbage = tmp_path / "garbage.npz"
    garbage.write_bytes(bytes(np.random.default_rng(3).integers(0, 256, 5000, dtype=np.uint8)))
    with pytest.raises(LogError, match="corrupt or truncated"):
        load(garbage)
    other = tmp_path / "other.npz"
    np.savez(other, a=np.zeros(3))
    with pytest.raises(LogError, match="not a match log"):
        load(other)
    # A member damaged inside an intact zip (bit rot in the compressed qpos).
    rotten = tmp_path / "rotten.npz"
    with zipfile.ZipFile(recorded.path) as zin, zipfile.ZipFile(rotten, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == "qpos_delta.npy":
                data = data[: len(data) // 2]
            zout.writestr(item, data)
    with pytest.raises(LogError):
        load(rotten)


def test_logs_that_do_not_fit_their_scene_are_refused(recorded):
    log = recorded.log
    with pytest.raises(LogError, match="qpos"):
        Replay(dataclasses.replace(log, qpos=log.qpos[:, :-3]))
    with pytest.raises(LogError, match="no frames"):
        Replay(dataclasses.replace(log, time=log.time[:0]))
    with pytest.raises(LogError, match="does not compile"):
        Replay(dataclasses.replace(log, xml="<mujoco><worldbody><bad/></worldbody></mujoco>"))


def test_render_command_refuses_a_truncated_log(recorded, tmp_path, capsys):
    trunc = _truncated(recorded.path, tmp_path / "trunc.npz", 0.8)
    out = tmp_path / "field.png"
    assert main(["render", str(trunc), "--out", str(out), "--at", "1"]) == 2
    err = capsys.readouterr().err
    assert "corrupt or truncated" in err and len(err.strip().splitlines()) == 1
    assert not out.exists()
    assert main(["render", str(tmp_path / "missing.npz"), "--out", str(out), "--at", "1"]) == 2
    assert "no such match log" in capsys.readouterr().err

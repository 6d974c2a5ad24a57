"""The transform chain camera -> torso -> level -> field against MuJoCo's own poses."""

from __future__ import annotations

import math

import numpy as np
import pytest

from agent.geometry import camera_in_torso, field_to_team, from_polar, to_polar
from agent.perception import observe
from models.geometry import wrap
from models.rules import PlayMode
from models.scene import Lineup
from server.match import Match
from skills.imu import TiltEstimator

from .helpers import place_standing


def test_polar_round_trip():
    rng = np.random.default_rng(0)
    v = rng.normal(size=(50, 3)) * 5
    np.testing.assert_allclose(from_polar(to_polar(v)), v, atol=1e-12)


def test_wrap():
    a = np.array([0.0, math.pi, -math.pi, 3 * math.pi, -7.0, 7.0])
    w = wrap(a)
    assert np.all(w >= -math.pi) and np.all(w < math.pi)
    np.testing.assert_allclose(np.sin(w), np.sin(a), atol=1e-12)
    np.testing.assert_allclose(np.cos(w), np.cos(a), atol=1e-12)


def test_team_frame_by_side():
    p = np.array([-15.0, 10.0, 0.0])  # F1L in the field frame
    np.testing.assert_allclose(field_to_team(p, "L"), p)
    np.testing.assert_allclose(field_to_team(p, "R"), [15.0, -10.0, 0.0])


@pytest.mark.parametrize("yaw,pitch", [(0.0, 0.0), (1.2, 0.3), (-2.0, -0.7), (0.5, 0.78)])
def test_camera_pose_matches_mujoco(yaw, pitch):
    m = Match(lambda *a: None, lambda *a: None, Lineup((0,), (0,)))
    w = m.world
    q = np.zeros(len(w.players[0].joint_qpos))
    q[0], q[1] = yaw, pitch
    w.place_robot(0, 1.0, 2.0, 0.7, joints=q)
    d = w.data
    rt = d.xmat[w.players[0].torso].reshape(3, 3)
    pt = d.xpos[w.players[0].torso]
    rc = d.site_xmat[w.players[0].camera].reshape(3, 3)
    pc = d.site_xpos[w.players[0].camera]
    r, p = camera_in_torso(yaw, pitch)
    np.testing.assert_allclose(r, rt.T @ rc, atol=1e-9)
    np.testing.assert_allclose(p, rt.T @ (pc - pt), atol=1e-9)


@pytest.mark.parametrize("side,heading,yaw,pitch", [("L", 0.3, 0.0, 0.0), ("L", -2.5, 1.0, -0.4),
                                                     ("R", 2.0, -0.8, 0.3)])
def test_known_object_lands_where_it_is(side, heading, yaw, pitch):
    """A ball seen through a panned, tilted head on a standing robot, moved by the
    estimated tilt and the true (x, y, heading) into the field, lands on the ball."""
    from agent.posture import PostureAgent

    m = Match(PostureAgent, PostureAgent, Lineup((0,), (0,)), seed=3)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    i = 0 if side == "L" else 1
    w = m.world
    x, y = 4.0, -3.0
    m.agents[i].target[0:2] = yaw, pitch  # hold the head there
    place_standing(m, i, x, y, heading)
    look = heading + yaw
    w.place_ball((x + 2.0 * math.cos(look), y + 2.0 * math.sin(look)))
    tilt = TiltEstimator()
    for _ in range(60):  # 1.2 s: the head reaches its angles, the tilt estimate settles
        tilt.update(m.percepts()[i].gyro, m.percepts()[i].accel, 0.02)
        m.step()
    while m.cycle % 3:
        m.step()
    pc = m.percepts()[i]
    tilt.update(pc.gyro, pc.accel, 0.02)
    assert pc.vision is not None and pc.vision.ball is not None
    assert abs(pc.joints[0] - yaw) < 0.02 and abs(pc.joints[1] - pitch) < 0.02
    obs = observe(pc.vision, pc.time, pc.joints[0], pc.joints[1], tilt.level)
    # The level frame agrees with the torso's true roll and pitch.
    rt = w.data.xmat[w.players[i].torso].reshape(3, 3)
    th = math.atan2(rt[1, 0], rt[0, 0])
    c, s = math.cos(th), math.sin(th)
    rz = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    np.testing.assert_allclose(tilt.level, rz.T @ rt, atol=0.02)
    # Torso (x, y, heading) and height from the simulator (truth).
    tx, ty, tz = w.data.xpos[w.players[i].torso]
    rel = obs.ball
    est = np.array([tx + c * rel[0] - s * rel[1], ty + s * rel[0] + c * rel[1], tz + rel[2]])
    true = w.ball_position()
    # Noise: calibration +-5 mm per axis, 0.1 % of distance, 0.15 deg; tilt estimate.
    assert np.linalg.norm(est - true) < 0.04
    # The same in the team frame of the robot's side.
    np.testing.assert_allclose(field_to_team(est, side), field_to_team(true, side), atol=0.04)


@pytest.mark.parametrize("n_players", [0, 1, 2, 7, 40])
def test_observe_repeats_the_numpy_chain_bit_for_bit(n_players):
    """observe's compiled conversion gives the floats of camera_in_torso, the level
    rotation and from_polar(...) @ R.T + p in numpy (one-row products included)."""
    from models.messages import Vision

    rng = np.random.default_rng(n_players)
    for k in range(20):
        n_lm, n_ln = (0, 0) if k % 2 else rng.integers(0, 4, 2)
        polar = lambda *s: rng.normal(size=(*s, 3)) * (5.0, 1.0, 0.4) + (6.0, 0.0, 0.0)  # noqa: E731
        ball = polar() if k % 3 else None
        v = Vision(landmark_names=tuple(f"F{i}" for i in range(n_lm)), landmarks=polar(n_lm), ball=ball,
                   lines=polar(n_ln, 2), player_ours=rng.random(n_players) < 0.5,
                   player_unum=rng.integers(1, 12, n_players), player_part=rng.integers(0, 5, n_players),
                   players=polar(n_players))
        yaw, pitch = rng.uniform(-2, 2), rng.uniform(-0.7, 0.7)
        tilt = TiltEstimator()
        tilt.roll, tilt.pitch = rng.normal(0, 0.1, 2).tolist()
        level = tilt.level
        obs = observe(v, 1.0, yaw, pitch, level)
        by_tilt = observe(v, 1.0, yaw, pitch, tilt=(tilt.roll, tilt.pitch))
        for f in ("landmarks", "lines", "players", "camera_rotation", "camera_position"):
            assert np.array_equal(getattr(obs, f), getattr(by_tilt, f))
        r, p = camera_in_torso(yaw, pitch)
        rot, pos = level @ r, level @ p
        parts = [v.landmarks.reshape(-1, 3), v.lines.reshape(-1, 3), v.players.reshape(-1, 3)]
        if ball is not None:
            parts.append(ball.reshape(1, 3))
        allp = from_polar(np.concatenate(parts)) @ rot.T + pos
        assert np.array_equal(obs.camera_rotation, rot) and np.array_equal(obs.camera_position, pos)
        got = [obs.landmarks, obs.lines.reshape(-1, 3), obs.players]
        if ball is not None:
            got.append(obs.ball[None])
        assert np.array_equal(np.concatenate(got), allp)

"""The server favors neither side: in the field turned 180 deg about its center, with
the two teams' robots swapped, every right player sees exactly what its left twin saw
(flags and posts under their turned names), and the physics runs on the same.

Noise and calibration are set to zero here; with them, each observer's draws differ.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from agent.player import Player
from models.scene import Lineup
from server.match import Match
from server.sensors import Proprioception
from server.vision import VisionSensor
from server.world import World
from tests.agent.test_symmetry import TURNED

LINEUP = Lineup.default(5, 5)
QZ = np.array([0.0, 0.0, 0.0, 1.0])  # 180 deg about z (w x y z)


def turn(world: World) -> World:
    """A new world: `world` turned 180 deg about the center spot, left and right robots swapped."""
    t = World(LINEUP)
    a, b = world.data, t.data
    n = len(world.players) // 2
    for i, p in enumerate(world.players):
        q = t.players[(i + n) % len(world.players)]  # the twin: same unum, other side
        pq, qq, pv, qv = p.root_qpos, q.root_qpos, p.root_qvel, q.root_qvel
        b.qpos[qq:qq + 2], b.qpos[qq + 2] = -a.qpos[pq:pq + 2], a.qpos[pq + 2]
        mujoco.mju_mulQuat(b.qpos[qq + 3:qq + 7], QZ, a.qpos[pq + 3:pq + 7])
        b.qvel[qv:qv + 2] = -a.qvel[pv:pv + 2]  # world frame
        b.qvel[qv + 2:qv + 6] = a.qvel[pv + 2:pv + 6]  # z; then the spin, in the body frame
        b.qpos[q.joint_qpos] = a.qpos[p.joint_qpos]
        b.qvel[q.joint_qvel] = a.qvel[p.joint_qvel]
        b.ctrl[q.actuators] = a.ctrl[p.actuators]
        w = a.qacc_warmstart  # the solver's warm start, mapped like qvel
        b.qacc_warmstart[q.root_qvel:q.root_qvel + 2] = -w[p.root_qvel:p.root_qvel + 2]
        b.qacc_warmstart[q.root_qvel + 2:q.root_qvel + 6] = w[p.root_qvel + 2:p.root_qvel + 6]
        b.qacc_warmstart[q.joint_qvel] = w[p.joint_qvel]
    bq, bv = world.ball_qpos, world.ball_qvel
    b.qpos[bq:bq + 2], b.qpos[bq + 2] = -a.qpos[bq:bq + 2], a.qpos[bq + 2]
    b.qvel[bv:bv + 2], b.qvel[bv + 2] = -a.qvel[bv:bv + 2], a.qvel[bv + 2]
    mujoco.mju_mulQuat(b.qpos[bq + 3:bq + 7], QZ, a.qpos[bq + 3:bq + 7])
    b.qvel[bv + 3:bv + 6] = a.qvel[bv + 3:bv + 6]
    b.qacc_warmstart[bv:bv + 2], b.qacc_warmstart[bv + 2:bv + 6] = (
        -a.qacc_warmstart[bv:bv + 2], a.qacc_warmstart[bv + 2:bv + 6])
    mujoco.mj_forward(t.model, b)
    return t


def noiseless(world: World) -> VisionSensor:
    v = VisionSensor(world, np.random.default_rng(0))
    v.sigma[:] = 0.0
    v.calibration[:] = 0.0
    return v


def _key(values) -> tuple:
    return tuple(round(v, 6) for v in values)  # sorting that ignores float round-off


def seen(vision, turned: bool) -> tuple[dict, np.ndarray | None, list, list]:
    names = [TURNED[n] if turned else n for n in vision.landmark_names]
    marks = dict(zip(names, vision.landmarks))
    players = sorted(zip(vision.player_ours.tolist(), vision.player_unum.tolist(),
                         vision.player_part.tolist(), map(tuple, vision.players)))
    ends = [sorted(map(tuple, seg), key=_key) for seg in vision.lines]
    lines = sorted((tuple(e) for e in ends), key=lambda e: _key(e[0] + e[1]))
    return marks, vision.ball, players, lines


@pytest.fixture(scope="module")
def played() -> World:
    """The world of a seeded 5 v 5 villa match after 12 s: robots walking, turning, the ball in play."""
    factory = Player
    m = Match(factory, factory, LINEUP, half_time=300.0, seed=5)
    m.run(max_cycles=600)
    mujoco.mj_forward(m.world.model, m.world.data)
    return m.world


def test_every_right_player_sees_what_its_left_twin_saw(played):
    turned = turn(played)
    a, b = noiseless(played).see_all(), noiseless(turned).see_all()
    n = len(played.players) // 2
    for i in range(len(played.players)):
        ma, ba, pa, la = seen(a[i], False)
        mb, bb, pb, lb = seen(b[(i + n) % (2 * n)], True)
        assert ma.keys() == mb.keys(), i
        for k in ma:
            np.testing.assert_allclose(ma[k], mb[k], atol=1e-9, err_msg=f"{i} {k}")
        assert (ba is None) == (bb is None), i
        if ba is not None:
            np.testing.assert_allclose(ba, bb, atol=1e-9)
        assert [p[:3] for p in pa] == [p[:3] for p in pb], i
        np.testing.assert_allclose(np.array([p[3] for p in pa]).reshape(-1, 3),
                                   np.array([p[3] for p in pb]).reshape(-1, 3), atol=1e-9)
        np.testing.assert_allclose(np.array(la).reshape(-1, 6), np.array(lb).reshape(-1, 6), atol=1e-9)


def test_the_turned_world_steps_and_feels_the_same(played):
    """20 ms of physics from the turned state stays the turned state (to round-off: the
    contact order differs), and every right player's body senses what its twin's did."""
    turned = turn(played)
    n = len(played.players) // 2
    played.step(played.data.ctrl.copy())
    turned.step(turned.data.ctrl.copy())
    body_a, body_b = Proprioception(played).read(), Proprioception(turned).read()
    for i, p in enumerate(played.players):
        q = turned.players[(i + n) % (2 * n)]
        np.testing.assert_allclose(turned.data.qpos[q.joint_qpos], played.data.qpos[p.joint_qpos], atol=1e-12)
        np.testing.assert_allclose(turned.data.qpos[q.root_qpos:q.root_qpos + 2],
                                   -played.data.qpos[p.root_qpos:p.root_qpos + 2], atol=1e-12)
        for a, b, what in zip(body_a[i], body_b[(i + n) % (2 * n)], ("joints", "gyro", "accel", "soles")):
            np.testing.assert_allclose(b, a, atol=1e-7, err_msg=f"{p.name} {what}")

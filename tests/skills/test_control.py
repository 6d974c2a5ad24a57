"""Joint PID: UT gains in SI, speed limits, and tracking in physics."""

import math

import numpy as np
import pytest

from models import nao
from models.rules import CYCLE
from skills.control import UT_KD, UT_KP, JointPid, PidGains


def test_ut_gains_in_si():
    # UT: 0.15 per degree of error -> rad/s per rad; D 0.01 on the per-cycle difference.
    assert UT_KP == pytest.approx(0.15 * 180 / math.pi)
    assert UT_KD == pytest.approx(0.01 * 180 / math.pi * CYCLE)
    pid = JointPid([10.0])
    err_deg = 2.0
    v = pid(np.array([math.radians(err_deg)]), np.zeros(1))[0]
    assert v == pytest.approx(0.15 * err_deg)  # UT's output for a 2 degree error
    # The error shrinks by one degree in a cycle: UT's D adds 0.01 * (-1).
    v = pid(np.array([math.radians(err_deg)]), np.array([math.radians(1.0)]))[0]
    assert v == pytest.approx(0.15 * 1.0 + 0.01 * (-1.0))


def test_commands_respect_each_joints_speed_limit():
    for t in range(5):
        pid = JointPid.for_robot(t)
        limits = np.array([j.max_speed for j in nao.joints(t)])
        n = len(limits)
        v = pid(np.full(n, 3.0), np.full(n, -3.0))
        np.testing.assert_allclose(v, limits)
        pid.reset()
        v = pid(np.full(n, -3.0), np.full(n, 3.0))
        np.testing.assert_allclose(v, -limits)
    lj5 = nao.joint_names(2).index("llj5")
    lj6 = nao.joint_names(2).index("llj6")
    v = JointPid.for_robot(2)(np.full(22, 3.0), np.zeros(22))
    assert v[lj5] == pytest.approx(nao.TYPE2_ANKLE_PITCH_SPEED)
    assert v[lj6] == pytest.approx(nao.TYPE2_ANKLE_ROLL_SPEED)


def test_integral_and_anti_windup():
    pid = JointPid([1.0], PidGains(kp=0.0, ki=10.0, kd=0.0), dt=0.02)
    for _ in range(5):
        v = pid(np.array([0.1]), np.zeros(1))[0]
    assert v == pytest.approx(10.0 * 0.1 * 0.02 * 5)
    pid = JointPid([0.05], PidGains(kp=0.0, ki=10.0, kd=0.0), dt=0.02)
    for _ in range(200):
        v = pid(np.array([1.0]), np.zeros(1))[0]
    assert v == pytest.approx(0.05)
    # Saturated cycles did not grow the integral: one step of opposite error turns it around.
    assert pid(np.array([-1.0]), np.zeros(1))[0] < 0.05


def test_no_derivative_kick_after_reset():
    pid = JointPid([10.0], PidGains(kp=0.0, ki=0.0, kd=1.0))
    assert pid(np.array([1.0]), np.zeros(1))[0] == 0.0
    pid.reset()
    assert pid(np.array([-1.0]), np.zeros(1))[0] == 0.0


def test_tracks_targets_in_physics():
    from models.scene import Lineup
    from server.sensors import Proprioception
    from server.world import World

    world = World(Lineup((0,), (0,)))
    world.place_robot(1, 10.0, 8.0, 0.0)
    world.place_robot(0, -3.0, 3.0, 0.0)
    sense = Proprioception(world)
    act = world.players[0].actuators
    names = nao.joint_names(0)
    target = np.zeros(len(names))
    target[names.index("laj1")] = -1.2
    target[names.index("raj1")] = -1.2
    target[names.index("laj2")] = 0.3
    target[names.index("raj2")] = -0.3
    target[names.index("hj1")] = 0.5
    pid = JointPid.for_robot(0)
    ctrl = np.zeros(world.model.nu)
    for _ in range(50):
        q = sense.read()[0][0]
        ctrl[act] = pid(target, q)
        world.step(ctrl)
    q = sense.read()[0][0]
    for n in ("laj1", "raj1", "laj2", "raj2", "hj1"):
        i = names.index(n)
        assert abs(q[i] - target[i]) < 0.05, n


def test_compiled_command_matches_the_numpy_path_bit_for_bit(monkeypatch):
    """`Motion.command`'s compiled pass (in place into the last target and error) against
    its numpy path: NaN targets held, resets, changed gains, and arrays kept by callers."""
    from types import SimpleNamespace

    from skills import motion as motion_module
    from skills.motion import Motion

    fast, slow = Motion(0), Motion(0)
    rng = np.random.default_rng(3)
    n = len(fast.names)
    kept = []
    for i in range(200):
        if i in (50, 120):
            fast.reset()
            slow.reset()
        if i == 80:
            fast.pid.kp[:] = slow.pid.kp[:] = 30.0
        target = rng.normal(0, 0.5, n)
        target[rng.random(n) < 0.2] = np.nan
        percept = SimpleNamespace(joints=rng.normal(0, 0.5, n))
        v = fast.command(target, percept)
        with monkeypatch.context() as m:
            m.setattr(motion_module.kernels, "joint_command", lambda *args: False)
            want = slow.command(target, percept)
        assert v.tobytes() == want.tobytes(), i
        assert fast.held_target.tobytes() == slow.held_target.tobytes(), i
        kept.append((v, v.copy()))
    assert all(a.tobytes() == b.tobytes() for a, b in kept)  # returned arrays are the caller's

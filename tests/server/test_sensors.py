"""The server's body sensors against MuJoCo's own gyro and touch sensors; the
accelerometer against the torso's velocity change over the cycle."""

import mujoco
import numpy as np

from models.scene import Lineup
from server.sensors import Proprioception
from server.world import World


def test_body_sensors_match_mujocos_sensors():
    """Standing, lying and leaning robots (floor, robot-robot and ball contacts), type 4's
    toes included: the compiled gyro and sole readings equal MuJoCo's sensor stage on the
    same state; the accelerometer reads the torso's mean acceleration over the cycle
    (its velocity change over 20 ms, minus gravity, in the torso frame)."""
    rng = np.random.default_rng(5)
    w = World(Lineup((0, 4, 2), (3, 1)))
    pr = Proprioception(w)
    w.place_robot(1, 0.0, 0.0, 0.4, lying="back")
    w.place_robot(2, 1.0, 1.0, 0.0)
    w.place_robot(3, 1.18, 1.05, 3.0)  # leaning on player 2
    w.place_robot(4, -1.0, 0.5, 1.0, lying="front")
    w.place_ball((-2.0 + 0.08, -1.0))
    w.place_robot(0, -2.0, -1.0, 0.0)
    ctrl = np.zeros(w.model.nu)
    bit = int(mujoco.mjtDisableBit.mjDSBL_SENSOR)
    checked = 0
    for k in range(60):
        ctrl[:] = rng.normal(0.0, 2.0, w.model.nu)
        v0 = [w.data.qvel[p.root_qvel:p.root_qvel + 3].copy() for p in w.players]
        w.step(ctrl)
        if k % 10:
            continue
        w.model.opt.disableflags &= ~bit  # MuJoCo's sensors on, for one forward pass
        mujoco.mj_forward(w.model, w.data)
        w.model.opt.disableflags |= bit
        got = pr.body()
        for i, p in enumerate(w.players):
            want = w.data.sensordata[p.sensors].copy()
            acc = (w.data.qvel[p.root_qvel:p.root_qvel + 3] - v0[i]) / 0.02 - w.model.opt.gravity
            want[3:6] = w.data.xmat[p.torso].reshape(3, 3).T @ acc
            np.testing.assert_allclose(got[i, :len(want)], want, rtol=1e-9, atol=1e-9)
            assert not got[i, len(want):].any()
            checked += want[6:].sum() > 0
    assert checked >= 15  # soles under load were compared, not just zeros

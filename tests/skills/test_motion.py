"""Motion.walk_step's one compiled call against its parts (tilt estimate, walk, command)."""

from types import SimpleNamespace

import numpy as np
import pytest

from skills.motion import Motion
from skills.walk import WALK_SETS


@pytest.mark.parametrize("robot_type", [0, 4])
def test_walk_step_matches_its_parts_bit_for_bit(robot_type):
    fused, parts = Motion(robot_type), Motion(robot_type)
    rng = np.random.default_rng(robot_type)
    n = len(fused.names)
    sets = list(WALK_SETS)
    for i in range(400):
        if i in (100, 250):
            fused.reset()
            parts.reset()
        cmd = (0.0, 0.0, 0.0) if (i // 50) % 4 == 3 else tuple(rng.uniform(-1.2, 1.2, 3))
        percept = SimpleNamespace(joints=rng.normal(0, 0.3, n), gyro=rng.normal(0, 0.5, 3),
                                  accel=np.array([0.0, 0.0, 9.81]) + rng.normal(0, 2.0, 3))
        set_name = sets[(i // 70) % len(sets)]
        kp = 20.0 if 150 <= i < 200 else None
        v = fused.walk_step(percept, *cmd, set_name, kp=kp)
        # The same cycle by parts, as walk_step ran before it was one call.
        pitch, roll = parts.sense(percept)
        out = parts.walk.update(*cmd, set_name, tilt=pitch, roll=roll, gyro=percept.gyro,
                                joints=percept.joints)
        parts.pid.kp[:] = kp if kp is not None else parts.walk.params.joint_kp  # the set in use
        want = parts.command(out.targets.copy(), percept)
        assert v.tobytes() == want.tobytes(), i
        assert fused.last.targets.tobytes() == out.targets.tobytes(), i
        assert fused.last.odometry == out.odometry and fused.last.standing == out.standing, i
        assert (fused.tilt.roll, fused.tilt.pitch) == (roll, pitch), i
        assert fused.held_target.tobytes() == parts.held_target.tobytes(), i
        assert fused.walk.step.tobytes() == parts.walk.step.tobytes(), i

"""The robot model matches the league's Nao (NAO.md) for every type."""

import math

import mujoco
import numpy as np
import pytest

from models import nao, robot

# NAO.md's joint table: name -> (lower, upper) in degrees.
NAO_RANGES = {
    "hj1": (-120, 120), "hj2": (-45, 45),
    "laj1": (-120, 120), "raj1": (-120, 120), "laj2": (-1, 95), "raj2": (-95, 1),
    "laj3": (-120, 120), "raj3": (-120, 120), "laj4": (-90, 1), "raj4": (-1, 90),
    "llj1": (-90, 1), "rlj1": (-90, 1), "llj2": (-25, 45), "rlj2": (-45, 25),
    "llj3": (-25, 100), "rlj3": (-25, 100), "llj4": (-130, 1), "rlj4": (-130, 1),
    "llj5": (-45, 75), "rlj5": (-45, 75), "llj6": (-45, 25), "rlj6": (-25, 45),
    "llj7": (-1, 70), "rlj7": (-1, 70),
}
NAO_MASS = 4.6  # kg, "total about 4.6 kg"


def build(t):
    return mujoco.MjModel.from_xml_string(robot.robot_mjcf(t))


@pytest.mark.parametrize("t", range(5))
def test_joints_names_and_ranges(t):
    m = build(t)
    names = nao.joint_names(t)
    assert len(names) == (24 if t == 4 else 22)
    hinge = [m.joint(i).name for i in range(m.njnt) if m.jnt_type[i] == mujoco.mjtJoint.mjJNT_HINGE]
    assert sorted(hinge) == sorted(names)
    for n in names:
        lo, hi = NAO_RANGES[n]
        assert np.allclose(m.jnt_range[m.joint(n).id], np.radians([lo, hi])), n
        assert m.jnt_limited[m.joint(n).id]


@pytest.mark.parametrize("t", range(5))
def test_total_mass_within_5_percent(t):
    m = build(t)
    total = m.body_subtreemass[m.body("torso").id]
    assert abs(total - NAO_MASS) / NAO_MASS < 0.05


@pytest.mark.parametrize("t", range(5))
def test_motor_speed_limits(t):
    m = build(t)
    for j in nao.joints(t):
        a = m.actuator(j.effector)
        assert m.actuator_trnid[a.id, 0] == m.joint(j.name).id
        expected = nao.MAX_JOINT_SPEED
        if t == 2 and j.name[1:] == "lj5":
            expected = 8.80667
        elif t == 2 and j.name[1:] == "lj6":
            expected = 3.47234
        assert np.allclose(m.actuator_ctrlrange[a.id], [-expected, expected])
        assert np.allclose(m.actuator_forcerange[a.id], [-10, 10])


@pytest.mark.parametrize("t", range(5))
def test_sensors_present(t):
    m = build(t)
    for s in ["gyro", "acc", "lfoot", "rfoot"] + (["ltoe", "rtoe"] if t == 4 else []):
        m.sensor(s)
    m.site("camera")


def test_longer_types_have_longer_legs():
    heights = [nao.standing_height(t) for t in range(5)]
    assert heights[1] > heights[0] and heights[3] > heights[1]
    assert heights[0] == heights[2] == heights[4]


def test_axes_follow_league_signs():
    """Positive hip pitch swings the foot forward; positive left hip roll moves it left."""
    m = build(0)
    d = mujoco.MjData(m)

    def foot(**q):
        d.qpos[:] = m.qpos0
        for k, v in q.items():
            d.qpos[m.jnt_qposadr[m.joint(k).id]] = v
        mujoco.mj_kinematics(m, d)
        return d.xpos[m.body("lfoot").id].copy()

    zero = foot()
    assert foot(llj3=0.5)[0] > zero[0] + 0.05
    assert foot(llj4=-0.5)[0] < zero[0] - 0.03
    assert foot(llj2=0.3)[1] > zero[1] + 0.05
    d.qpos[:] = m.qpos0
    d.qpos[m.jnt_qposadr[m.joint("laj1").id]] = -math.pi / 2
    mujoco.mj_kinematics(m, d)
    assert d.xpos[m.body("llowerarm").id][2] < d.xpos[m.body("lshoulder").id][2] - 0.1


def test_unknown_type_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown robot type 7"):
        nao.joints(7)

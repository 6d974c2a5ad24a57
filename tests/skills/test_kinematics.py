"""Pinocchio kinematics agree with MuJoCo on the same MJCF, for every robot type."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from models import nao
from models.robot import robot_mjcf
from skills.frames import matrix_to_rpy, rpy_to_matrix
from skills.kinematics import RobotKinematics, leg_geometry

TYPES = [0, 1, 2, 3, 4]
TOL = 1e-12


class MujocoRobot:
    """MuJoCo's view of one robot with the torso held at the world origin."""

    def __init__(self, t: int):
        self.model = mujoco.MjModel.from_xml_string(robot_mjcf(t))
        self.data = mujoco.MjData(self.model)
        names = nao.joint_names(t)
        self.adr = np.array([self.model.jnt_qposadr[self.model.joint(n).id] for n in names])

    def set(self, q: np.ndarray) -> None:
        self.data.qpos[:7] = [0, 0, 0, 1, 0, 0, 0]
        self.data.qpos[self.adr] = q
        mujoco.mj_kinematics(self.model, self.data)
        mujoco.mj_comPos(self.model, self.data)

    def body(self, name: str) -> np.ndarray:
        T = np.eye(4)
        b = self.data.body(name)
        T[:3, :3] = b.xmat.reshape(3, 3)
        T[:3, 3] = b.xpos
        return T

    def site(self, name: str) -> np.ndarray:
        T = np.eye(4)
        s = self.data.site(name)
        T[:3, :3] = s.xmat.reshape(3, 3)
        T[:3, 3] = s.xpos
        return T

    def com(self) -> np.ndarray:
        return self.data.subtree_com[self.model.body("torso").id]


@pytest.fixture(scope="module", params=TYPES)
def pair(request):
    t = request.param
    return RobotKinematics(t), MujocoRobot(t)


def test_mass_matches_mujoco(pair):
    kin, mj = pair
    assert kin.mass == pytest.approx(mj.model.body_mass.sum(), abs=1e-9)
    assert kin.mass == pytest.approx(nao.total_mass(kin.robot_type), abs=1e-5)


def test_fk_and_com_match_mujoco(pair):
    kin, mj = pair
    rng = np.random.default_rng(kin.robot_type)
    bodies = [ln.name for ln in nao.links(kin.robot_type)]
    for _ in range(25):
        q = rng.uniform(kin.lower, kin.upper)
        mj.set(q)
        for name in bodies:
            np.testing.assert_allclose(kin.frame_pose(q, name), mj.body(name), atol=TOL, err_msg=name)
        left, right = kin.foot_poses(q)
        np.testing.assert_allclose(left, mj.site("lfoot_sole"), atol=TOL)
        np.testing.assert_allclose(right, mj.site("rfoot_sole"), atol=TOL)
        np.testing.assert_allclose(kin.camera_pose(q), mj.site("camera"), atol=TOL)
        np.testing.assert_allclose(kin.com(q), mj.com(), atol=TOL)
        la, ra = kin.ankle_positions(q)
        np.testing.assert_allclose(la, mj.data.joint("llj6").xanchor, atol=TOL)
        np.testing.assert_allclose(ra, mj.data.joint("rlj6").xanchor, atol=TOL)
        fl, fr, com = kin.feet_and_com(q)
        np.testing.assert_allclose(fl, left, atol=TOL)
        np.testing.assert_allclose(fr, right, atol=TOL)
        np.testing.assert_allclose(com, mj.com(), atol=TOL)


def test_frame_jacobian_matches_finite_differences(pair):
    kin, _ = pair
    rng = np.random.default_rng(10 + kin.robot_type)
    q = rng.uniform(kin.lower, kin.upper)
    J = kin.frame_jacobian(q, "lfoot_sole")
    T0 = kin.frame_pose(q, "lfoot_sole")
    eps = 1e-7
    for i in range(len(q)):
        dq = q.copy()
        dq[i] += eps
        T1 = kin.frame_pose(dq, "lfoot_sole")
        v_local = T0[:3, :3].T @ (T1[:3, 3] - T0[:3, 3]) / eps
        np.testing.assert_allclose(J[:3, i], v_local, atol=1e-6)


@pytest.mark.parametrize("t", TYPES)
def test_zero_pose_matches_the_table(t):
    kin = RobotKinematics(t)
    q = np.zeros(len(kin.joint_names))
    left, right = kin.foot_poses(q)
    for T in (left, right):
        assert T[2, 3] == pytest.approx(-nao.standing_height(t), abs=1e-12)
        np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-15)
    assert left[1, 3] == pytest.approx(nao.robot_type(t).hip1_x)
    assert right[1, 3] == pytest.approx(-nao.robot_type(t).hip1_x)
    np.testing.assert_allclose(kin.camera_pose(q)[:3, 3], [0, 0, 0.155], atol=1e-12)


@pytest.mark.parametrize("t", TYPES)
def test_leg_geometry(t):
    rt = nao.robot_type(t)
    g = leg_geometry(t)
    for leg, sign in ((g.left, 1), (g.right, -1)):
        np.testing.assert_allclose(leg.hip, [-0.01, sign * rt.hip1_x, -0.115], atol=1e-12)
        assert leg.tilt == pytest.approx(sign * np.pi / 4, abs=1e-6)
        # The knee sits 5 mm forward of the hip-ankle line (SimSpark's thigh/shank offsets).
        np.testing.assert_allclose(leg.thigh, [0.005, 0, rt.thigh_z - 0.08], atol=1e-12)
        np.testing.assert_allclose(leg.shank, [0, 0, rt.ankle_z - 0.045], atol=1e-12)
        assert leg.reach_min < leg.reach_max < np.linalg.norm(leg.thigh) + np.linalg.norm(leg.shank)


def test_rpy_round_trip():
    rng = np.random.default_rng(3)
    for _ in range(200):
        rpy = rng.uniform([-np.pi, -np.pi / 2, -np.pi], [np.pi, np.pi / 2, np.pi])
        np.testing.assert_allclose(matrix_to_rpy(rpy_to_matrix(rpy)), rpy, atol=1e-9)


@pytest.mark.parametrize("robot_type", range(5))
def test_compiled_com_is_pinocchio_s_bit_for_bit(robot_type):
    """`RobotKinematics.com` (`skills._kernels.center_of_mass`) against pinocchio's
    centerOfMass, inside the joint limits and far outside them."""
    import pinocchio as pin

    kin = RobotKinematics(robot_type)
    rng = np.random.default_rng(robot_type)
    for trial in range(1000):
        q = rng.uniform(kin.lower, kin.upper) if trial % 2 else rng.uniform(-4.0, 4.0, len(kin.lower))
        want = pin.centerOfMass(kin.model, kin.data, kin.pin_q(q), False)
        assert kin.com(q).tobytes() == want.tobytes(), trial

"""Closed-form leg IK: IK then FK returns the target, unreachable targets are flagged."""

from __future__ import annotations

import numpy as np
import pytest

from skills.frames import matrix_to_rpy, rotation_angle
from skills.ik import LegIK, arm_point_ik, leg_ik, solve_leg
from skills.kinematics import RobotKinematics, leg_geometry
from tests.skills.ik_reference import solve_leg_py

TYPES = [0, 1, 2, 3, 4]
SIDES = ["l", "r"]
POS_TOL = 1e-3  # m, the bound
ROT_TOL = 1e-3  # rad


@pytest.fixture(scope="module", params=TYPES)
def kin(request):
    return RobotKinematics(request.param)


def _sole(kin: RobotKinematics, q: np.ndarray, side: str) -> np.ndarray:
    return kin.foot_poses(q)[0 if side == "l" else 1]


def _with_leg(kin: RobotKinematics, q: np.ndarray, side: str, q6: np.ndarray) -> np.ndarray:
    out = q.copy()
    out[kin.leg_indices(side)] = q6
    return out


def test_ik_then_fk_returns_reachable_targets(kin):
    """Targets from FK of random in-limit angles: IK finds them (and the same angles)."""
    rng = np.random.default_rng(100 + kin.robot_type)
    geom = leg_geometry(kin.robot_type)
    worst_p = worst_r = 0.0
    for _ in range(400):
        q = rng.uniform(kin.lower, kin.upper)
        for side in SIDES:
            T = _sole(kin, q, side)
            q6, ok = leg_ik(geom, side, T[:3, 3], matrix_to_rpy(T[:3, :3]))
            assert ok
            T2 = _sole(kin, _with_leg(kin, q, side, q6), side)
            worst_p = max(worst_p, np.linalg.norm(T2[:3, 3] - T[:3, 3]))
            worst_r = max(worst_r, rotation_angle(T[:3, :3], T2[:3, :3]))
            # Inside the limits the solution is unique.
            np.testing.assert_allclose(q6, q[kin.leg_indices(side)], atol=1e-6)
    assert worst_p < POS_TOL
    assert worst_r < ROT_TOL


def test_ankle_target(kin):
    rng = np.random.default_rng(200 + kin.robot_type)
    ik = LegIK(kin.robot_type)
    for _ in range(100):
        q = rng.uniform(kin.lower, kin.upper)
        la, ra = kin.ankle_positions(q)
        lf, rf = kin.foot_poses(q)
        ql, qr, ok = ik.solve_both(la, matrix_to_rpy(lf[:3, :3]), ra, matrix_to_rpy(rf[:3, :3]),
                                   target="ankle")
        assert ok
        q2 = _with_leg(kin, _with_leg(kin, q, "l", ql), "r", qr)
        la2, ra2 = kin.ankle_positions(q2)
        assert np.linalg.norm(la2 - la) < POS_TOL and np.linalg.norm(ra2 - ra) < POS_TOL


def test_stand_pose(kin):
    """The league's stand pose (hip 0.35, knee -0.7, ankle 0.35) round-trips with a flat foot."""
    ik = LegIK(kin.robot_type)
    q = np.zeros(len(kin.joint_names))
    for side in SIDES:
        q[kin.leg_indices(side)] = [0, 0, 0.35, -0.7, 0.35, 0]
    for side in SIDES:
        T = _sole(kin, q, side)
        np.testing.assert_allclose(T[:3, :3], np.eye(3), atol=1e-12)
        q6, ok = ik.solve(side, T[:3, 3], np.zeros(3))
        assert ok
        np.testing.assert_allclose(q6, [0, 0, 0.35, -0.7, 0.35, 0], atol=1e-9)


@pytest.mark.parametrize("side", SIDES)
def test_unreachable_far_target(kin, side):
    """1 m below the hip: flagged, and the answer is the straight leg pointing at the target."""
    g = leg_geometry(kin.robot_type)
    leg = g.leg(side)
    target = leg.hip + np.array([0.0, 0.0, -1.0])
    q6, ok = leg_ik(g, side, target, np.zeros(3), target="ankle")
    assert not ok
    assert np.all(q6 >= leg.lower) and np.all(q6 <= leg.upper)
    q = _with_leg(kin, np.zeros(len(kin.joint_names)), side, q6)
    ankle = kin.ankle_positions(q)[0 if side == "l" else 1]
    np.testing.assert_allclose(ankle, leg.hip + [0, 0, -leg.reach_max], atol=1e-9)
    # Same for the sole target, far away in another direction.
    q6, ok = leg_ik(g, side, leg.hip + [0.5, 0.2, -0.6], [0.1, 0.2, 0.0])
    assert not ok
    assert np.all(q6 >= leg.lower) and np.all(q6 <= leg.upper)


@pytest.mark.parametrize("side", SIDES)
def test_unreachable_near_target(kin, side):
    g = leg_geometry(kin.robot_type)
    leg = g.leg(side)
    for target in (leg.hip, leg.hip + [0.0, 0.0, -0.05]):
        q6, ok = leg_ik(g, side, target, np.zeros(3), target="ankle")
        assert not ok
        assert np.all(q6 >= leg.lower) and np.all(q6 <= leg.upper)


def test_joint_limits_flagged(kin):
    """Foot turned outward beyond the hip yaw-pitch range is in reach but not in limits."""
    g = leg_geometry(kin.robot_type)
    for side, yaw in (("l", 0.5), ("r", -0.5)):
        leg = g.leg(side)
        q6, ok = leg_ik(g, side, leg.hip + [0, 0, -0.18], [0, 0, yaw], target="ankle")
        assert not ok
        assert np.all(q6 >= leg.lower) and np.all(q6 <= leg.upper)


def test_random_targets_reachable_means_exact(kin):
    """Any pose: the answer is within limits, and when flagged reachable FK gives the target."""
    rng = np.random.default_rng(300 + kin.robot_type)
    g = leg_geometry(kin.robot_type)
    n_ok = n_bad = 0
    for _ in range(600):
        side = SIDES[rng.integers(2)]
        leg = g.leg(side)
        pos = leg.hip + rng.uniform([-0.15, -0.15, -0.35], [0.15, 0.15, 0.0])
        rpy = rng.uniform(-0.6, 0.6, 3)
        q6, ok = leg_ik(g, side, pos, rpy)
        assert np.all(q6 >= leg.lower) and np.all(q6 <= leg.upper)
        T = _sole(kin, _with_leg(kin, np.zeros(len(kin.joint_names)), side, q6), side)
        if ok:
            n_ok += 1
            assert np.linalg.norm(T[:3, 3] - pos) < POS_TOL
            assert matrix_to_rpy(T[:3, :3]) == pytest.approx(rpy, abs=ROT_TOL)
        else:
            n_bad += 1
    assert n_ok > 20 and n_bad > 20  # the sample covers both cases


def test_out_of_limit_angles_are_flagged(kin):
    """Targets made by FK of angles just outside the limits are reported unreachable."""
    rng = np.random.default_rng(400 + kin.robot_type)
    g = leg_geometry(kin.robot_type)
    for side in SIDES:
        leg = g.leg(side)
        idx = kin.leg_indices(side)
        for _ in range(100):
            q = rng.uniform(kin.lower, kin.upper)
            j = rng.integers(6)
            q6 = q[idx]
            q6[j] = leg.upper[j] + 0.05 if rng.random() < 0.5 else leg.lower[j] - 0.05
            T = _sole(kin, _with_leg(kin, q, side, q6), side)
            sol, ok = leg_ik(g, side, T[:3, 3], matrix_to_rpy(T[:3, :3]))
            if j == 3 and q6[j] > 0:
                # A knee over-stretched past straight (the knee sits 5 mm forward, so straight
                # is about +2.4 deg) makes the same pose as a knee bent by as much, which may
                # be in reach; if so the answer must be exact.
                T2 = _sole(kin, _with_leg(kin, q, side, sol), side)
                assert not ok or np.linalg.norm(T2[:3, 3] - T[:3, 3]) < POS_TOL
            else:
                assert not ok


@pytest.mark.parametrize("side", SIDES)
def test_arm_pointing(kin, side):
    rng = np.random.default_rng(500 + kin.robot_type)
    arm = leg_geometry(kin.robot_type).arm(side)
    idx = kin.arm_indices(side)
    for _ in range(100):
        q = np.zeros(len(kin.joint_names))
        q[idx[:2]] = rng.uniform(arm.lower, arm.upper)
        # With the elbow at zero the arm is rigid and turns about the shoulder.
        tip = arm.shoulder + kin.frame_pose(q, f"{side}lowerarm")[:3, :3] @ arm.hand
        # Aim at a point farther along the arm's own line: the arm points there again
        # (near 90 degrees of roll two branches do; either is fine).
        q2, ok = arm_point_ik(arm, arm.shoulder + 3.0 * (tip - arm.shoulder))
        assert ok
        assert np.all(q2 >= arm.lower) and np.all(q2 <= arm.upper)
        q[idx[:2]] = q2
        tip2 = arm.shoulder + kin.frame_pose(q, f"{side}lowerarm")[:3, :3] @ arm.hand
        np.testing.assert_allclose(tip2, tip, atol=1e-9)
    # Beyond the roll range (left arm across the chest, right arm across to the left).
    _, ok = arm_point_ik(arm, arm.shoulder + [0.05, -0.3 if side == "l" else 0.3, 0.0])
    assert not ok


def test_compiled_leg_ik_is_the_python_one_bit_for_bit():
    """skills._kernels.solve_leg follows solve_leg_py line for line (CPython's hypot, Python's
    min/max/%): the same angles and reachability, reachable targets or not."""
    rng = np.random.default_rng(7)
    for t in (0, 4):
        for side in "lr":
            g = leg_geometry(t).leg(side)
            for i in range(300):
                sc = (0.02, 0.1, 0.3)[i % 3]
                pos = np.array([0.0, 0.055 if side == "l" else -0.055, -0.2]) + rng.normal(0, sc, 3)
                rpy = rng.normal(0, (0.05, 0.5, 2.0)[i % 3], 3)
                target = "sole" if i % 2 else "ankle"
                a, ok_a = solve_leg(g, pos, rpy, target)
                b, ok_b = solve_leg_py(g, pos, rpy, target)
                assert ok_a == ok_b and a.tobytes() == b.tobytes()

"""IK kicks: the spline, the foot following it in kinematics, unreachable swings,
the parameter file, and kicks in physics (the kick reads only percepts; the test reads truth)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from optimization.trials import kick_trial
from skills.kicks.ik import (
    KINDS,
    UnreachableKick,
    hermite,
    hermite_tangents,
    ik_kicks,
    load_ik_params,
)
from skills.kinematics import RobotKinematics
from skills.params import ParamError

FOLLOW_TOL = 0.01  # m: the bound on the foot following the spline


@pytest.fixture(scope="module")
def kicks0():
    return ik_kicks(0)


def test_hermite_spline_passes_through_points_with_continuous_velocity():
    rng = np.random.default_rng(1)
    t = np.array([0.0, 0.2, 0.45, 0.7, 1.0])
    p = rng.normal(size=(5, 3))
    m = hermite_tangents(t, p)
    for ti, pi in zip(t, p):
        np.testing.assert_allclose(hermite(t, p, m, float(ti)), pi, atol=1e-12)
    # C1: the derivative from either side of an inner knot agrees (and equals the tangent).
    h = 1e-6
    for k in range(1, 4):
        left = (hermite(t, p, m, t[k]) - hermite(t, p, m, t[k] - h)) / h
        right = (hermite(t, p, m, t[k] + h) - hermite(t, p, m, t[k])) / h
        np.testing.assert_allclose(left, m[k], atol=1e-3)
        np.testing.assert_allclose(right, m[k], atol=1e-3)
    np.testing.assert_allclose(m[0], 0.0)  # the foot starts and ends at rest
    np.testing.assert_allclose(m[-1], 0.0)
    scipy_interp = pytest.importorskip("scipy.interpolate")
    ref = scipy_interp.CubicHermiteSpline(t, p, m)
    for s in np.linspace(0, 1, 37):
        np.testing.assert_allclose(hermite(t, p, m, float(s)), ref(s), atol=1e-12)


def test_every_kick_and_its_mirror_exist(kicks0):
    assert len(kicks0) == 2 * len(KINDS)
    for kind in KINDS:
        left, right = kicks0[f"ik_{kind}_left"], kicks0[f"ik_{kind}_right"]
        assert left.spec.foot == "l" and right.spec.foot == "r"
        assert right.spec.ball == pytest.approx((left.spec.ball[0], -left.spec.ball[1]))
        assert right.spec.direction == pytest.approx(-left.spec.direction)
        assert left.spec.duration > 1.0 and left.spec.distance > 0.0
    assert kicks0["ik_forward_left"].spec.direction == 0.0
    # "in" crosses the body: the left foot's inward kicks go right (negative), outward left;
    # the 45 deg kicks' directions are measured (the ball leaves at 30-55 deg by type).
    for a in (90,):
        assert kicks0[f"ik_{a}_in_left"].spec.direction == pytest.approx(-math.radians(a))
        assert kicks0[f"ik_{a}_out_left"].spec.direction == pytest.approx(math.radians(a))
    assert -math.radians(55) < kicks0["ik_45_in_left"].spec.direction < -math.radians(30)
    assert math.radians(30) < kicks0["ik_45_out_left"].spec.direction < math.radians(55)


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_foot_follows_the_waypoints_in_kinematics(robot_type):
    """FK of the kick's IK joint angles puts the kicking sole on the spline (within 1 cm)
    over the whole swing, with the ball at its nominal spot and moved 5 mm; the spline
    passes through every waypoint placed relative to the ball."""
    kin = RobotKinematics(robot_type)
    kicks = ik_kicks(robot_type)
    for name, k in kicks.items():
        bx, by = k.spec.ball
        for ball in (None, (bx + 0.005, by), (bx - 0.005, by), (bx, by + 0.005), (bx, by - 0.005)):
            k.reset(ball)
            assert k.reachable, (name, ball, k.unreachable[:3])
            b = np.array([*k.ball, 0.0])
            for w in k.params.waypoints:  # the spline's control points sit at the waypoints
                pos, rpy = k.foot_at(w.t)
                np.testing.assert_allclose(pos, b + np.array(w.pos), atol=1e-12)
                np.testing.assert_allclose(rpy, w.rpy, atol=1e-12)
            p = k.params
            worst = 0.0
            for t in np.arange(p.shift_time, p.shift_time + p.swing_time, 0.02):
                feet, torso, phase = k.pose_at(float(t))
                assert phase == "swing"
                q = k.targets_at(float(t))
                q = np.where(np.isnan(q), 0.0, q)
                sole = kin.foot_poses(q)[0 if k.kick_side == "l" else 1]
                want, _ = k.foot_at((t - p.shift_time) / p.swing_time)
                worst = max(worst, float(np.linalg.norm(sole[:3, 3] + torso - want)))
                support = kin.foot_poses(q)[1 if k.kick_side == "l" else 0]
                assert np.linalg.norm(support[:3, 3] + torso - k.spot[k.support]) < 1e-3
            assert worst < FOLLOW_TOL, (name, worst)


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_every_kick_is_reachable_anywhere_in_its_box(robot_type):
    """The approach stops the ball anywhere within the kick's tolerance box (tol_x, tol_y):
    the whole swing must stay reachable with the ball at the box's corners and edges."""
    for name, k in ik_kicks(robot_type).items():
        bx, by = k.spec.ball
        tx, ty = k.spec.tolerance[:2]
        assert tx >= 0.01 and ty >= 0.01, name
        for dx in (-tx, 0.0, tx):
            for dy in (-ty, 0.0, ty):
                bad = k.check((bx + dx, by + dy))
                assert not bad, (name, dx, dy, bad[:3])


def test_unreachable_waypoints_are_reported(kicks0):
    k = kicks0["ik_forward_left"]
    k.reset((0.6, 0.05))  # the ball far out of the leg's reach
    assert not k.reachable
    assert k.unreachable and all(0.0 <= u.s <= 1.0 for u in k.unreachable)
    assert max(u.target[0] for u in k.unreachable) > 0.4
    # The kick still plays a posture within the joint limits.
    kin = RobotKinematics(0)
    p = k.params
    q = k.targets_at(p.shift_time + 0.8 * p.swing_time)
    legs = kin.leg_indices("l")
    assert np.all(q[legs] >= kin.lower[legs] - 1e-9) and np.all(q[legs] <= kin.upper[legs] + 1e-9)
    k.reset()
    assert k.reachable
    strict = ik_kicks(0, strict=True)["ik_forward_right"]
    with pytest.raises(UnreachableKick, match="ik_forward_right.*cannot reach"):
        strict.reset((0.6, -0.05))


def test_malformed_params_name_their_line(tmp_path):
    bad = tmp_path / "bad.params"
    bad.write_text("# tuned\nforward_wp1_x\t-150\nforward_wp2_z\tforty\n", encoding="utf-8")
    with pytest.raises(ParamError, match=r"bad\.params:3:.*forty"):
        load_ik_params([bad])
    bad.write_text("forward_swing_time\t0.7\n\nforward_wp9_x\t10\n", encoding="utf-8")
    with pytest.raises(ParamError, match=r"bad\.params:3:.*unknown parameter"):
        ik_kicks(0, [bad])
    ok = tmp_path / "ok.params"
    ok.write_text("forward_swing_time\t0.7\nforward_wp1_z\t55\n", encoding="utf-8")
    k = ik_kicks(0, [ok])["ik_forward_left"]  # later files override, in SI
    assert k.params.swing_time == pytest.approx(0.7)
    assert k.params.waypoints[0].pos[2] == pytest.approx(0.055)
    ok.write_text("forward_wp7_t\t0.9\n", encoding="utf-8")
    with pytest.raises(ValueError, match="waypoint 7 lacks forward_wp7_x"):
        ik_kicks(0, [ok])


# Physics: the minimum distance (m) per kind (the goal for the forward kick:
# 3 m; the others about 2/3 of what the ball at the nominal spot goes with the
# 0.5-restitution ball, and at least the 1 m of a success) and the direction
# tolerance (deg).
MIN_DISTANCE = {"forward": 3.0, "45_in": 4.5, "45_out": 2.5, "90_in": 1.2, "90_out": 1.2}
PHYSICS = [(f"ik_{kind}_{side}", d, 10.0) for kind, d in MIN_DISTANCE.items() for side in ("left", "right")]


@pytest.mark.parametrize("name,min_distance,tol_deg", PHYSICS)
def test_kick_moves_the_ball_in_physics(kicks0, name, min_distance, tol_deg):
    """The ball at the kick's offset: played from percepts (the kick is told where the ball
    is), the kick sends it at least its minimum distance in its direction, and the robot
    stands. (Physics is deterministic: no seed needed beyond the world's.)"""
    r = kick_trial(0, kicks0[name])
    assert not r["fell"], r
    assert r["distance"] >= min_distance, r
    assert math.degrees(r["error"]) < tol_deg, r


def test_the_45_out_kick_keeps_its_direction_anywhere_in_its_box(kicks0):
    """The 45 deg outward kick meets the ball with the flat outer side of the foot, so the
    ball leaves along the face's normal wherever the face meets it: with the ball at the
    box's four corners and its center, every kick goes within 7 deg of the kick's
    direction, at least 2 m. (The toe-corner swing it replaced sent balls 5 mm apart
    8 deg and -19 deg off.)"""
    kick = kicks0["ik_45_out_left"]
    tx, ty = kick.spec.tolerance[:2]
    for off in ((0.0, 0.0), (-tx, -ty), (-tx, ty), (tx, -ty), (tx, ty)):
        r = kick_trial(0, kick, off)
        assert not r["fell"], (off, r)
        assert math.degrees(r["error"]) < 7.0 and r["distance"] >= 2.0, (off, r)


@pytest.mark.parametrize("robot_type", range(5))
def test_the_backswing_clears_the_ball_before_the_strike(robot_type):
    """Kinematics: pulling back, the kicking leg passes the ball at the kick's offset by at
    least 2 mm (type 4's toe grazed it in its 45 deg inward kick, -3 mm, and rolled the
    ball off the strike's path in most walking kicks); a ball 3 cm nearer is grazed."""
    from optimization.trials import backswing_clearance

    for name, kick in ik_kicks(robot_type).items():
        clear, s = backswing_clearance(kick)
        assert clear >= 0.002, f"type {robot_type} {name}: {1000 * clear:.1f} mm at s={s:.2f}"
    kick = ik_kicks(robot_type)["ik_forward_left"]
    bx, by = kick.spec.ball
    assert backswing_clearance(kick, (bx - 0.03, by))[0] < 0.0  # the check sees a graze


@pytest.mark.parametrize("robot_type", range(5))
def test_the_45_out_backswing_clears_the_ball_anywhere_in_its_box(robot_type):
    """Kinematics: the 45 deg outward kick's lift passes the ball by at least 1 mm wherever
    in its tolerance box the approach leaves it (a lift that touched the ball pushed it
    away before the swing: 3 of 20 of type 3's standing right kicks went 0.5 m with an
    earlier swing); a ball 20 mm nearer than the box's edge is touched."""
    from optimization.trials import backswing_clearance

    kicks = ik_kicks(robot_type)
    for name in ("ik_45_out_left", "ik_45_out_right"):
        kick = kicks[name]
        (bx, by), (tx, ty) = kick.spec.ball, kick.spec.tolerance[:2]
        for dx in (-tx, 0.0, tx):
            for dy in (-ty, 0.0, ty):
                clear, s = backswing_clearance(kick, (bx + dx, by + dy))
                where = f"type {robot_type} {name}, ball off by ({dx}, {dy}) m"
                assert clear >= 0.001, f"{where}: {1000 * clear:.1f} mm at s={s:.2f}"
        assert backswing_clearance(kick, (bx - 0.02 - tx, by))[0] < 0.0  # the check sees a touch

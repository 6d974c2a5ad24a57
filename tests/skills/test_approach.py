"""The ball approach (skills/approach.py) and the percept-only kicker (agent/kicker.py).

Geometry tests need no physics. The physics test drives `agent.kicker.Kicker`
from its percepts alone (vision on, seeded) and reads the truth only to judge:
the robot stops with the ball inside the kick's box, facing the target, without
touching the ball or falling.
"""

import math

import numpy as np
import pytest

from skills.approach import (
    BALL_PENALTY,
    Approach,
    ApproachParams,
    ball_in_path,
    choose_kick,
    decel_speed,
    kick_cost,
    kick_pose,
)
from skills.kicks import KickSpec
from skills.walk import default_param_files, load_walk_sets

LEFT = KickSpec("hold_l", "l", (0.17, 0.05), (0.03, 0.03, math.radians(8)))
RIGHT = KickSpec("hold_r", "r", (0.17, -0.05), (0.03, 0.03, math.radians(8)))
TARGET = (10.0, 0.0)


def test_kick_pose_puts_the_ball_at_the_spec_offset_facing_the_target():
    x, y, h = kick_pose((1.0, 0.0), TARGET, LEFT)
    assert (x, y, h) == pytest.approx((0.83, -0.05, 0.0))
    # Seen from the pose, the ball lies at the spec's offset.
    c, s = math.cos(h), math.sin(h)
    assert (c * (1.0 - x) + s * (0.0 - y), -s * (1.0 - x) + c * (0.0 - y)) == pytest.approx(LEFT.ball)


def test_kick_pose_of_a_directional_kick_turns_by_the_kick_angle():
    spec = KickSpec("side", "r", (0.1, 0.0), (0.03, 0.03, 0.1), direction=math.radians(45))
    x, y, h = kick_pose((0.0, 0.0), (0.0, 5.0), spec)  # the ball must go along +y
    assert h == pytest.approx(math.radians(45))
    assert (x, y) == pytest.approx((-0.1 * math.cos(h), -0.1 * math.sin(h)))


@pytest.mark.parametrize("side, foot", [(-0.6, "hold_l"), (0.6, "hold_r")])
def test_the_foot_on_the_robots_side_costs_less(side, foot):
    # Behind the ball and off to one side: the kick whose pose lies on that side wins.
    robot = (-1.0, side, 0.0)
    assert choose_kick(robot, (0.0, 0.0), TARGET, [LEFT, RIGHT]).name == foot


def test_ball_in_path_costs_the_penalty():
    ball = (0.0, 0.0)
    ahead = (0.8, -0.05, math.pi)  # in front of the ball, on the kick line
    pose = kick_pose(ball, TARGET, LEFT)
    assert ball_in_path(ahead, pose, ball)
    plain = math.hypot(pose[0] - ahead[0], pose[1] - ahead[1]) + abs(math.pi) / (2 * math.pi)
    assert kick_cost(ahead, ball, TARGET, LEFT) == pytest.approx(plain + BALL_PENALTY)
    behind = (-1.0, -0.05, 0.0)
    assert not ball_in_path(behind, pose, ball)
    assert kick_cost(behind, ball, TARGET, LEFT) == pytest.approx(math.hypot(pose[0] + 1.0, 0.0))


def test_choose_kick_keeps_the_current_kick_unless_another_is_clearly_cheaper():
    robot = (-1.0, -0.01, 0.0)  # barely right of the line: the left-foot pose is closer
    assert choose_kick(robot, (0, 0), TARGET, [LEFT, RIGHT]).name == "hold_l"
    assert choose_kick(robot, (0, 0), TARGET, [LEFT, RIGHT], current="hold_r").name == "hold_r"
    far = (-0.5, -1.0, 0.0)
    assert choose_kick(far, (0, 0), TARGET, [LEFT, RIGHT], current="hold_r").name == "hold_l"


def test_decel_speed_is_monotone_signed_and_zero_inside_the_buffer():
    a, buf = 0.15, 0.005
    d = np.linspace(0.0, 1.0, 201)
    v = np.array([decel_speed(x, a, buf) for x in d])
    assert np.all(np.diff(v) >= 0.0)
    assert decel_speed(buf, a, buf) == 0.0 and decel_speed(0.0, a, buf) == 0.0
    assert decel_speed(-0.3, a, buf) == -decel_speed(0.3, a, buf) < 0.0
    assert decel_speed(0.5, a, buf) == pytest.approx(math.sqrt(2 * a * 0.5))  # UT's rule beyond 2 BUFFER


def test_shipped_parameters_load():
    from skills.params import read_entries
    from skills.skill import skill_path

    p = ApproachParams.load()
    file_mm = read_entries([skill_path("approach.params")])["approach_buffer"].value
    assert 0.0 < p.max_decel_x < 1.0 and 0.0 < p.max_decel_y < 1.0
    assert p.buffer == pytest.approx(file_mm / 1000.0) and 0.0 < p.buffer < 0.05  # mm -> m
    assert ApproachParams() == p  # the dataclass's defaults are the shipped file's values


def test_approach_is_ready_only_after_standing_still_in_the_box():
    appr = Approach(load_walk_sets(default_param_files(0)))
    ball = (0.0, 0.0)
    pose = kick_pose(ball, TARGET, LEFT)
    far = appr.step((-1.5, 0.4, 0.0), ball, TARGET, LEFT)
    assert far.mode in ("walk", "around") and not far.ready and far.set_name == "go_to_target"
    appr.reset()
    there = (pose[0] + 0.005, pose[1], pose[2])  # just past the pose (the creep stops at it)
    cmds = [appr.step(there, ball, TARGET, LEFT, standing=True) for _ in range(40)]
    assert cmds[0].mode == "stop" and not cmds[0].ready  # stops first ...
    assert cmds[-1].ready and (cmds[-1].x, cmds[-1].y, cmds[-1].turn) == (0.0, 0.0, 0.0)  # ... then ready
    appr.reset()
    turned = (there[0], there[1], math.radians(20))
    assert not any(appr.step(turned, ball, TARGET, LEFT, standing=True).ready for _ in range(40))


def test_a_small_error_standing_is_handed_to_the_align():
    from skills.align import AlignParams

    sets = load_walk_sets(default_param_files(0))
    ball = (0.0, 0.0)
    gx, gy, gh = kick_pose(ball, TARGET, LEFT)
    short = (gx - 0.02, gy + 0.025, gh + math.radians(9))  # 2 cm short, 2.5 cm left, turned 9 deg
    for align, modes in ((AlignParams(), {"align"}), (None, {"fix", "back", "creep"})):
        appr = Approach(sets, align=align)
        appr.step(short, ball, TARGET, LEFT, standing=True)  # near the pose: the creep stops at once
        cmds = [appr.step(short, ball, TARGET, LEFT, standing=True) for _ in range(40)]
        first = next(c for c in cmds if c.mode != "stop")
        assert first.mode in modes and not any(c.ready for c in cmds)
        if align is not None:  # the error to step off: the pose in the robot frame
            dx, dy, dh = first.error
            c, s = math.cos(short[2]), math.sin(short[2])
            ex, ey = gx - short[0], gy - short[1]
            assert (dx, dy, dh) == pytest.approx((c * ex + s * ey, -s * ex + c * ey, -math.radians(9)))
            appr.aligned()
            assert appr.step(short, ball, TARGET, LEFT, standing=True).mode == "stop"  # judged again


def test_turned_far_off_behind_the_pose_it_turns_before_creeping_in():
    # Behind the pose and near it, but facing 90 deg off the kick's heading: the creep
    # (which turns about 10 deg/s) waits until the robot has turned at the staging point.
    appr = Approach(load_walk_sets(default_param_files(0)))
    ball = (0.0, 0.0)
    gx, gy, gh = kick_pose(ball, TARGET, LEFT)
    behind = (gx - 0.12 * math.cos(gh), gy - 0.12 * math.sin(gh))
    for off, mode in ((90.0, "walk"), (-90.0, "walk"), (20.0, "creep")):
        appr.reset()
        cmd = appr.step((*behind, gh + math.radians(off)), ball, TARGET, LEFT, standing=True)
        assert cmd.mode == mode, off
        assert math.copysign(1.0, cmd.turn) == -math.copysign(1.0, off)  # turns toward the kick heading
    appr.reset()
    turning = appr.step((*behind, gh + math.radians(90.0)), ball, TARGET, LEFT, standing=True)
    creeping = appr.step((*behind, gh + math.radians(20.0)), ball, TARGET, LEFT, standing=True)
    assert abs(turning.turn) > abs(creeping.turn)


def test_going_round_the_ball_turns_by_the_around_gain():
    """In front of the ball (the kick pose is behind it), turned off the ball: going
    round, the turn input scales with `around_turn_gain`; walking straight to the
    staging point it does not."""
    from dataclasses import replace

    sets = load_walk_sets(default_param_files(0))
    ball = (0.0, 0.0)
    gx, gy, gh = kick_pose(ball, TARGET, LEFT)
    front = (0.5 * math.cos(gh) - 0.05 * math.sin(gh), 0.5 * math.sin(gh) + 0.05 * math.cos(gh))
    robot = (*front, gh + math.radians(60.0))
    turns = {}
    for gain in (1.0, 3.0):
        appr = Approach(sets, replace(ApproachParams(), around_turn_gain=gain))
        cmd = appr.step(robot, ball, TARGET, LEFT, standing=True)
        assert cmd.mode == "around"
        turns[gain] = cmd.turn
    assert turns[1.0] != 0.0
    assert turns[3.0] == pytest.approx(max(-1.0, min(1.0, 3.0 * turns[1.0])))
    behind = (gx - 0.5 * math.cos(gh), gy - 0.5 * math.sin(gh), gh + math.radians(30.0))
    walks = [Approach(sets, replace(ApproachParams(), around_turn_gain=g)).step(behind, ball, TARGET, LEFT)
             for g in (1.0, 3.0)]
    assert walks[0].mode == "walk" and walks[0].turn == walks[1].turn


def test_going_round_the_ball_it_steps_round_facing_the_ball():
    """In front of the ball, facing it: going round, it keeps facing the ball and steps
    sideways along the circle (UT's circling); facing away, it turns back to the ball."""
    sets = load_walk_sets(default_param_files(0))
    ball = (0.0, 0.0)
    gx, gy, gh = kick_pose(ball, TARGET, LEFT)
    ux, uy = math.cos(gh), math.sin(gh)  # the kick heading; the robot stands beyond the ball
    front = (0.45 * ux - 0.1 * uy, 0.45 * uy + 0.1 * ux)
    to_ball = math.atan2(-front[1], -front[0])
    facing = Approach(sets).step((*front, to_ball), ball, TARGET, LEFT)
    assert facing.mode == "around"
    assert abs(facing.turn) < 0.05 and abs(facing.y) > 1.5 * abs(facing.x) and abs(facing.y) > 0.3
    assert facing.y < 0.0  # left of the kick line, facing back: the way round is to its right
    away = Approach(sets).step((*front, to_ball + math.radians(90.0)), ball, TARGET, LEFT)
    assert away.mode == "around" and away.turn < -0.3  # turns back toward the ball


def test_going_round_the_ball_never_cuts_through_it():
    appr = Approach(load_walk_sets(default_param_files(0)))
    g = (-0.17, 0.05)  # the pose in the kick frame (LEFT)
    for angle in np.radians(np.arange(-170, 180, 20)):
        for dist in (0.45, 1.0, 2.0):
            r = (dist * math.cos(angle), dist * math.sin(angle))
            behind = r[0] < g[0] and abs(r[1] - g[1]) < 0.1
            wu, wv, mode = appr.waypoint(r, g, behind)
            if mode == "around":
                assert math.hypot(wu, wv) >= appr.params.around - 1e-9
            assert not ball_in_path(r, (wu, wv), (0.0, 0.0), clearance=0.12), (angle, dist, mode)


@pytest.mark.parametrize("start", [(0.45, 0.1), (0.3, -0.6), (0.1, 0.39), (1.5, 0.2)])
def test_going_round_the_ball_keeps_clear_of_it(start):
    """A point stepping 1 cm a cycle straight at each waypoint goes round the ball and
    leaves the circle behind it, never nearer than 0.2 m to it (its toes reach 0.1 m
    ahead of the torso). Aimed 50 deg further round on the circle, the path cuts
    inside it: about two thirds of `around` at its nearest."""
    appr = Approach(load_walk_sets(default_param_files(0)), ApproachParams.load())
    g = (-0.17, 0.05)  # the pose in the kick frame (LEFT)
    r = np.array(start, dtype=float)
    dists = []
    for _ in range(2000):
        behind = r[0] < g[0] and abs(r[1] - g[1]) < 0.1
        wu, wv, mode = appr.waypoint(tuple(r), g, behind)
        if mode != "around":
            break
        d = np.array([wu, wv]) - r
        r += 0.01 * d / np.linalg.norm(d)
        dists.append(float(np.hypot(*r)))
    assert mode == "walk" and r[0] < 0.0  # left the circle behind the ball
    assert dists and min(dists) > 0.2, min(dists)


# ------------------------------------------------------------------ physics


class Hold:
    """A kick that does nothing: the test only judges where the approach stopped."""

    def __init__(self, spec):
        self.spec = spec
        self.n = 0

    def reset(self, ball=None, start=None):
        self.n = 0

    def step(self, percept):
        self.n += 1
        return np.full(len(percept.joints), np.nan)

    @property
    def done(self):
        return self.n > 5


def approach(robot_type, start, seconds=20.0, seed=0):
    """Run the kicker from `start` (x, y, heading; field frame) to a ball at the origin,
    kicking toward +x; returns (ready time or None, true ball in the robot frame,
    true heading, how far the ball moved, fell)."""
    from agent.kicker import KICK, Kicker
    from models.messages import Action
    from models.scene import Lineup
    from optimization.phases import WalkAgent
    from server.trainer import Trainer

    tr = Trainer(Lineup((robot_type,), ()), seed=seed)
    w = tr.world
    w.place_ball(np.array([0.0, 0.0]))
    kicker = Kicker(robot_type, {"hold_l": Hold(LEFT), "hold_r": Hold(RIGHT)})
    w.place_robot(0, *start, joints=WalkAgent(robot_type, kicker.motion.walk.sets).stand_pose())
    w.settle_height(0)
    kicker.start(start, TARGET)
    ready, fell = None, False
    while w.time < seconds:
        v = kicker.act(tr.percepts()[0])
        tr.step({0: Action(v)})
        fell = fell or w.torso_up()[0] < 0.5
        if kicker.state == KICK:
            ready = w.time
            break
    x, y, h = w.player_pose(0)
    b = w.ball_position()
    c, s = math.cos(h), math.sin(h)
    rel = (c * (b[0] - x) + s * (b[1] - y), -s * (b[0] - x) + c * (b[1] - y))
    return ready, rel, h, float(np.linalg.norm(b[:2])), fell, kicker.kick.spec


def test_approach_stops_in_the_box_without_touching_the_ball():
    # From 1.2-1.5 m behind the ball, 30-60 deg to either side, facing it: percepts
    # only (vision every third cycle, noisy), truth only to judge. The walk is
    # chaotic at this scale (a stop turns the robot by about 5 deg at random) and the
    # approach still falls about one time in four (issue 4's open shortfall), so the
    # test asks three of five seeded approaches to succeed. Box: the kick's tolerance
    # plus 1.5 cm and 3 deg (what the robot sees while standing is off by about that much).
    ok = falls = 0
    for dist, angle in ((1.4, 150), (1.3, 140), (1.3, -140), (1.5, 120), (1.2, -150)):
        a = math.radians(angle)
        start = (dist * math.cos(a), dist * math.sin(a), a + math.pi)
        ready, rel, heading, moved, fell, spec = approach(0, start)
        falls += fell
        tx, ty, th = spec.tolerance
        ok += (ready is not None and not fell and moved < 0.02
               and abs(rel[0] - spec.ball[0]) < tx + 0.015
               and abs(rel[1] - spec.ball[1]) < ty + 0.015 and abs(heading) < th + math.radians(3))
    assert ok >= 3, (ok, falls)


def test_after_an_align_the_box_is_wider_and_a_reset_narrows_it_again():
    from skills.align import AlignParams

    appr = Approach(load_walk_sets(default_param_files(0)), align=AlignParams())
    ball = (0.0, 0.0)
    gx, gy, gh = kick_pose(ball, TARGET, LEFT)
    wide = appr.params.after_align
    assert wide > 1.0
    off = (gx, gy + 0.03 * (1.0 + wide) / 2.0, gh)  # outside the kick's box, inside the wider one

    def ready_within(steps: int) -> bool:
        return any(appr.step(off, ball, TARGET, LEFT, standing=True).ready for _ in range(steps))

    assert not ready_within(40)  # handed to the align instead
    appr.aligned()
    assert ready_within(40)
    appr.reset()  # a fall, a lost ball or another kick: the kick's own box again
    assert not ready_within(40)

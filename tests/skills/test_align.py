"""Quasi-static stance moves (skills/align.py).

The plan is checked in kinematics (where the feet and torso end, which foot
leads, that every sample is reachable); physics checks that the robot really
moves by the requested amount without falling, from the walk's stand.
"""

import math

import numpy as np
import pytest

from skills.align import Align, AlignParams

MOVES = [(0.04, 0.02, math.radians(12)), (-0.03, -0.04, math.radians(-15)), (0.0, 0.05, 0.0),
         (0.05, -0.01, math.radians(-5)), (-0.05, 0.0, math.radians(18))]


@pytest.fixture(scope="module")
def align():
    return Align(0)


def test_shipped_parameters_load():
    assert AlignParams.load() == AlignParams()  # the dataclass's defaults are the file's values


@pytest.mark.parametrize("move", MOVES)
def test_the_plan_ends_on_the_moved_stand_spots(align, move):
    align.reset(move)
    feet, torso, yaw = align.pose_at(align.params.duration)
    assert (*torso, yaw) == pytest.approx(move)
    c, s = math.cos(move[2]), math.sin(move[2])
    for side, (xy, z, foot_yaw) in feet.items():
        sx, sy = align.spot[side]
        assert xy == pytest.approx((move[0] + c * sx - s * sy, move[1] + s * sx + c * sy))
        assert z == 0.0 and foot_yaw == pytest.approx(move[2])


@pytest.mark.parametrize("move", MOVES)
def test_the_support_foot_stays_put_and_every_sample_is_reachable(align, move):
    align.reset(move)
    first, second = align.order
    step = align.params.step_time
    for t in np.arange(0.0, align.params.duration, 0.02):
        feet, torso, yaw = align.pose_at(float(t))
        support = second if t < step else first
        if align.params.shift_time <= t % step < step - align.params.unshift_time:
            xy, z, _ = feet[support]
            assert z == 0.0
        for side, (xy, z, foot_yaw) in feet.items():
            c, s = math.cos(-yaw), math.sin(-yaw)
            rel = xy - torso
            target = np.array([c * rel[0] - s * rel[1], s * rel[0] + c * rel[1], z - align.height])
            _, ok = align.ik.solve(side, target, np.array([0.0, 0.0, foot_yaw - yaw]))
            assert ok, (move, round(float(t), 2), side)


@pytest.mark.parametrize("turn, first", [(math.radians(10), "r"), (math.radians(-10), "l")])
def test_turning_the_foot_that_turns_inward_leads(align, turn, first):
    # A Nao's sole turns only inward from its hip: turning left, the right foot turns first.
    align.reset((0.0, 0.0, turn))
    assert align.order[0] == first


@pytest.mark.parametrize("dy, first", [(0.03, "l"), (-0.03, "r")])
def test_stepping_sideways_the_stance_widens_first(align, dy, first):
    align.reset((0.0, dy, 0.0))
    assert align.order[0] == first


def test_fits_only_small_moves(align):
    p = align.params
    assert align.fits((p.max_move, -p.max_move, p.max_turn))
    assert not align.fits((p.max_move + 0.01, 0.0, 0.0))
    assert not align.fits((0.0, 0.0, -p.max_turn - 0.01))


# ------------------------------------------------------------------ physics


@pytest.mark.parametrize("robot_type", [0, 4])
def test_the_robot_moves_by_the_request_without_falling(robot_type):
    from models.messages import Action
    from optimization.robot import new_robot

    align = Align(robot_type)
    for move in MOVES[:3]:
        tr, mo = new_robot(robot_type)
        w = tr.world
        for _ in range(25):  # stand 0.5 s
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        x0, y0, h0 = w.player_pose(0)
        mo.walk.reset()
        align.reset(move)
        while not align.done:
            pc = tr.percepts()[0]
            tr.step({0: Action(mo.command(align.step(pc), pc))})
            assert w.torso_up()[0] > 0.8, (move, align.t)
        for _ in range(25):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        x1, y1, h1 = w.player_pose(0)
        c, s = math.cos(h0), math.sin(h0)
        dx, dy = c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0)
        assert (dx, dy) == pytest.approx(move[:2], abs=0.012), move
        assert math.remainder(h1 - h0, 2 * math.pi) == pytest.approx(move[2], abs=math.radians(3)), move


def test_after_a_walk_the_rocking_stand_rarely_falls_aligning():
    # Started 0.5-0.8 s after a walk stops, as in the ball approach, when the stand rocks
    # at about 6.5 Hz. Type 3 fell worst: the IK kicks' 0.6 s shift and 15 mm lift fell
    # 9 times in these 64 moves (18% over 300 others), the shipped values 4.
    from optimization.trials import align_errors

    row = align_errors(3, tries=64, move=0.05, turn=18.0, seed=5, start="walk")
    assert row["falls"] <= 5, row
    assert max(row["error_mean_mm_mm_deg"][:2]) < 6.0, row

"""The walk in physics: the robot's control reads only its percepts; the test reads truth."""

import math

import numpy as np
import pytest

from models.geometry import wrap
from models.messages import Action
from optimization.robot import new_robot
from skills.navigate import Odometry, walk_toward


def walk(t, seconds, command, stand=0.5, rng=None, set_name="go_to_target"):
    """Stand `stand` s, then walk with `set_name` (the stand is the go-to-target set's);
    returns the trainer, the robot's odometry and whether it fell. With `rng`, the start
    joints are perturbed (`optimization.robot.new_robot`)."""
    tr, mo = new_robot(t, rng)
    odo = Odometry()
    fell = False
    first = round(stand / 0.02)
    for k in range(first + round(seconds / 0.02)):
        pc = tr.percepts()[0]
        cmd = (0.0, 0.0, 0.0) if k < first else command(odo, mo)
        v = mo.walk_step(pc, *cmd, "go_to_target" if k < first else set_name)
        odo.update(*mo.last.odometry)
        tr.step({0: Action(v)})
        if tr.world.torso_up()[0] < 0.5:
            fell = True
            break
    return tr, odo, fell


@pytest.mark.parametrize("t", [0, 4])
def test_walks_3_m_forward_without_falling(t):
    # Head for a point 4 m ahead by the robot's own odometry (which drifts), and
    # measure in truth: at least 3 m along the start heading, upright all the way.
    target = (4.0, 0.0)

    def command(odo, mo):
        dx, dy = odo.relative(*target)
        return walk_toward(dx, dy, None, mo.walk.params) if math.hypot(dx, dy) > 0.1 else (0, 0, 0)

    tr, _, fell = walk(t, 30.0, command)
    x, y, _ = tr.world.player_pose(0)
    assert not fell
    assert x >= 3.0, (x, y)


def test_turns_90_degrees_in_place():
    # Turning on the spot and stopping falls now and then, and stops off by 20 deg or more
    # now and then; which runs do is chaotic. Over 40 starts (0.5-1.45 s, both directions)
    # the hand-tuned walk fell once and missed 7 times, type 0's learned walk
    # (walk_type0.txt) fell twice and missed 4 times. Six runs: at most one may fall and
    # at most one miss; every other run ends facing its goal within 20 deg, in place.
    falls, bad = 0, []
    for stand in (0.5, 0.6, 0.7):
        for goal in (math.pi / 2, -math.pi / 2):
            done = []

            def command(odo, mo, goal=goal, done=done):  # turn until odometry says goal, then stand
                err = wrap(goal - odo.heading)
                if done or abs(err) < 0.05:
                    done.append(True)
                    return (0.0, 0.0, 0.0)
                # Proportional, gentle enough that the walk's turn lag (a latched step) does not overshoot.
                return (0.0, 0.0, float(np.clip(1.5 * err / math.pi, -1, 1)))

            tr, odo, fell = walk(0, 8.0, command, stand)
            x, y, h = tr.world.player_pose(0)
            falls += fell
            if not fell and (abs(math.degrees(wrap(h - goal))) >= 20.0 or math.hypot(x, y) >= 0.3):
                bad.append((stand, math.degrees(goal), math.degrees(h), x, y))
    assert falls <= 1
    assert len(bad) <= 1, bad  # truth within 20 deg of odometry's goal, within 0.3 m of the start


@pytest.mark.parametrize("walk_first", [False, True])
def test_a_standing_robot_stays_still(walk_first):
    # The ankles' gyro damping, one cycle late, fed the stance's own 7 Hz sway: standing,
    # the body rate grew to 17-25 deg/s within a second. It now fades out once the robot
    # has stood a second; from then on the stand must stay calm (about 11 deg/s).
    tr, mo = new_robot(0)
    rates = []
    for k in range(round(5.0 / 0.02)):
        pc = tr.percepts()[0]
        walking = walk_first and k < round(2.0 / 0.02)  # walk 2 s, then stand
        tr.step({0: Action(mo.walk_step(pc, 0.6 if walking else 0.0, 0.0, 0.0))})
        rates.append(np.linalg.norm(pc.gyro))
        assert tr.world.torso_up()[0] > 0.5
    calm = np.degrees(np.mean(rates[-50:]))  # the last second, two seconds after any stop
    assert calm < 15.0, calm


@pytest.mark.parametrize("t", range(5))
def test_the_sprint_set_walks_forward_at_0_3_m_s(t):
    # Issue 3's forward goal, walked with the set made for it (each type's sprint set,
    # walk_type<T>.txt): stand 0.5 s with the go-to-target set, then 10 s straight ahead
    # from a perturbed start. Over 48 starts each set falls 2-4 times, so of three starts
    # one may fail; the other two must cover 3 m in the 10 s (truth, along the start
    # heading) without falling. The shared sprint values walk types 2 and 4 at 0.24-0.26 m/s.
    good = []
    for seed in (500, 501, 502):
        tr, _, fell = walk(t, 10.0, lambda odo, mo: (1.0, 0.0, 0.0), rng=np.random.default_rng(seed),
                           set_name="sprint")
        good.append(not fell and tr.world.player_pose(0)[0] >= 3.0)  # from the start spot, x = 0
    assert sum(good) >= 2, good


@pytest.mark.parametrize("t", range(5))
def test_from_straight_legs_into_the_stand(t):
    # As a match begins: beamed with straight legs (every joint 0), the robot blends into the
    # walk's stand (Motion.enter_stand) and stands 3 s. Sent straight to the stand instead,
    # each joint at its top speed, type 2 rocked back onto its heels and fell within 2.5 s.
    tr, mo = new_robot(t)
    tr.world.place_robot(0, 0.0, 0.0, 0.0, joints=np.zeros(len(mo.names)))
    tr.world.settle_height(0)
    mo.reset()
    lowest = 1.0
    for k in range(round(3.0 / 0.02)):
        pc = tr.percepts()[0]
        v = mo.enter_stand(pc) if k < round(0.5 / 0.02) else mo.walk_step(pc, 0.0, 0.0, 0.0)
        tr.step({0: Action(v)})
        lowest = min(lowest, float(tr.world.torso_up()[0]))
    assert lowest > 0.98, lowest  # within 11 deg of upright throughout
    stand = mo.walk.update(0.0, 0.0, 0.0).targets
    legs = ~np.isnan(stand)
    assert np.abs(tr.world.joint_angles(0)[legs] - stand[legs]).max() < 0.05  # in the stand

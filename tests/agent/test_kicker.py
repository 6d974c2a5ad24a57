"""The striker (no physics): landmark fixes pull the pose, misfits are ignored; kicks play at
their own joint gains."""

import math

import numpy as np
import pytest

from agent.geometry import landmarks_in_team
from agent.kicker import KICK, LANDMARK_GAIN, SKILL_GAINS, Kicker
from agent.perception import Observation
from models.messages import Percept
from skills.kicks import KickSpec
from skills.walk import DATA, load_walk_sets


class Hold:
    """A stand-in kick: the Kicker only needs its spec here."""

    spec = KickSpec(name="hold", foot="l", ball=(0.18, 0.05), tolerance=(0.03, 0.03, 0.2),
                    direction=0.0, distance=1.0)


def seen_from(pose, names, side="left", ball=None):
    """The landmarks `names` (and a ball at `ball`, robot frame) as a robot at `pose`
    (x, y, heading; team frame) sees them."""
    marks = landmarks_in_team(side)
    x, y, h = pose
    c, s = math.cos(h), math.sin(h)
    rel = []
    for n in names:
        dx, dy = marks[n][0] - x, marks[n][1] - y
        rel.append((c * dx + s * dy, -s * dx + c * dy, 0.0))
    return Observation(time=1.0, landmark_names=tuple(names), landmarks=np.array(rel),
                       ball=None if ball is None else np.array([*ball, 0.0]),
                       lines=np.zeros((0, 2, 3)), player_ours=np.zeros(0, bool),
                       player_unum=np.zeros(0, int), player_part=np.zeros(0, int),
                       players=np.zeros((0, 3)), camera_rotation=np.eye(3), camera_position=np.zeros(3))


@pytest.mark.parametrize("offset, moves", [((0.5, 0.0), True), ((0.0, -0.8), True), ((3.0, 2.0), False),
                                           ((-9.8, 2.2), False)])
def test_a_landmark_fix_pulls_the_pose_unless_it_is_far_off(offset, moves):
    kicker = Kicker(0, {"hold": Hold()})
    kicker.start((-5.0, 1.0, 0.3), (5.0, 0.0))
    truth = (-5.0 + offset[0], 1.0 + offset[1], 0.3)  # what the flags say
    kicker.landmark_fix(seen_from(truth, ["F1R", "F2R", "G1R"]), "left")
    x, y, h = kicker.pose
    if moves:
        assert (x, y) == pytest.approx((-5.0 + LANDMARK_GAIN * offset[0], 1.0 + LANDMARK_GAIN * offset[1]))
    else:  # a misfit (misread flags while the torso tilts) must not drag the pose 2 m a frame
        assert (x, y, h) == (-5.0, 1.0, 0.3)


class StubKick:
    """A kick that holds the stand pose for `cycles` cycles."""

    spec = Hold.spec

    def __init__(self, targets: np.ndarray, cycles: int = 3) -> None:
        self.targets, self.left, self.done = targets, cycles, False

    def reset(self, ball=None, start=None) -> None:
        pass

    def step(self, percept) -> np.ndarray:
        self.left -= 1
        self.done = self.left <= 0
        return self.targets


def test_kicks_play_at_the_gains_they_were_tuned_at_whatever_the_walk_uses():
    assert SKILL_GAINS[0] == load_walk_sets([DATA / "walk_defaults.txt"])["go_to_target"].joint_kp
    kick = StubKick(None)
    kicker = Kicker(3, {"hold": kick})
    walk_kp = kicker.motion.walk.sets["go_to_target"].joint_kp
    assert walk_kp != SKILL_GAINS[0]  # type 3 walks softer
    kicker.start((0.0, 0.0, 0.0), (5.0, 0.0))
    q = np.nan_to_num(kicker.motion.walk.update(0.0, 0.0, 0.0).targets)
    kick.targets = q

    def percept(t: float) -> Percept:
        return Percept(t, t, "PlayOn", 0, 0, "L", 1, 3, q.copy(), np.zeros(3), np.array([0.0, 0.0, 9.81]),
                       np.array([20.0, 20.0]))

    kicker.act(percept(0.0))
    assert np.all(kicker.motion.pid.kp == walk_kp)  # approaching: the walk's gain
    kicker.ball.see(seen_from((0.0, 0.0, 0.0), [], ball=Hold.spec.ball), kicker.odo)
    assert kicker.kick_now(percept(0.02)) and kicker.state == KICK
    kicker.act(percept(0.02))
    assert np.all(kicker.motion.pid.kp == SKILL_GAINS[0])  # kicking: the kicks' own
    kicker.start((0.0, 0.0, 0.0), (5.0, 0.0))  # approaching again
    kicker.act(percept(0.04))
    assert np.all(kicker.motion.pid.kp == walk_kp)

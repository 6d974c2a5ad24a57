"""The posture agent: stands still in a stable pose, beamed to a home position.

A real agent: it reads only its percepts (joint angles, play mode) and answers
with joint velocities and, before kickoff and after goals, a beam. It lets the
match loop run 22 robots upright for a whole match before the real team exists,
and is the baseline opponent for regression runs.
"""

from __future__ import annotations

import numpy as np

from models import nao
from models.messages import Action, Percept
from models.rules import PlayMode

# Stand pose (rad) by joint perceptor name without its side letter; others 0.
STAND_POSE = {"lj3": 0.35, "lj4": -0.7, "lj5": 0.35, "aj1": -1.5, "aj4": 0.0}
ARM_ROLL = 0.15  # rad, arms slightly away from the body (sign per side)
GAIN = 15.0  # 1/s: commanded velocity per rad of angle error

# Home positions (team frame: own goal at -x; m) by uniform number.
HOME = {
    1: (-14.5, 0.0), 2: (-10.0, 3.0), 3: (-10.0, -3.0), 4: (-7.0, 6.0), 5: (-7.0, -6.0),
    6: (-6.0, 0.0), 7: (-3.5, 3.0), 8: (-3.5, -3.0), 9: (-2.0, 7.0), 10: (-2.0, -7.0),
    11: (-0.8, 0.0),
}
BEAM_MODES = (PlayMode.BEFORE_KICK_OFF, PlayMode.GOAL_LEFT, PlayMode.GOAL_RIGHT)


def stand_pose(robot_type: int) -> np.ndarray:
    """Target joint angles (rad, league order) of the stand pose for a robot type."""
    out = []
    for name in nao.joint_names(robot_type):
        v = STAND_POSE.get(name[1:], 0.0)
        if name[1:] == "aj2":
            v = ARM_ROLL if name[0] == "l" else -ARM_ROLL
        out.append(v)
    return np.array(out)


class PostureAgent:
    """Holds the stand pose with a proportional joint controller."""

    def __init__(self, side: str, unum: int, robot_type: int, seed: int = 0) -> None:
        self.unum = unum
        self.target = stand_pose(robot_type)
        self.max_speed = np.array([j.max_speed for j in nao.joints(robot_type)])
        self._beamed_for: tuple[PlayMode, float] | None = None
        self._mode: PlayMode | None = None
        self._mode_since = 0.0

    def act(self, percept: Percept) -> Action:
        mode = PlayMode(percept.play_mode)
        if mode != self._mode:
            self._mode, self._mode_since = mode, percept.time
        vel = np.clip(GAIN * (self.target - percept.joints), -self.max_speed, self.max_speed)
        beam = None
        if mode in BEAM_MODES and self._beamed_for != (self._mode, self._mode_since):
            x, y = HOME.get(self.unum, (-1.0, 0.0))
            beam = (x, y, 0.0)
            self._beamed_for = (self._mode, self._mode_since)
        return Action(joint_velocities=vel, beam=beam)

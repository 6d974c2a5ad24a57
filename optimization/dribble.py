"""Position-to-dribble (Appendix A.1.5, UT's driveBallToGoal2): drive the ball toward
the opponent's goal for 15 s from varied starts.

The robot's control reads only its percepts: the ball comes from vision
(every third cycle, `agent.perception.observe` into the torso's level frame)
and is kept in the dead-reckoning frame between sightings; the robot is told
its true pose once, at the start (as after a beam), and walks on its own
odometry after that. It circles to a point behind the ball facing the goal,
then walks through the ball. Within `near` (0.8 m) of the ball it uses the
"position_to_dribble" walk set; farther away "sprint" when the target is
within 15 degrees, "go_to_target" otherwise (both frozen in this layer).

Fitness (ground truth): the ball's progress toward the goal, summed over the
phases (15 s in three 5 s phases, so that a fall, which ends its phase with
the fall penalty, costs only the rest of that phase), minus 5 per fall.

Frames: the field frame (x toward the opponent's goal); m, rad.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from agent.perception import observe
from models import field as fieldmodel
from models.geometry import wrap
from models.messages import Percept
from optimization.phases import Sim, WalkAgent
from skills.navigate import walk_toward

GOAL = (fieldmodel.HALF_LENGTH, 0.0)  # m, field frame: the opponent's goal center
HEAD_PITCH = -0.6  # rad: the camera looks down enough to see the ball at the feet
BEHIND = 0.22  # m behind the ball (toward our side) where the robot lines up
ALIGNED = 0.12  # m of lateral offset and ...
ALIGNED_ANGLE = math.radians(30.0)  # ... heading error under which the robot walks through
LOST = 4.0  # s without seeing the ball before the robot turns to look for it


@dataclass
class BallTracker:
    """The last seen ball in the dead-reckoning frame (m) and when (s, server time)."""

    ball: tuple[float, float] | None = None
    seen_at: float = -math.inf

    def update(self, percept: Percept, agent: WalkAgent) -> None:
        v = percept.vision
        if v is None or v.ball is None:
            return
        obs = observe(v, percept.time, float(percept.joints[0]), float(percept.joints[1]))
        bx, by = float(obs.ball[0]), float(obs.ball[1])
        self.ball = agent.odo.pose.to_world(bx, by)
        self.seen_at = percept.time


def dribble_inputs(robot: tuple[float, float, float], ball: tuple[float, float],
                   goal: tuple[float, float] = GOAL) -> tuple[tuple[float, float], float, bool]:
    """Where to walk (field-frame point) and which final heading (rad, field frame) to
    drive the ball from `ball` toward `goal`; True when lined up to walk through it."""
    rx, ry, rh = robot
    bx, by = ball
    gx, gy = goal
    dx, dy = gx - bx, gy - by
    n = math.hypot(dx, dy) or 1.0
    dx, dy = dx / n, dy / n
    along = (rx - bx) * dx + (ry - by) * dy  # robot's position along the drive line (negative: behind)
    across = -(rx - bx) * dy + (ry - by) * dx
    drive = math.atan2(dy, dx)
    if along < -0.05 and abs(across) < ALIGNED and abs(wrap(rh - drive)) < ALIGNED_ANGLE:
        return (bx + 0.6 * dx, by + 0.6 * dy), drive, True
    if along > -BEHIND * 0.5:
        # Beside or ahead of the ball: go round it on the robot's side, never through it.
        side = 1.0 if across >= 0 else -1.0
        target = (bx - 0.1 * dx - 0.35 * side * dy, by - 0.1 * dy + 0.35 * side * dx)
    else:
        target = (bx - BEHIND * dx, by - BEHIND * dy)
    return target, math.atan2(by - ry, bx - rx), False


@dataclass
class DribblePhase:
    """Drive the ball toward the goal for `duration` s; utility = the ball's progress (m)."""

    duration: float
    near: float = 0.8  # m: the position-to-dribble set within this of the ball
    sprint_within: float = math.radians(15.0)

    def start(self, sim: Sim) -> None:
        self._b0 = sim.world.ball_position()[:2]
        self.tracker = sim.memory.setdefault("ball", BallTracker())  # one memory across the phases

    def act(self, sim: Sim, percept: Percept) -> np.ndarray:
        agent = sim.agent
        self.tracker.update(percept, agent)
        o = agent.odo
        b = self.tracker.ball
        if b is None or percept.time - self.tracker.seen_at > LOST:
            return agent.walk(percept, 0.0, 0.0, 0.5, head=np.array([0.0, HEAD_PITCH]))
        bearing = wrap(math.atan2(b[1] - o.y, b[0] - o.x) - o.heading)
        head = np.array([max(-1.0, min(1.0, bearing)), HEAD_PITCH])
        (tx, ty), heading, _ = dribble_inputs((o.x, o.y, o.heading), b)
        rel = o.relative(tx, ty)
        dist_ball = math.hypot(b[0] - o.x, b[1] - o.y)
        if dist_ball < self.near:
            set_name = "position_to_dribble"
        elif abs(math.atan2(rel[1], rel[0])) < self.sprint_within:
            set_name = "sprint"
        else:
            set_name = "go_to_target"
        params = agent.motion.walk.sets[set_name]
        x, y, turn = walk_toward(rel[0], rel[1], wrap(heading - o.heading), params, brake=0.3,
                                 face_beyond=1.0)
        return agent.walk(percept, x, y, turn, set_name, head=head)

    def after_step(self, sim: Sim) -> None:
        pass

    def done(self, sim: Sim) -> bool:
        return False

    def utility(self, sim: Sim, elapsed: float) -> tuple[float, dict]:
        b = sim.world.ball_position()[:2]
        gx, gy = GOAL
        dx, dy = gx - self._b0[0], gy - self._b0[1]
        n = math.hypot(dx, dy) or 1.0
        return float(((b[0] - self._b0[0]) * dx + (b[1] - self._b0[1]) * dy) / n), {}

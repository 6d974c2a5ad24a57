"""A standing agent that perceives: the posture agent's body with a world model and head.

It holds the posture agent's stand pose (and beams like it), pans its head
(`agent.head`), keeps a `WorldModel` up to date from every percept and talks to
its teammates in its time slot. Until the walk exists it never moves, so its
odometry is zero unless someone sets `odometry` (a benchmark that moves it
with the trainer does). Tests and benchmarks use it to check perception on
physics.
"""

from __future__ import annotations

from agent.head import HeadController
from agent.localization import LocalizationParams
from agent.posture import PostureAgent
from agent.worldmodel import WorldModel
from models.messages import Action, Percept


class PerceivingAgent(PostureAgent):
    """PostureAgent + WorldModel + HeadController + team messages."""

    def __init__(self, side: str, unum: int, robot_type: int, seed: int = 0, pan: bool = True,
                 talk: bool = True, params: LocalizationParams | None = None) -> None:
        super().__init__(side, unum, robot_type, seed)
        self.robot_type = robot_type
        self.world = WorldModel(side, unum, seed=seed, params=params)
        self.head = HeadController(goalie=unum == 1)
        self.pan = pan
        self.talk = talk
        self.odometry = (0.0, 0.0, 0.0)  # (dx m, dy m, dtheta rad) to feed at the next cycle

    def act(self, percept: Percept) -> Action:
        self.world.update(percept, self.odometry)
        self.odometry = (0.0, 0.0, 0.0)
        action = super().act(percept)
        if action.beam is not None:
            self.world.beamed(*action.beam)
        if self.pan:
            rel = self.world.ball_relative() if self.world.ball.valid else None  # else scan for it
            bearing, dist = rel if rel is not None else (None, None)
            action.joint_velocities[0:2] = self.head.velocities(percept.time, percept.joints, bearing, dist)
        if self.talk:
            action.say = self.world.say(robot_type=self.robot_type)
        x, y, _ = self.world.pose
        action.annotations["pose"] = (float(x), float(y))
        return action


__all__ = ["PerceivingAgent"]

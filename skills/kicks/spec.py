"""What every kick offers the ball approach and the behaviors (dissertation 8.2.7).

A kick is a skill that starts with the robot standing still behind the ball
and ends with the robot standing again. Frames:

* robot frame: the torso's position projected on the ground, x forward along
  the torso's heading, y left, z up (m, rad). Where the ball must lie at the
  start of a kick, and where the kick sends it, are given in it.

`KickSpec` says where the ball must be, in which direction it goes and how far
it nominally travels; a kick skill (`KickSkill`) turns percepts into joint
targets until it is `done`. The approach (`skills.approach`) stops the robot
with the ball at `KickSpec.ball` within `KickSpec.tolerance`, then hands over.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from models.messages import Percept


@dataclass(frozen=True)
class KickSpec:
    """A kick's standing offset from the ball, its direction and its reach.

    name: unique, e.g. "kick_left", "ik_forward_left", "ik_45_in_right";
    foot: the kicking foot, "l" or "r";
    ball: (x, y) m, robot frame: the ball's center when the kick starts;
    tolerance: (dx m, dy m, dtheta rad): half-widths of the box around `ball`
        (and around the facing) the approach must stop in;
    direction: rad, robot frame: where the ball goes (0 straight ahead, + left);
    distance: m: nominal distance the ball travels on grass (to the stop);
    duration: s: from the start to the end of the kick (standing again).
    """

    name: str
    foot: str
    ball: tuple[float, float]
    tolerance: tuple[float, float, float]
    direction: float = 0.0
    distance: float = 0.0
    duration: float = 0.0


class KickSkill(Protocol):
    """One kick, played cycle by cycle from the robot's percepts."""

    spec: KickSpec

    def reset(self, ball: tuple[float, float] | None = None, start: np.ndarray | None = None) -> None:
        """Start over at the next `step`; `ball` is the agent's estimate of the ball
        (m, robot frame) when it has one (IK kicks place the foot from it); `start` the
        joint targets (rad, league order) the robot holds as the kick begins (`Motion.held_target`;
        keyframe kicks move from them into their base pose)."""
        ...

    def step(self, percept: Percept) -> np.ndarray:
        """Joint targets (rad, league order; NaN = hold) for this cycle."""
        ...

    @property
    def done(self) -> bool:
        """True once the kick is over and the robot stands again."""
        ...

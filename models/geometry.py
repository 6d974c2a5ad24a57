"""Plane geometry shared by every layer: angle wrapping and 2-D poses.

Frames are right-handed on the ground: x forward, y left, headings
counter-clockwise from x (m, rad). A `Pose2` is a frame placed in another
(the robot in the field, the kick frame at the ball): `to_world` takes a point
given in the pose's frame into the outer frame, `to_local` the reverse.

The formulas are written once, in the order the callers used to write them
out, so results are the same to the bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi


def wrap(a: np.ndarray | float) -> np.ndarray | float:
    """Angle(s) wrapped into [-pi, pi) (rad); a float for a float, an array for an array."""
    return (a + math.pi) % TWO_PI - math.pi


def rotate(x: float, y: float, angle: float) -> tuple[float, float]:
    """The vector (x, y) turned counter-clockwise by `angle` (rad)."""
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


@dataclass(frozen=True)
class Pose2:
    """A position (x, y, m) and heading (rad) on the ground."""

    x: float = 0.0
    y: float = 0.0
    heading: float = 0.0

    def to_world(self, px, py):
        """A point given in this pose's frame, in the outer frame (floats or arrays)."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        return self.x + c * px - s * py, self.y + s * px + c * py

    def to_local(self, px, py):
        """A point given in the outer frame, in this pose's frame (floats or arrays)."""
        c, s = math.cos(self.heading), math.sin(self.heading)
        ex, ey = px - self.x, py - self.y
        return c * ex + s * ey, -s * ex + c * ey

    def compose(self, other: Pose2) -> Pose2:
        """`other` (given in this pose's frame) in the outer frame."""
        x, y = self.to_world(other.x, other.y)
        return Pose2(x, y, float(wrap(self.heading + other.heading)))

    def inverse(self) -> Pose2:
        """The outer frame's origin seen from this pose: `p.compose(p.inverse())` is the identity."""
        x, y = rotate(-self.x, -self.y, -self.heading)
        return Pose2(x, y, float(wrap(-self.heading)))


__all__ = ["TWO_PI", "Pose2", "rotate", "wrap"]

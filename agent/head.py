"""Head movement (dissertation 8.2.1): what the neck yaw hj1 and head pitch hj2 aim at.

* Scanning: an 8 s cycle that moves the pan every 2 s from straight ahead to
  120 deg left, back to straight ahead, to 120 deg right and back; with the
  120 deg view cone that sweeps the whole 360 deg around the robot.
* Ball focus (a field player within `focus_distance` of the ball, or the reach
  a cycle's call names, the goalie always): the pan swings 30 deg to either
  side of the ball's bearing, so the ball never leaves the view.

The head pitch is held at `tilt` (rad, positive looks up; UT Austin Villa keeps
the head bent down).
"""

from __future__ import annotations

import math

import numpy as np

from models import nao

PAN_LIMIT = math.radians(120.0)  # rad, hj1 range
PITCH_LIMIT = math.radians(45.0)  # rad, hj2 range
SCAN_PERIOD = 8.0  # s
SCAN_KEYS = (0.0, PAN_LIMIT, 0.0, -PAN_LIMIT)  # rad, one every SCAN_PERIOD / 4
FOCUS_SWING = math.radians(30.0)  # rad either side of the ball
FOCUS_PERIOD = 2.0  # s for a full left-right-left swing around the ball


def scan_pan(t: float) -> float:
    """Pan angle (rad) of the 8 s scanning cycle at time t (s): straight, left, straight,
    right, straight, moving linearly between the key angles."""
    phase = (t % SCAN_PERIOD) / (SCAN_PERIOD / 4)
    i = int(phase)
    f = phase - i
    a, b = SCAN_KEYS[i % 4], SCAN_KEYS[(i + 1) % 4]
    return a + (b - a) * f


def focus_pan(t: float, ball_bearing: float) -> float:
    """Pan angle (rad) swinging +-30 deg around the ball's bearing (rad, torso frame)."""
    tri = 1.0 - 4.0 * abs((t / FOCUS_PERIOD) % 1.0 - 0.5)  # -1..1 triangle wave
    return min(max(float(ball_bearing + FOCUS_SWING * tri), -PAN_LIMIT), PAN_LIMIT)


class HeadController:
    """Targets and velocities for hj1 (pan) and hj2 (tilt)."""

    def __init__(self, goalie: bool = False, focus_distance: float = 1.0, tilt: float = 0.0,
                 gain: float = 12.0) -> None:
        self.goalie = goalie
        self.focus_distance = focus_distance
        self.tilt = float(np.clip(tilt, -PITCH_LIMIT, PITCH_LIMIT))
        self.gain = gain  # 1/s, velocity per rad of error
        self.focusing = False

    def target(self, t: float, ball_bearing: float | None, ball_distance: float | None,
               focus_distance: float | None = None) -> tuple[float, float]:
        """(pan, tilt) targets (rad) at time t (s) given the ball's bearing (rad, torso
        frame) and ground distance (m), or None when the ball is unknown; focusing on the
        ball within `focus_distance` (m; None: the controller's own) this cycle."""
        near = self.focus_distance if focus_distance is None else focus_distance
        self.focusing = ball_bearing is not None and ball_distance is not None and (
            self.goalie or ball_distance <= near)
        if self.focusing:
            return focus_pan(t, ball_bearing), self.tilt
        return scan_pan(t), self.tilt

    def velocities(self, t: float, joints: np.ndarray, ball_bearing: float | None,
                   ball_distance: float | None, focus_distance: float | None = None) -> np.ndarray:
        """Joint velocities (rad/s) for hj1, hj2 from their current angles joints[0:2]
        (`target`'s arguments)."""
        pan, tilt = self.target(t, ball_bearing, ball_distance, focus_distance)
        # Two floats clamped by hand: np.clip's values, without its cost on a 2-array.
        m, g = nao.MAX_JOINT_SPEED, self.gain
        q0, q1 = joints[0:2].tolist()
        vp, vt = g * (pan - q0), g * (tilt - q1)
        return np.array([min(max(vp, -m), m), min(max(vt, -m), m)])

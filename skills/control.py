"""Joint control: PID from target angles to joint velocity commands.

UT Austin Villa runs one PID per joint on the angle error in degrees, once a
20 ms cycle, with P 0.15, I 0 and D 0.01, and sends the result as the
joint's angular velocity (SimSpark's hinge effectors take rad/s). In SI, with
the error e in rad and the command in rad/s:

    v = kp e + ki sum(e dt) + kd de/dt
    kp = 0.15 * 180/pi            =  8.59 1/s
    kd = 0.01 * 180/pi * CYCLE    =  0.0115 s   (UT's D acts on the per-cycle difference)
    ki = 0 * 180/pi / CYCLE       =  0 1/s^2   (UT's I acts on the per-cycle sum)

The command is clamped at each joint's maximum speed (`models.nao`), as the
server would; the integral stops growing while a joint is saturated.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from models import nao
from models.rules import CYCLE

_DEG = 180.0 / math.pi
UT_KP = 0.15 * _DEG  # 1/s
UT_KI = 0.0  # 1/s^2
UT_KD = 0.01 * _DEG * CYCLE  # s


@dataclass(frozen=True)
class PidGains:
    """Gains of the joint PID in SI: command (rad/s) per error (rad), per rad s, per rad/s."""

    kp: float = UT_KP  # 1/s
    ki: float = UT_KI  # 1/s^2
    kd: float = UT_KD  # s


class JointPid:
    """One PID per joint turning target angles (rad) into velocity commands (rad/s).

    Gains may be scalars or one per joint (league order). Call `reset` when a
    new motion starts so that the derivative does not kick.
    """

    def __init__(self, max_speed: Sequence[float] | np.ndarray, gains: PidGains = PidGains(),
                 dt: float = CYCLE) -> None:
        self.max_speed = np.asarray(max_speed, dtype=float)
        n = len(self.max_speed)
        self.kp = np.broadcast_to(np.asarray(gains.kp, dtype=float), (n,)).copy()
        self.ki = np.broadcast_to(np.asarray(gains.ki, dtype=float), (n,)).copy()
        self.kd = np.broadcast_to(np.asarray(gains.kd, dtype=float), (n,)).copy()
        self.dt = dt
        self._integral = np.zeros(n)
        self._prev: np.ndarray | None = None
        self._out = np.zeros(n)

    @classmethod
    def for_robot(cls, robot_type: int, gains: PidGains = PidGains(), dt: float = CYCLE) -> JointPid:
        """A PID over every joint of `robot_type` with its speed limits."""
        return cls([j.max_speed for j in nao.joints(robot_type)], gains, dt)

    def reset(self) -> None:
        """Forget the integral and the previous error."""
        self._integral[:] = 0.0
        self._prev = None

    def __call__(self, target: np.ndarray, angles: np.ndarray) -> np.ndarray:
        """Velocity commands (rad/s, clamped) for joint `angles` to reach `target` (rad).

        The returned array is reused by the next call; copy it to keep it.
        """
        err = np.subtract(target, angles)
        derr = np.zeros_like(err) if self._prev is None else (err - self._prev) / self.dt
        self._prev = err
        integral = self.ki.any()
        if integral:
            self._integral += err * self.dt
        out = self._out
        np.multiply(self.kp, err, out=out)
        out += self.kd * derr
        if integral:
            out += self.ki * self._integral
            saturated = np.abs(out) > self.max_speed
            if saturated.any():
                self._integral[saturated] -= err[saturated] * self.dt  # anti-windup
        # np.clip as minimum(maximum()): the same values without np.clip's Python layers.
        np.maximum(out, -self.max_speed, out=out)
        np.minimum(out, self.max_speed, out=out)
        return out

"""The tilt estimate's update in plain Python: the reference `skills._kernels.tilt_update`
follows line for line (tests compare them bit for bit)."""

from __future__ import annotations

import math

import numpy as np

from skills.imu import GRAVITY


def _roll_pitch(x: float, y: float, z: float) -> tuple[float, float]:
    """Roll and pitch (rad) of a torso that sees the world's up direction along (x, y, z)
    (torso frame; any length): up = (-sin pitch, cos pitch sin roll, cos pitch cos roll)."""
    return math.atan2(y, z), math.atan2(-x, math.hypot(y, z))


class TiltEstimatorRef:
    """`skills.imu.TiltEstimator`'s state and update in plain Python."""

    def __init__(self, blend: float = 0.05, fall_angle: float = math.radians(55.0),
                 accel_smoothing: float = 0.1, from_first: bool = False, exact: bool = False) -> None:
        self.blend = blend
        self.exact = exact
        self.fall_angle = fall_angle
        self.accel_smoothing = accel_smoothing
        self.roll = 0.0
        self.pitch = 0.0
        self._a = [0.0, 0.0, GRAVITY]  # the low-passed accelerometer (m/s^2), as floats
        self._started = not from_first

    def update(self, gyro: np.ndarray, accel: np.ndarray, dt: float) -> None:
        """One cycle: gyro (rad/s) and accelerometer (m/s^2) in the torso frame, dt in s."""
        ax, ay, az = np.asarray(accel, dtype=float).tolist()
        if not (math.isfinite(ax) and math.isfinite(ay) and math.isfinite(az)):
            return
        a = self._a
        if self._started:
            s = self.accel_smoothing
            a[0] += s * (ax - a[0])
            a[1] += s * (ay - a[1])
            a[2] += s * (az - a[2])
        else:
            a[0], a[1], a[2] = ax, ay, az
        acc_roll, acc_pitch = _roll_pitch(a[0], a[1], a[2])
        if not self._started:
            self.roll, self.pitch, self._started = acc_roll, acc_pitch, True
            return
        gx, gy, gz = np.asarray(gyro, dtype=float).tolist()
        if self.exact:
            # The world's up direction in the torso frame turns against the torso's
            # angular velocity, du/dt = -omega x u, whatever the yaw rate.
            cp = math.cos(self.pitch)
            ux, uy, uz = -math.sin(self.pitch), cp * math.sin(self.roll), cp * math.cos(self.roll)
            roll, pitch = _roll_pitch(ux - (gy * uz - gz * uy) * dt, uy - (gz * ux - gx * uz) * dt,
                                      uz - (gx * uy - gy * ux) * dt)
        else:
            # Small-angle Euler rates: droll ~ gx, dpitch ~ gy.
            roll = self.roll + gx * dt
            pitch = self.pitch + gy * dt
        k = self.blend
        # Wrapped: lying, the roll passes +-pi, and an unwrapped 2 pi read as a lean.
        self.roll = math.remainder(roll + k * math.remainder(acc_roll - roll, 2 * math.pi), 2 * math.pi)
        self.pitch = pitch + k * (acc_pitch - pitch)

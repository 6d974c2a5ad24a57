"""Torso tilt from the IMU and a simple accelerometer fall flag.

The accelerometer reads the specific force in the torso frame: about
(0, 0, +9.81) m/s^2 when upright and still. With the torso's orientation
R = Rz(yaw) Ry(pitch) Rx(roll), gravity's reaction in the torso frame is
g (-sin pitch, cos pitch sin roll, cos pitch cos roll), so roll and pitch follow
from its direction. A complementary filter integrates the gyro (rad/s, torso
frame) for fast changes and pulls toward the low-passed accelerometer's answer,
so walking accelerations do not shake the estimate. The pull is fairly strong
(5 % a cycle): a standing robot's torso vibrates (the gyro reads about 0.2 rad/s
about y while the pitch stays within 0.4 deg), and the gyro sampled every 20 ms
integrates that into a drift of about 1 deg/s. Measured on a standing robot:
0.23 deg rms pitch error, 0.06 deg roll. Walking, foot strikes shake the
accelerometer, and at 5 % the estimate errs 4-6 deg rms (up to 15-19 deg); the
skills keep 5 % (their balance was tuned with it), the world model, which levels
what the camera sees, takes 1 % (`agent.worldmodel`: 2-3 deg rms walking; standing,
0.37 against 0.47 deg pitch on type 0 now).

By default the estimate starts upright (roll = pitch = 0, the accelerometer at
gravity): it is made or reset with the robot on its feet, after a beam or in a
stand. The first readings after a beam are of the robot landing: about (0, 0, -0)
in free fall, then jolts of 5-16 m/s^2 in any direction for about 0.2 s. Started
from one of them, the roll began anywhere up to +-180 deg and took 1-2 s to come
back: vision was levelled by that roll, and started from a jolt (roll 142 deg) the
robot took itself for fallen and froze. The kicks start theirs from the first reading
(`from_first`) on a robot already standing: their balance was tuned so.
"""

from __future__ import annotations

import math

import numpy as np

from skills import _kernels as kernels
from skills.frames import rot_x, rot_y

GRAVITY = 9.81  # m/s^2


class TiltEstimator:
    """Roll and pitch of the torso (rad) from gyro and accelerometer.

    `blend` is the share of the accelerometer's answer taken each cycle (0..1);
    `fall_angle` is the tilt from vertical (rad) beyond which the robot counts as
    fallen, judged on the low-passed accelerometer and the fused estimate both;
    `from_first`: start from the first reading instead of upright; `exact`: turn the
    estimate by the whole gyro (the world's up direction in the torso frame turns as
    -omega x up) rather than taking the gyro's x and y as roll and pitch rates. The
    small-angle rule errs by about tan(pitch) x yaw rate while turning (a torso pitched
    0.3 rad turning at 2 rad/s leans 13 deg sideways in the estimate); the skills keep
    it, as their balance was tuned with it, the world model takes the exact one.
    """

    def __init__(self, blend: float = 0.05, fall_angle: float = math.radians(55.0),
                 accel_smoothing: float = 0.1, from_first: bool = False, exact: bool = False) -> None:
        self.blend = blend
        self.exact = exact
        self.fall_angle = fall_angle
        self.accel_smoothing = accel_smoothing
        # roll, pitch, the low-passed accelerometer and started (`skills._kernels.T_ROLL` ...)
        self._st = np.array([0.0, 0.0, 0.0, 0.0, GRAVITY, 0.0 if from_first else 1.0])

    @property
    def roll(self) -> float:
        """Estimated roll (rad)."""
        return float(self._st[kernels.T_ROLL])

    @roll.setter
    def roll(self, value: float) -> None:
        self._st[kernels.T_ROLL] = value

    @property
    def pitch(self) -> float:
        """Estimated pitch (rad, forward positive)."""
        return float(self._st[kernels.T_PITCH])

    @pitch.setter
    def pitch(self, value: float) -> None:
        self._st[kernels.T_PITCH] = value

    @property
    def _a(self) -> list[float]:
        """The low-passed accelerometer (m/s^2, torso frame), as floats."""
        return self._st[kernels.T_ACC:kernels.T_ACC + 3].tolist()

    @property
    def _acc(self) -> np.ndarray:
        """The low-passed accelerometer (m/s^2, torso frame)."""
        return self._st[kernels.T_ACC:kernels.T_ACC + 3].copy()

    def update(self, gyro: np.ndarray, accel: np.ndarray, dt: float) -> None:
        """One cycle: gyro (rad/s) and accelerometer (m/s^2) in the torso frame, dt in s.

        Compiled (`skills._kernels.tilt_update`), the same floats as the Python it replaced;
        a non-finite accelerometer is skipped, an infinite roll raises as math.remainder does.
        """
        status = kernels.tilt_update(self._st, np.asarray(gyro, dtype=float), np.asarray(accel, dtype=float),
                                     float(dt), float(self.blend), float(self.accel_smoothing),
                                     bool(self.exact))
        if status == kernels.TILT_DOMAIN_ERROR:
            raise ValueError("math domain error")

    @property
    def level(self) -> np.ndarray:
        """3x3 rotation from the torso frame to the level frame (z vertical, same yaw)."""
        return rot_y(self.pitch) @ rot_x(self.roll)

    @property
    def tilt(self) -> float:
        """Angle (rad) between the torso's z axis and the vertical, from the smoothed accelerometer."""
        a = self._acc
        n = float(np.linalg.norm(a))
        return math.acos(max(-1.0, min(1.0, a[2] / n))) if n > 1e-6 else 0.0

    @property
    def fused_tilt(self) -> float:
        """Angle (rad) between the torso's z axis and the vertical, from the fused roll and pitch."""
        c = math.cos(self.roll) * math.cos(self.pitch)
        return math.acos(max(-1.0, min(1.0, c)))

    @property
    def fallen(self) -> bool:
        """True while the torso leans more than `fall_angle` from vertical, by the smoothed
        accelerometer and by the fused estimate both. Walking, foot strikes alone can tip the
        smoothed accelerometer past 80 deg on an upright torso, whose fused tilt stays near
        10 deg; a robot that took that for a fall froze mid-step and toppled."""
        return self.fused_tilt > self.fall_angle and self.tilt > self.fall_angle  # the cheaper first

    @property
    def fall_direction(self) -> str | None:
        """'front', 'back' or 'side' when fallen, else None."""
        if not self.fallen:
            return None
        ax, ay, _ = self._a
        if abs(ax) >= abs(ay):
            return "front" if ax < 0 else "back"  # face down: x axis points at the ground
        return "side"

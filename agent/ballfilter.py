"""Ball tracking: a Kalman filter over the ball's position and velocity on the ground.

State (x, y, vx, vy) in the team frame (m, m/s). The motion model is a rolling ball
slowed by the league's linear drag (`ROLLING_DRAG`, a deceleration proportional to
speed) and a small rolling friction (`ROLLING_DECELERATION`, constant, along the
current velocity), both fitted on this project's MuJoCo ball (3 m/s rolls about 8
m), with white-noise acceleration for kicks and bounces. Measurements are ground
positions from the agent's own vision (noise growing with distance) and from
teammates' messages (coarser). A measurement far outside the filter's belief (a
kick, a referee's drop) resets it. Dissertation, Appendix D.3.2.
"""

from __future__ import annotations

import math

import numpy as np
from filterpy.kalman import KalmanFilter

from models.field import BALL_ROLL_DECEL, BALL_ROLL_DRAG, rolling_distance

ROLLING_DRAG = BALL_ROLL_DRAG  # 1/s: dv/dt = -ROLLING_DRAG v - ROLLING_DECELERATION v/|v|
ROLLING_DECELERATION = BALL_ROLL_DECEL  # m/s^2


def _kf_update(kf: KalmanFilter, z: np.ndarray, r: np.ndarray) -> None:
    """filterpy's `kf.update(z, R=r)` for a (2,) measurement, its very products (bit for
    bit: the Joseph form, `np.linalg.inv` of S), without its checks, its deepcopy of z
    and its copies of the posterior (x_post, P_post: unused here)."""
    kf._log_likelihood = kf._likelihood = kf._mahalanobis = None
    h = kf.H
    kf.y = y = z - np.dot(h, kf.x)
    pht = np.dot(kf.P, h.T)
    kf.S = np.dot(h, pht) + r
    kf.SI = kf.inv(kf.S)
    kf.K = k = np.dot(pht, kf.SI)
    kf.x = kf.x + np.dot(k, y)
    i_kh = kf._I - np.dot(k, h)
    kf.P = np.dot(np.dot(i_kh, kf.P), i_kh.T) + np.dot(np.dot(k, r), k.T)
    kf.z = z.copy()


class BallFilter:
    """Kalman filter (filterpy) over ball position and velocity in the team frame."""

    def __init__(self, sigma_accel: float = 1.5, deceleration: float = ROLLING_DECELERATION,
                 drag: float = ROLLING_DRAG, gate: float = 5.0, maneuver: float = 2.5,
                 maneuver_sigma_v: float = 0.3, history: int = 3) -> None:
        """sigma_accel: process noise (m/s^2, white acceleration); deceleration: rolling friction
        (m/s^2); drag: deceleration per unit speed (1/s); gate: innovation (in standard
        deviations) beyond which a measurement resets the filter instead of correcting
        it; maneuver: innovation (standard deviations) beyond which the ball is taken to
        have been kicked: the filter restarts from a straight-line fit of the last
        `history` measurements with at least maneuver_sigma_v (m/s) of velocity
        uncertainty."""
        self.history = history
        self._recent: list[tuple[float, float, float]] = []
        self.sigma_accel = sigma_accel
        self.maneuver = maneuver
        self.maneuver_sigma_v = maneuver_sigma_v
        self.deceleration = deceleration
        self.drag = drag
        self.gate = gate
        kf = KalmanFilter(dim_x=4, dim_z=2)
        kf.H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
        self.kf = kf
        self._dt = -1.0
        self.initialized = False
        self.last_update = -math.inf  # s, time of the last measurement
        self.reset(np.zeros(2), 100.0)

    def reset(self, xy: np.ndarray, sigma: float, velocity: np.ndarray | None = None) -> None:
        """Restart at a position (m) with a position uncertainty (m) and unknown velocity."""
        kf = self.kf
        kf.x = np.array([xy[0], xy[1], 0.0, 0.0]) if velocity is None else np.array(
            [xy[0], xy[1], velocity[0], velocity[1]])
        kf.P = np.diag([sigma ** 2, sigma ** 2, 4.0, 4.0])
        self._recent = []

    def predict(self, dt: float) -> None:
        """Advance the belief by dt seconds."""
        if dt <= 0:
            return
        kf = self.kf
        if dt != self._dt:  # the matrices depend on dt only (20 ms nearly always)
            self._dt = dt
            decay = math.exp(-self.drag * dt)  # velocity kept over dt under the drag
            reach = (1.0 - decay) / self.drag if self.drag > 0 else dt  # distance per unit speed
            kf.F = np.array([[1.0, 0.0, reach, 0.0], [0.0, 1.0, 0.0, reach],
                             [0.0, 0.0, decay, 0.0], [0.0, 0.0, 0.0, decay]])
            kf.B = np.array([[0.5 * dt * dt, 0.0], [0.0, 0.5 * dt * dt], [dt, 0.0], [0.0, dt]])
            g = np.array([0.5 * dt * dt, dt])
            qb = np.outer(g, g) * self.sigma_accel ** 2
            kf.Q = np.array([[qb[0, 0], 0, qb[0, 1], 0], [0, qb[0, 0], 0, qb[0, 1]],
                             [qb[1, 0], 0, qb[1, 1], 0], [0, qb[1, 0], 0, qb[1, 1]]])
        v = kf.x[2:4]
        speed = float(np.hypot(v[0], v[1]))
        if speed * math.exp(-self.drag * dt) > self.deceleration * dt:
            u = -self.deceleration * v / speed
        else:
            u = -v * math.exp(-self.drag * dt) / dt  # comes to rest within this step
        # filterpy's KalmanFilter.predict(u=u), its very products (bit for bit), without
        # its argument checks and its copies of the prior (x_prior, P_prior: unused here).
        f = kf.F
        kf.x = np.dot(f, kf.x) + np.dot(kf.B, u)
        p = np.dot(np.dot(f, kf.P), f.T)
        if kf.alpha != 1.0:
            p = kf._alpha_sq * p
        kf.P = p + kf.Q

    def update(self, xy: np.ndarray, sigma: float, time: float) -> None:
        """Correct with a measured ground position xy (m, team frame) of standard
        deviation sigma (m) taken at `time` (s)."""
        z = np.asarray(xy, dtype=float)[:2]
        kf = self.kf
        r = np.eye(2) * sigma ** 2
        if not self.initialized:
            self.reset(z, sigma)
            self.initialized = True
        else:
            s = kf.P[:2, :2] + r
            innov = z - kf.x[:2]
            nis = float(innov @ np.linalg.solve(s, innov))
            if nis > self.gate ** 2:
                self.reset(z, sigma)
            else:
                if nis > self.maneuver ** 2 and len(self._recent) >= 2:
                    self._refit(z, sigma, time)
                else:
                    _kf_update(kf, z, r)
        self.last_update = time
        self._recent.append((time, z[0], z[1]))
        del self._recent[:-self.history]

    def _refit(self, z: np.ndarray, sigma: float, time: float) -> None:
        """Restart from a straight-line fit of the last measurements and this one (the
        ball was kicked: the old velocity no longer holds)."""
        pts = np.array(self._recent[-(self.history - 1):] + [(time, z[0], z[1])])
        t = pts[:, 0] - time
        a = np.stack([np.ones_like(t), t], axis=1)
        coef, *_ = np.linalg.lstsq(a, pts[:, 1:], rcond=None)
        span = max(float(t.max() - t.min()), 1e-3)
        sigma_v = max(self.maneuver_sigma_v, 2.0 * sigma / span)
        self.kf.x = np.array([z[0], z[1], coef[1, 0], coef[1, 1]])
        self.kf.P = np.diag([sigma ** 2, sigma ** 2, sigma_v ** 2, sigma_v ** 2])

    @property
    def position(self) -> np.ndarray:
        """Estimated ball position (x, y) in the team frame (m)."""
        return self.kf.x[:2].copy()

    @property
    def velocity(self) -> np.ndarray:
        """Estimated ball velocity (vx, vy) in the team frame (m/s)."""
        return self.kf.x[2:4].copy()

    @property
    def position_sigma(self) -> float:
        """Standard deviation (m) of the position estimate (root mean of the two axes)."""
        return float(math.sqrt(0.5 * (self.kf.P[0, 0] + self.kf.P[1, 1])))

    def stop_position(self) -> np.ndarray:
        """Where the ball comes to rest (m, team frame) if nothing touches it: under
        dv/dt = -k v - a it travels v/k - (a/k^2) ln(1 + k v / a) further."""
        v = self.velocity
        speed = float(np.hypot(v[0], v[1]))
        if speed < 1e-6:
            return self.position
        return self.position + v * (rolling_distance(speed, self.drag, self.deceleration) / speed)

    def time_to_stop(self) -> float:
        """Seconds until the ball comes to rest (s): ln(1 + k v / a) / k."""
        speed = float(np.hypot(*self.velocity))
        k, a = self.drag, self.deceleration
        return math.log1p(k * speed / a) / k if k > 0 else speed / a


__all__ = ["ROLLING_DECELERATION", "ROLLING_DRAG", "BallFilter", "rolling_distance"]

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
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from models.field import BALL_ROLL_DECEL, BALL_ROLL_DRAG, rolling_distance
from models.jit import njit

ROLLING_DRAG = BALL_ROLL_DRAG  # 1/s: dv/dt = -ROLLING_DRAG v - ROLLING_DECELERATION v/|v|
ROLLING_DECELERATION = BALL_ROLL_DECEL  # m/s^2


# The filter's arithmetic, compiled. It repeats the products of filterpy's KalmanFilter
# (predict with a control input, update in the Joseph form) as numpy's OpenBLAS forms
# them on these shapes, so the results are bit for bit filterpy's: a matrix product is
# one fused multiply-add chain from zero per entry in k order (dgemm); a matrix times a
# 4-vector sums (a0 x0 + a2 x2) + (a1 x1 + a3 x3), times a 2-vector fma(a0, x0, a1 x1)
# (dgemv); a 2x2 inverse (dgesv with B = I) and solve (dgesv, one column) are LU with
# partial pivoting, multiplying by reciprocal pivots, except that the solve's back
# substitution divides. tests/agent/test_ballfilter.py checks all of it against filterpy.

@intrinsic
def _fma(typingctx, a, b, c):
    """a * b + c in float64 with one rounding (LLVM's fma intrinsic)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        f64 = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [f64], ir.FunctionType(f64, [f64] * 3))
        return builder.call(fn, args)

    return sig, codegen


@njit
def _mm(a: np.ndarray, b: np.ndarray, transpose_b: bool) -> np.ndarray:
    """a @ b (or a @ b.T) as dgemm forms it."""
    m = b.shape[0] if transpose_b else b.shape[1]
    out = np.empty((a.shape[0], m))
    for i in range(a.shape[0]):
        for j in range(m):
            acc = 0.0
            for k in range(a.shape[1]):
                acc = _fma(a[i, k], b[j, k] if transpose_b else b[k, j], acc)
            out[i, j] = acc
    return out


@njit
def _mv(a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """a @ v for a (n, 4) or (n, 2) matrix, as dgemv forms it."""
    out = np.empty(a.shape[0])
    for i in range(a.shape[0]):
        if a.shape[1] == 4:
            out[i] = (a[i, 0] * v[0] + a[i, 2] * v[2]) + (a[i, 1] * v[1] + a[i, 3] * v[3])
        else:
            out[i] = _fma(a[i, 0], v[0], a[i, 1] * v[1])
    return out


@njit
def _lu2(s: np.ndarray) -> tuple[bool, float, float, float, float]:
    """LU of a 2x2 matrix with partial pivoting (dgetrf): (rows swapped, u00, u01, l10, u11)."""
    swap = abs(s[1, 0]) > abs(s[0, 0])
    a, b, c, d = (s[1, 0], s[1, 1], s[0, 0], s[0, 1]) if swap else (s[0, 0], s[0, 1], s[1, 0], s[1, 1])
    lo = c * (1.0 / a)
    return swap, a, b, lo, d - lo * b


@njit
def _inv2(s: np.ndarray) -> np.ndarray:
    """np.linalg.inv of a 2x2 matrix."""
    swap, a, b, lo, u = _lu2(s)
    ia, iu = 1.0 / a, 1.0 / u
    out = np.empty((2, 2))
    for col in range(2):
        e0 = 1.0 if (col == 1) == swap else 0.0  # the identity's column, rows pivoted
        e1 = 1.0 - e0
        x1 = (e1 - lo * e0) * iu
        out[0, col] = (e0 - b * x1) * ia
        out[1, col] = x1
    return out


@njit
def _predict(x: np.ndarray, p: np.ndarray, dt: float, drag: float, deceleration: float,
             accel_var: float) -> None:
    """Advance state x (4,) and covariance p (4, 4) in place by dt (s) under drag (1/s),
    rolling friction (m/s^2) and white acceleration noise of variance accel_var
    (m^2/s^4): filterpy's predict(u) with F, B, Q of `BallFilter.predict`."""
    decay = math.exp(-drag * dt)  # velocity kept over dt under the drag
    reach = (1.0 - decay) / drag if drag > 0 else dt  # distance per unit speed
    half = 0.5 * dt * dt
    f = np.zeros((4, 4))
    f[0, 0] = f[1, 1] = 1.0
    f[0, 2] = f[1, 3] = reach
    f[2, 2] = f[3, 3] = decay
    bm = np.zeros((4, 2))
    bm[0, 0] = bm[1, 1] = half
    bm[2, 0] = bm[3, 1] = dt
    q = np.zeros((4, 4))
    q[0, 0] = q[1, 1] = half * half * accel_var
    q[0, 2] = q[1, 3] = half * dt * accel_var
    q[2, 0] = q[3, 1] = dt * half * accel_var
    q[2, 2] = q[3, 3] = dt * dt * accel_var
    u = np.empty(2)
    speed = math.hypot(x[2], x[3])
    if speed * math.exp(-drag * dt) > deceleration * dt:
        u[0], u[1] = -deceleration * x[2] / speed, -deceleration * x[3] / speed
    else:  # comes to rest within this step
        u[0], u[1] = -x[2] * math.exp(-drag * dt) / dt, -x[3] * math.exp(-drag * dt) / dt
    xf, xb = _mv(f, x), _mv(bm, u)
    x[:] = xf + xb
    p[:] = _mm(_mm(f, p, False), f, True) + q


@njit
def _nis(x: np.ndarray, p: np.ndarray, z: np.ndarray, r_var: float) -> float:
    """Squared innovation of a position z (2,) of variance r_var (m^2) over its
    covariance, in standard deviations^2 (innov @ np.linalg.solve(S, innov))."""
    s = np.empty((2, 2))
    s[0, 0], s[0, 1] = p[0, 0] + r_var, p[0, 1] + 0.0
    s[1, 0], s[1, 1] = p[1, 0] + 0.0, p[1, 1] + r_var
    i0, i1 = z[0] - x[0], z[1] - x[1]
    swap, a, b, lo, u = _lu2(s)
    e0, e1 = (i1, i0) if swap else (i0, i1)
    s1 = (e1 - lo * e0) / u
    s0 = (e0 - b * s1) / a
    return i0 * s0 + i1 * s1


@njit
def _correct(x: np.ndarray, p: np.ndarray, z: np.ndarray, r_var: float) -> None:
    """filterpy's update(z, R = r_var I) of state x and covariance p in place."""
    h = np.zeros((2, 4))
    h[0, 0] = h[1, 1] = 1.0
    r = np.zeros((2, 2))
    r[0, 0] = r[1, 1] = r_var
    y = z - _mv(h, x)
    pht = _mm(p, h, True)
    k = _mm(pht, _inv2(_mm(h, pht, False) + r), False)
    x[:] = x + _mv(k, y)
    i_kh = np.eye(4) - _mm(k, h, False)
    p[:] = _mm(_mm(i_kh, p, False), i_kh, True) + _mm(_mm(k, r, False), k, True)


class BallFilter:
    """Kalman filter over ball position and velocity in the team frame: state `x` (4,:
    x, y, vx, vy; m, m/s), covariance `P` (4, 4)."""

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
        self.x = np.zeros(4)
        self.P = np.zeros((4, 4))
        self.initialized = False
        self.last_update = -math.inf  # s, time of the last measurement
        self.reset(np.zeros(2), 100.0)

    def reset(self, xy: np.ndarray, sigma: float, velocity: np.ndarray | None = None) -> None:
        """Restart at a position (m) with a position uncertainty (m) and unknown velocity."""
        self.x[:] = (xy[0], xy[1], 0.0, 0.0) if velocity is None else (xy[0], xy[1], velocity[0], velocity[1])
        self.P[:] = np.diag([sigma ** 2, sigma ** 2, 4.0, 4.0])
        self._recent = []

    def predict(self, dt: float) -> None:
        """Advance the belief by dt seconds: constant velocity slowed by the drag and the
        rolling friction (stopping at rest), white acceleration noise."""
        if dt > 0:
            _predict(self.x, self.P, dt, self.drag, self.deceleration, self.sigma_accel ** 2)

    def update(self, xy: np.ndarray, sigma: float, time: float) -> None:
        """Correct with a measured ground position xy (m, team frame) of standard
        deviation sigma (m) taken at `time` (s)."""
        z = np.asarray(xy, dtype=float)[:2]
        r_var = sigma ** 2
        if not self.initialized:
            self.reset(z, sigma)
            self.initialized = True
        else:
            nis = _nis(self.x, self.P, z, r_var)
            if nis > self.gate ** 2:
                self.reset(z, sigma)
            elif nis > self.maneuver ** 2 and len(self._recent) >= 2:
                self._refit(z, sigma, time)
            else:
                _correct(self.x, self.P, z, r_var)
        self.last_update = time
        self._recent.append((time, float(z[0]), float(z[1])))
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
        self.x[:] = (z[0], z[1], coef[1, 0], coef[1, 1])
        self.P[:] = np.diag([sigma ** 2, sigma ** 2, sigma_v ** 2, sigma_v ** 2])

    @property
    def position(self) -> np.ndarray:
        """Estimated ball position (x, y) in the team frame (m)."""
        return self.x[:2].copy()

    @property
    def velocity(self) -> np.ndarray:
        """Estimated ball velocity (vx, vy) in the team frame (m/s)."""
        return self.x[2:4].copy()

    @property
    def position_sigma(self) -> float:
        """Standard deviation (m) of the position estimate (root mean of the two axes)."""
        return float(math.sqrt(0.5 * (self.P[0, 0] + self.P[1, 1])))

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

"""The skills' hot loop, compiled with numba: one cycle of joint commands (target
fill-in, PID without its integral, feed-forward, clamps) in one pass.

It repeats the numpy code of `Motion.command` and `JointPid.__call__` operation for
operation, so results are bit for bit theirs; what goes is a dozen small array
operations a cycle.
"""

from __future__ import annotations

import warnings

import numba
import numpy as np


def _njit(fn):
    """`numba.njit(cache=True)`, compiled in memory where no cache directory is writable."""
    try:
        return numba.njit(cache=True)(fn)
    except RuntimeError as exc:  # "cannot cache function ...: no locator available"
        warnings.warn(f"skills kernels compile in memory, not cached: {exc}", RuntimeWarning,
                      stacklevel=2)
        return numba.njit(fn)


@_njit
def joint_command(target: np.ndarray, q: np.ndarray, prev_target: np.ndarray, has_prev_target: bool,
                  prev_err: np.ndarray, has_prev_err: bool, kp: np.ndarray, kd: np.ndarray, dt: float,
                  max_speed: np.ndarray, feedforward: float, cycle: float, new_target: np.ndarray,
                  err: np.ndarray, pid_out: np.ndarray, v: np.ndarray) -> None:
    """Joint velocities v (rad/s) toward `target` (NaN: hold the previous target, else the
    angle q) for a PID with gains kp, kd (no integral) whose last error was prev_err,
    plus feedforward times the target's rate of change over `cycle`; the PID's output
    and the sum each clamped at +-max_speed (as np.maximum then np.minimum). Also fills
    new_target (the targets used), err (their errors) and pid_out (the clamped PID)."""
    for i in range(target.shape[0]):
        t = target[i]
        if t != t:
            if has_prev_target:
                t = q[i] if prev_target[i] != prev_target[i] else prev_target[i]
            else:
                t = q[i]
        new_target[i] = t
        e = t - q[i]
        err[i] = e
        d = (e - prev_err[i]) / dt if has_prev_err else 0.0
        o = kp[i] * e
        o += kd[i] * d
        hi = max_speed[i]
        lo = -hi
        if not (o >= lo or o != o):
            o = lo
        if not (o <= hi or o != o):
            o = hi
        pid_out[i] = o
        if has_prev_target:
            w = o + feedforward * ((t - prev_target[i]) / cycle)
        else:
            w = o + feedforward * 0.0
        if not (w >= lo or w != w):
            w = lo
        if not (w <= hi or w != w):
            w = hi
        v[i] = w

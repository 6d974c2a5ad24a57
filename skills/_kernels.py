"""The skills' hot loops, compiled with numba: one cycle of joint commands (target
fill-in, PID without its integral, feed-forward, clamps) in one pass, and the
closed-form leg IK.

Each repeats its Python original operation for operation (numpy's elementwise
operations; Python's min, max and float %; CPython's own math.hypot, which is not
libm's), so results are bit for bit theirs; what goes is the interpreter.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from models.jit import njit


@njit
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


@intrinsic
def _fma64(typingctx, a, b, c):
    """a * b + c with one rounding (LLVM's fma intrinsic)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        f64 = ir.DoubleType()
        fn = builder.module.declare_intrinsic("llvm.fma", [f64], ir.FunctionType(f64, [f64] * 3))
        return builder.call(fn, args)

    return sig, codegen


@njit
def _norm2(ax: float, ay: float, mx: float) -> float:
    e = math.frexp(mx)[1]
    scale = math.ldexp(1.0, -e)  # lossless scaling
    csum, frac1, frac2 = 1.0, 0.0, 0.0
    x = ax * scale
    hi = x * x  # lossless squaring (with its error lo), then compensated sums
    lo = _fma64(x, x, -hi)
    s = csum + hi
    frac2 += (csum - s) + hi
    csum = s
    frac1 += lo
    x = ay * scale
    hi = x * x
    lo = _fma64(x, x, -hi)
    s = csum + hi
    frac2 += (csum - s) + hi
    csum = s
    frac1 += lo
    h = math.sqrt(csum - 1.0 + (frac1 + frac2))
    hi = -h * h
    lo = _fma64(-h, h, -hi)
    s = csum + hi
    frac2 += (csum - s) + hi
    csum = s
    frac1 += lo
    x = csum - 1.0 + (frac1 + frac2)
    h += x / (2.0 * h)  # differential correction
    return h / scale


@njit
def py_hypot(x: float, y: float) -> float:
    """CPython's math.hypot(x, y) (its vector_norm, not libm's hypot), bit for bit."""
    ax, ay = abs(x), abs(y)
    if math.isinf(ax) or math.isinf(ay):
        return math.inf
    if math.isnan(ax) or math.isnan(ay):
        return math.nan
    mx = ay if ay > ax else ax
    if mx == 0.0:
        return mx
    if math.frexp(mx)[1] < -1023:  # subnormal: make it normal first
        d = 2.2250738585072014e-308
        return d * _norm2(ax / d, ay / d, mx / d)
    return _norm2(ax, ay, mx)


@njit
def _max2(a: float, b: float) -> float:
    """Python's max(a, b)."""
    return b if b > a else a


@njit
def _min2(a: float, b: float) -> float:
    """Python's min(a, b)."""
    return b if b < a else a


@njit
def _excess(a: float, lo: float, up: float) -> float:
    """Python's max(lo - a, a - up, 0.0)."""
    return _max2(_max2(lo - a, a - up), 0.0)


@njit
def _wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


@njit
def solve_leg(k: np.ndarray, r: float, p: float, y: float, px: float, py: float, pz: float, sole: bool,
              out: np.ndarray) -> bool:
    """`skills.ik.solve_leg` compiled, line for line (Python's min/max/% and CPython's
    hypot included): the joint angles into out (6,), returns whether reachable.
    k: `LegGeometry.kconsts`."""
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    r00, r01, r02 = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    r10, r11, r12 = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    r20, r21, r22 = -sp, cp * sr, cp * cr
    hipx, hipy, hipz, tilt, hx, hz, kx, kz = k[0], k[1], k[2], k[3], k[4], k[5], k[6], k[7]
    ox, oy, oz = k[8], k[9], k[10]
    reach_min, reach_max = k[23], k[24]
    lh2, lk2, den, q4_0, ct, st = k[25], k[26], k[27], k[28], k[29], k[30]
    if sole:
        px -= r00 * ox + r01 * oy + r02 * oz
        py -= r10 * ox + r11 * oy + r12 * oz
        pz -= r20 * ox + r21 * oy + r22 * oz
    dx, dy, dz = px - hipx, py - hipy, pz - hipz
    ux = r00 * dx + r10 * dy + r20 * dz
    uy = r01 * dx + r11 * dy + r21 * dz
    uz = r02 * dx + r12 * dy + r22 * dz
    reachable = True
    L = math.sqrt(ux * ux + uy * uy + uz * uz)
    if L > reach_max or L < reach_min:
        reachable = False
        if L < 1e-12:
            ux, uy, uz, L = 0.0, 0.0, -1.0, 1.0
        Lc = _min2(_max2(L, reach_min), reach_max)
        ux, uy, uz, L = ux * Lc / L, uy * Lc / L, uz * Lc / L, Lc
    c = (L * L - lh2 - lk2) / den
    q4 = q4_0 - math.acos(_min2(1.0, _max2(-1.0, c)))
    q6 = math.atan2(-uy, -uz)
    ryz = py_hypot(uy, uz)
    q6b = (q6 + math.pi + math.pi) % (2.0 * math.pi) - math.pi
    lo5, up5 = k[16], k[22]
    if _excess(q6b, lo5, up5) < _excess(q6, lo5, up5):
        q6, ryz = q6b, -ryz
    c4, s4 = math.cos(q4), math.sin(q4)
    wx = c4 * hx + s4 * hz + kx
    wz = -s4 * hx + c4 * hz + kz
    q5 = _wrap(math.atan2(wx, -wz) - math.atan2(ux, ryz))
    c6, s6 = math.cos(q6), math.sin(q6)
    c45, s45 = math.cos(q4 + q5), math.sin(q4 + q5)
    a01, a02 = c6 * r01 - s6 * r02, s6 * r01 + c6 * r02
    a11, a12 = c6 * r11 - s6 * r12, s6 * r11 + c6 * r12
    a21, a22 = c6 * r21 - s6 * r22, s6 * r21 + c6 * r22
    m00, m01, m02 = c45 * r00 - s45 * a02, a01, s45 * r00 + c45 * a02
    m10, m11, m12 = c45 * r10 - s45 * a12, a11, s45 * r10 + c45 * a12
    m20, m21 = c45 * r20 - s45 * a22, a21
    m22 = s45 * r20 + c45 * a22
    n00, n02 = m00, m02
    n01 = m01
    n10, n11, n12 = ct * m10 + st * m20, ct * m11 + st * m21, ct * m12 + st * m22
    n21 = -st * m11 + ct * m21
    sb_abs = py_hypot(n01, n21)
    b = math.atan2(sb_abs, n11)
    lo1, up1, bp, bm = k[12], k[18], b + tilt, -b + tilt
    sgn = 1.0 if _excess(bp, lo1, up1) <= _excess(bm, lo1, up1) else -1.0
    b *= sgn
    if sb_abs > 1e-9 or n11 < 0.0:
        q1 = math.atan2(sgn * n01, sgn * n21)
        gam = math.atan2(sgn * n10, -sgn * n12)
    else:
        q1 = 0.0
        gam = math.atan2(n02, n00)
    out[0], out[1], out[2], out[3], out[4], out[5] = q1, b + tilt, -gam, q4, q5, q6
    for i in range(6):
        a = out[i]
        qc = _min2(_max2(a, k[11 + i]), k[17 + i])
        if reachable and abs(a - qc) > 1e-9:
            reachable = False
        out[i] = qc
    return reachable

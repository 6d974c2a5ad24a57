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
                  prev_err: np.ndarray, has_prev_err: bool, kp: np.ndarray, ki: np.ndarray, kd: np.ndarray,
                  dt: float, max_speed: np.ndarray, feedforward: float, cycle: float, new_target: np.ndarray,
                  err: np.ndarray, pid_out: np.ndarray, v: np.ndarray) -> bool:
    """Joint velocities v (rad/s) toward `target` (NaN: hold the previous target, else the
    angle q) for a PID with gains kp, kd (no integral) whose last error was prev_err,
    plus feedforward times the target's rate of change over `cycle`; the PID's output
    and the sum each clamped at +-max_speed (as np.maximum then np.minimum). Also fills
    new_target (the targets used), err (their errors) and pid_out (the clamped PID);
    new_target may be prev_target and err prev_err (each is read before it is written).
    Returns False, having written nothing, when a gain of ki is not zero (an integral)."""
    for i in range(ki.shape[0]):
        if ki[i] != 0.0:
            return False
    for i in range(target.shape[0]):
        pt = prev_target[i] if has_prev_target else 0.0
        pe = prev_err[i] if has_prev_err else 0.0
        t = target[i]
        if t != t:
            if has_prev_target:
                t = q[i] if pt != pt else pt
            else:
                t = q[i]
        new_target[i] = t
        e = t - q[i]
        err[i] = e
        d = (e - pe) / dt if has_prev_err else 0.0
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
            w = o + feedforward * ((t - pt) / cycle)
        else:
            w = o + feedforward * 0.0
        if not (w >= lo or w != w):
            w = lo
        if not (w <= hi or w != w):
            w = hi
        v[i] = w
    return True


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


# ------------------------------------------------------------------------ the walk

# The walk parameters the walk kernels read, in the order of their params vector
# (`skills.walk.WalkEngine` builds it from a `WalkParams`), and their indices.
WALK_PARAMS = (
    "max_step_size_x", "max_step_size_y", "max_step_size_angle", "backward_factor",
    "pid_step_size_x", "pid_step_size_y", "pid_step_size_rot", "max_normal_com_error",
    "max_acceptable_com_error", "phase_length", "heading_gain", "walk_height", "fraction_still",
    "fraction_on_ground", "fraction_moving", "fraction_in_air", "gyro_roll", "gyro_pitch",
    "gyro_pitch_walk", "swing_steepness", "default_com_pos_x", "fwd_offset", "fwd_offset_factor",
    "shift_amount", "step_height", "pid_roll", "pid_tilt", "swing_ankle_offset", "arm_pitch",
    "pid_arm_x", "arm_roll", "toe_amplitude", "toe_phase_offset", "toe_const_offset",
    "ankle_amplitude", "ankle_phase_offset", "ankle_const_offset", "balance_step_x", "balance_step_y",
    "balance_deadband", "balance_fade", "backward_fraction_still", "slow_step_height",
)
(P_MAX_X, P_MAX_Y, P_MAX_A, P_BACKWARD, P_PID_X, P_PID_Y, P_PID_ROT, P_COM_NORMAL, P_COM_ACCEPT,
 P_PHASE_LENGTH, P_HEADING_GAIN, P_WALK_HEIGHT, P_F_STILL, P_F_GROUND, P_F_MOVING, P_F_AIR,
 P_GYRO_ROLL, P_GYRO_PITCH, P_GYRO_PITCH_WALK, P_STEEPNESS, P_COM_X, P_FWD_OFFSET, P_FWD_FACTOR,
 P_SHIFT, P_STEP_HEIGHT, P_PID_ROLL, P_PID_TILT, P_SWING_ANKLE, P_ARM_PITCH, P_PID_ARM_X,
 P_ARM_ROLL, P_TOE_AMP, P_TOE_PHASE, P_TOE_CONST, P_ANKLE_AMP, P_ANKLE_PHASE,
 P_ANKLE_CONST, P_BAL_X, P_BAL_Y, P_BAL_DEAD, P_BAL_FADE, P_BACK_STILL,
 P_SLOW_STEP_HEIGHT) = range(len(WALK_PARAMS))

# The walk engine's state vector: phase (start, end, now), the swinging foot (0 left,
# 1 right), step sizes x, y (m) and theta (rad), walking (0/1), s since zero velocity was
# asked, low-passed tilt and roll (rad), the CoM step factor, the gyro (rad/s, torso
# frame), heading error (rad), turn per phase (rad), latched side step (m) and turn (rad),
# whether the CoM the last targets put the body at is known (0/1), that CoM (m, 3), the
# swing foot's balance step (m, x and y, torso frame) and the stance foot's (the one it
# landed with, fading over the step).
(S_PHI_START, S_PHI_END, S_PHI, S_SWING, S_STEP_X, S_STEP_Y, S_STEP_TH, S_WALKING, S_STOP_TIME,
 S_TILT, S_ROLL, S_STEP_FACTOR, S_GYRO_X, S_GYRO_Y, S_GYRO_Z, S_HEADING_ERROR, S_TURN_STEP,
 S_LATCHED_Y, S_LATCHED_TH, S_HAS_EXPECTED_COM, S_EXPECTED_COM, S_BAL_X, S_BAL_Y, S_BAL_STANCE_X,
 S_BAL_STANCE_Y, WALK_STATE) = (*range(21), *range(23, 28))

# Joint indices of the walk's targets (`WalkEngine._idx`): left then right leg lj1..lj6,
# arm joints laj1, raj1, laj2, raj2, laj3, raj3, laj4, raj4, then whether the robot has
# toes, and left toe, left ankle pitch, right toe, right ankle pitch.
I_LEGS, I_ARMS, I_HAS_TOE, I_TOES = 0, 12, 20, 21

_G = 9.80665  # m/s^2, as `skills.walk.G`
_FOOT_SEPARATION = 0.10  # `skills.walk.FOOT_SEPARATION`
_STOP_JOG_TIME = 0.5  # `skills.walk.STOP_JOG_TIME`
_STAND_DAMP_TIME = 1.0  # `skills.walk.STAND_DAMP_TIME`
_STAND_DAMP_FADE = 0.5  # `skills.walk.STAND_DAMP_FADE`
_BALANCE_SMOOTHING = 0.3  # `skills.walk.BALANCE_SMOOTHING`
_BALANCE_STEP_OUT = 0.06  # `skills.walk.BALANCE_STEP_OUT`
_BALANCE_STEP_IN = 0.02  # `skills.walk.BALANCE_STEP_IN`


@njit
def _clip(v: float, lo: float, hi: float) -> float:
    """`skills.walk._clip`: lo if v < lo else hi if v > hi else v (NaN stays NaN)."""
    return lo if v < lo else hi if v > hi else v


@njit
def _sigmoid(v: float) -> float:
    return 1.0 / (1.0 + math.exp(-v))


@njit
def walk_feet(s: np.ndarray, p: np.ndarray, hips: np.ndarray, standing: bool, feet: np.ndarray) -> None:
    """`skills.walk.WalkEngine.foot_targets` for state s and params p: feet[side] = ankle
    position (m) then foot roll, pitch, yaw (rad), torso frame; side 0 left, 1 right.
    hips: (2, >=3), each side's hip center first."""
    phi_start, phi_end = s[S_PHI_START], s[S_PHI_END]
    t = 0.0 if standing else (s[S_PHI] - phi_start) / (phi_end - phi_start)
    t = _min2(_max2(t, 0.0), 1.0)
    k = math.sqrt(_G / p[P_WALK_HEIGHT])
    fs, fg = _min2(p[P_F_STILL], 0.9), _min2(p[P_F_GROUND], 0.9)
    fm, fa = _min2(p[P_F_MOVING], 1.0 - fs), _min2(p[P_F_AIR], 1.0 - fg)
    if standing:
        sx, sy, sth = 0.0, 0.0, 0.0
    else:
        sx, sy, sth = s[S_STEP_X], s[S_LATCHED_Y], s[S_LATCHED_TH]
    swing = int(s[S_SWING])
    stance = 1 - swing
    fade = 1.0
    if standing:
        fade = _min2(_max2((_STAND_DAMP_TIME + _STAND_DAMP_FADE - s[S_STOP_TIME]) / _STAND_DAMP_FADE, 0.0),
                     1.0)
    gyro_roll, gyro_pitch = fade * p[P_GYRO_ROLL], fade * p[P_GYRO_PITCH]
    gyro_pitch += p[P_GYRO_PITCH_WALK] * _min2(1.0, abs(sx) / _max2(p[P_MAX_X], 1e-9))
    zfrac = 0.5 * (1 - math.cos(2 * math.pi * (t - fg) / fa)) if fg <= t <= fg + fa else 0.0
    xs, xm = fs, fm  # a backward swing may start sooner (backward_fraction_still; < 0: fs)
    if sx < 0.0 and p[P_BACK_STILL] >= 0.0:
        xs = _min2(p[P_BACK_STILL], 0.9)
        xm = _min2(p[P_F_MOVING], 1.0 - xs)
    if t < xs:
        xfrac = -0.5 - t
    elif t < xs + xm:
        c = p[P_STEEPNESS]
        sg = _sigmoid(c * (-0.5 + (t - xs) / xm))
        s0, s1 = _sigmoid(-0.5 * c), _sigmoid(0.5 * c)
        sg = (sg - s0) / (s1 - s0)
        xfrac = (-0.5 - xs) + sg * ((1.5 - xs - xm) - (-0.5 - xs))
    else:
        xfrac = 1.5 - t
    x_stance, x_swing = sx * (0.5 - t), sx * xfrac
    dx = p[P_COM_X] + p[P_FWD_OFFSET] - sx * p[P_FWD_FACTOR]
    phi = phi_start if standing else s[S_PHI]
    shift = 0.0 if standing else p[P_SHIFT] * (-1.5 + 0.5 * math.cosh(0.5 * k * phi))
    y_stance = 0.5 * _FOOT_SEPARATION + shift
    y_swing = _FOOT_SEPARATION - y_stance
    if t < fs:
        yfrac = 0.0
    elif t < fs + fm:
        yfrac = 0.5 * (1 - math.cos(math.pi * (t - fs) / fm))
    else:
        yfrac = 1.0
    lead = 0 if sy > 0 else 1
    a = abs(sy)
    swing_out = a * yfrac if swing == lead else a * (1.0 - yfrac)
    stance_out = a * (1.0 - t) if stance == lead else a * t
    groin = 0.0
    if t >= fs + fm:
        groin = abs(sth)
    elif t >= fs:
        groin = 0.5 * abs(sth) * (1 - math.cos(math.pi * (t - fs) / fm))
    tlead = 1 if sth > 0 else 0
    swing_yaw = groin if swing == tlead else abs(sth) - groin
    stance_yaw = abs(sth) * (1.0 - t) if stance == tlead else abs(sth) * t
    z_swing = _lift(p, sx, sy, sth) * zfrac
    for j in range(2):
        if j == 0:
            side, xo, yo, out_y, yaw, z = swing, x_swing, y_swing, swing_out, swing_yaw, z_swing
        else:
            side, xo, yo, out_y, yaw, z = stance, x_stance, y_stance, stance_out, stance_yaw, 0.0
        sign = 1.0 if side == 0 else -1.0
        f = feet[side]
        f[0] = hips[side, 0] + xo + dx
        f[1] = sign * (yo + out_y)
        f[2] = hips[side, 2] - p[P_WALK_HEIGHT] + z
        f[3] = p[P_PID_ROLL] * s[S_ROLL] + gyro_roll * s[S_GYRO_X]
        f[4] = p[P_PID_TILT] * s[S_TILT] + gyro_pitch * s[S_GYRO_Y]
        f[5] = -sign * yaw
        if j == 0 and not standing:  # toes up stepping forward, down stepping back
            f[4] += p[P_SWING_ANKLE] * zfrac * (1.0 if sx >= 0 else -1.0)
            f[0] += s[S_BAL_X] * yfrac
            f[1] += s[S_BAL_Y] * yfrac
        elif not standing:  # the torso moves over where the foot landed as the step goes on
            fade = _max2(0.0, 1.0 - t / _max2(p[P_BAL_FADE], 1e-9))
            f[0] += s[S_BAL_STANCE_X] * fade
            f[1] += s[S_BAL_STANCE_Y] * fade


@njit
def _lift(p: np.ndarray, sx: float, sy: float, sth: float) -> float:
    """The swing foot's lift (m): step_height, or with slow_step_height >= 0 that height in
    place growing to step_height with the step's largest share of its bound (x, y, turn)."""
    h, low = p[P_STEP_HEIGHT], p[P_SLOW_STEP_HEIGHT]
    if low < 0.0:
        return h
    bx = p[P_MAX_X] * (p[P_BACKWARD] if sx < 0.0 else 1.0)
    r = _max2(abs(sx) / _max2(bx, 1e-9),
              _max2(abs(sy) / _max2(p[P_MAX_Y], 1e-9), abs(sth) / _max2(p[P_MAX_A], 1e-9)))
    return low + (h - low) * _min2(r, 1.0)


@njit
def _dead(v: float, band: float) -> float:
    """v less `band` toward zero (0 within it)."""
    return v - band if v > band else v + band if v < -band else 0.0


@njit
def _balance_step(s: np.ndarray, p: np.ndarray) -> None:
    """The swing foot's balance step into the state: its offset (m, torso frame x, y)
    toward where the torso leans (tilt forward, roll rightward positive; rad) beyond the
    deadband, out at most `_BALANCE_STEP_OUT`, inward `_BALANCE_STEP_IN`."""
    band = p[P_BAL_DEAD]
    sign = 1.0 if s[S_SWING] == 0.0 else -1.0  # the left foot swings: +y is out
    s[S_BAL_X] = _clip(p[P_BAL_X] * _dead(s[S_TILT], band), -_BALANCE_STEP_OUT, _BALANCE_STEP_OUT)
    out = _clip(-sign * p[P_BAL_Y] * _dead(s[S_ROLL], band), -_BALANCE_STEP_IN, _BALANCE_STEP_OUT)
    s[S_BAL_Y] = sign * out


@njit
def walk_targets(s: np.ndarray, p: np.ndarray, legs: np.ndarray, idx: np.ndarray, standing: bool,
                 feet: np.ndarray, q: np.ndarray, full: np.ndarray) -> None:
    """`skills.walk.WalkEngine._targets`: the joint targets q (rad, league order; NaN
    where the walk leaves a joint alone) and full, q with 0 for NaN (for the expected
    CoM). legs: each side's `LegGeometry.kconsts`; feet: scratch (2, 6)."""
    walk_feet(s, p, legs, standing, feet)
    q[:] = np.nan
    q6 = np.empty(6)
    swing = int(s[S_SWING])
    for side in (swing, 1 - swing):
        f = feet[side]
        solve_leg(legs[side], f[3], f[4], f[5], f[0], f[1], f[2], False, q6)
        for i in range(6):
            q[idx[I_LEGS + 6 * side + i]] = q6[i]
    swing_x = feet[0, 0] - feet[1, 0]
    q[idx[I_ARMS]] = p[P_ARM_PITCH] - p[P_PID_ARM_X] * swing_x
    q[idx[I_ARMS + 1]] = p[P_ARM_PITCH] + p[P_PID_ARM_X] * swing_x
    q[idx[I_ARMS + 2]] = p[P_ARM_ROLL]
    q[idx[I_ARMS + 3]] = -p[P_ARM_ROLL]
    for i in range(4, 8):
        q[idx[I_ARMS + i]] = 0.0
    if idx[I_HAS_TOE]:
        t = 0.0 if standing else (s[S_PHI] - s[S_PHI_START]) / (s[S_PHI_END] - s[S_PHI_START])
        toe = p[P_TOE_AMP] * math.cos(t * math.pi + p[P_TOE_PHASE]) + p[P_TOE_CONST]
        ank = p[P_ANKLE_AMP] * math.cos(t * math.pi + p[P_ANKLE_PHASE]) + p[P_ANKLE_CONST]
        for side in range(2):
            q[idx[I_TOES + 2 * side]] = toe
            q[idx[I_TOES + 2 * side + 1]] += ank
    for i in range(q.shape[0]):
        full[i] = 0.0 if q[i] != q[i] else q[i]


@njit
def walk_update(s: np.ndarray, p: np.ndarray, legs: np.ndarray, idx: np.ndarray, x: float, y: float,
                turn: float, tilt: float, roll: float, gyro: np.ndarray, has_gyro: bool, joints: np.ndarray,
                has_joints: bool, com_int: np.ndarray, com_float: np.ndarray, dt: float, feet: np.ndarray,
                q: np.ndarray, full: np.ndarray) -> tuple[bool, float, float, float]:
    """`skills.walk.WalkEngine.update`: one cycle of state s for inputs x, y, turn in
    [-1, 1], tilt and roll (rad), the gyro (rad/s; zeros when not has_gyro) and, when
    has_joints, the measured angles (rad, league order) whose CoM (`center_of_mass` over
    com_int, com_float) against the expected one shrinks the steps. Fills q and full as
    `walk_targets` and the expected CoM of full into s; returns (standing, odometry dx,
    dy, dtheta) (m, m, rad)."""
    mx, my, ma = p[P_MAX_X], p[P_MAX_Y], p[P_MAX_A]
    dx = _clip(x, -1.0, 1.0) * mx
    dy = _clip(y, -1.0, 1.0) * my
    dt_ = _clip(turn, -1.0, 1.0) * ma
    if dx < 0:
        dx *= p[P_BACKWARD]
    moving = abs(dx) > 1e-9 or abs(dy) > 1e-9 or abs(dt_) > 1e-9
    s[S_STOP_TIME] = 0.0 if moving else s[S_STOP_TIME] + dt
    s0, s1, s2 = s[S_STEP_X], s[S_STEP_Y], s[S_STEP_TH]
    s0 = _clip(s0 + p[P_PID_X] * (dx - s0), -mx, mx)
    s1 = _clip(s1 + p[P_PID_Y] * (dy - s1), -my, my)
    s2 = _clip(s2 + p[P_PID_ROT] * (dt_ - s2), -ma, ma)
    if has_joints and s[S_HAS_EXPECTED_COM] != 0.0:
        com = np.empty(3)
        center_of_mass(joints, com_int, com_float, com)
        err = _max2(abs(com[0] - s[S_EXPECTED_COM]), abs(com[1] - s[S_EXPECTED_COM + 1]))
        span = _max2(p[P_COM_ACCEPT] - p[P_COM_NORMAL], 1e-6)
        f = 1.0 - _min2(1.0, _max2(0.0, (err - p[P_COM_NORMAL]) / span))
        s[S_STEP_FACTOR] = f
        s0, s1, s2 = s0 * f, s1 * f, s2 * f
    s[S_STEP_X], s[S_STEP_Y], s[S_STEP_TH] = s0, s1, s2
    s[S_TILT] += _BALANCE_SMOOTHING * (tilt - s[S_TILT])
    s[S_ROLL] += _BALANCE_SMOOTHING * (roll - s[S_ROLL])
    s[S_GYRO_X], s[S_GYRO_Y], s[S_GYRO_Z] = gyro[0], gyro[1], gyro[2]
    if not moving and s[S_STOP_TIME] >= _STOP_JOG_TIME:
        s[S_WALKING] = 0.0
        s[S_HEADING_ERROR] = 0.0
        s[S_TURN_STEP] = 0.0
        s[S_PHI] = s[S_PHI_START]
        s[S_STEP_X], s[S_STEP_Y], s[S_STEP_TH] = 0.0, 0.0, 0.0
        s[S_BAL_X], s[S_BAL_Y], s[S_BAL_STANCE_X], s[S_BAL_STANCE_Y] = 0.0, 0.0, 0.0, 0.0
        walk_targets(s, p, legs, idx, True, feet, q, full)
        _expect_com(s, full, com_int, com_float)
        return True, 0.0, 0.0, gyro[2] * dt if has_gyro else 0.0
    new_phase = s[S_WALKING] == 0.0
    s[S_WALKING] = 1.0
    s[S_PHI] += dt / p[P_PHASE_LENGTH]
    if s[S_PHI] >= s[S_PHI_END]:
        walk_swap(s, p)
        new_phase = True
    span = s[S_PHI_END] - s[S_PHI_START]
    frac = dt / (p[P_PHASE_LENGTH] * span)
    turned = gyro[2] * dt if has_gyro else s[S_TURN_STEP] * frac
    s[S_HEADING_ERROR] += turned - s2 * frac
    limit = p[P_MAX_A]
    wanted_turn = _clip(s2 - p[P_HEADING_GAIN] * s[S_HEADING_ERROR], -limit, limit)
    if new_phase:  # side step and turn are fixed for a whole step
        s[S_LATCHED_Y], s[S_LATCHED_TH] = s1, wanted_turn
    s[S_TURN_STEP] = s[S_LATCHED_TH]
    _balance_step(s, p)
    walk_targets(s, p, legs, idx, False, feet, q, full)
    _expect_com(s, full, com_int, com_float)
    return False, s0 * frac, s[S_LATCHED_Y] * frac, turned


@njit
def _expect_com(s: np.ndarray, full: np.ndarray, com_int: np.ndarray, com_float: np.ndarray) -> None:
    """The CoM (m, torso frame) the targets `full` put the body at, into the state."""
    center_of_mass(full, com_int, com_float, s[S_EXPECTED_COM:S_EXPECTED_COM + 3])
    s[S_HAS_EXPECTED_COM] = 1.0


@njit
def walk_swap(s: np.ndarray, p: np.ndarray) -> None:
    """`skills.walk.WalkEngine._swap`: the feet swap roles; the new pendulum phase starts
    where its lateral position matches the old one's end."""
    k = math.sqrt(_G / p[P_WALK_HEIGHT])
    alpha = 6.0 - math.cosh(0.5 * k * s[S_PHI_END])
    start = -math.acosh(alpha) / (0.5 * k) if alpha >= 1.0 else -0.5
    start = _max2(start, -0.5)
    s[S_PHI_START], s[S_PHI_END] = start, -start
    s[S_PHI] = start
    s[S_SWING] = 1.0 - s[S_SWING]
    s[S_BAL_STANCE_X], s[S_BAL_STANCE_Y] = s[S_BAL_X], s[S_BAL_Y]  # the swing foot has landed


# ---------------------------------------------------------------------- the IMU

# `skills.imu.TiltEstimator`'s state vector: roll and pitch (rad), the low-passed
# accelerometer (m/s^2, torso frame), started (0/1).
T_ROLL, T_PITCH, T_ACC, T_STARTED, TILT_STATE = 0, 1, 2, 5, 6
TILT_OK, TILT_SKIPPED, TILT_DOMAIN_ERROR = 0, 1, 2  # what `tilt_update` returns


@njit
def py_remainder(x: float, y: float) -> float:
    """CPython's math.remainder(x, y) for finite x and finite, nonzero y (its m_remainder;
    IEEE's remainder is exact, so any correct one agrees); NaN x gives NaN."""
    if x != x:
        return x
    absx, absy = abs(x), abs(y)
    m = np.fmod(absx, absy)
    c = absy - m
    if m < c:
        r = m
    elif m > c:
        r = -c
    else:  # halfway: the even multiple
        r = m - 2.0 * np.fmod(0.5 * (absx - m), absy)
    return math.copysign(1.0, x) * r


@njit
def tilt_update(st: np.ndarray, gyro: np.ndarray, accel: np.ndarray, dt: float, blend: float,
                smoothing: float, exact: bool) -> int:
    """`skills.imu.TiltEstimator.update` line for line on state st: gyro (rad/s) and
    accelerometer (m/s^2) in the torso frame, dt in s. Returns TILT_SKIPPED (accelerometer
    not finite: nothing changed) or TILT_DOMAIN_ERROR (where math.remainder raises, an
    infinite roll: the accelerometer's low-pass moved, roll and pitch did not), else TILT_OK."""
    ax, ay, az = accel[0], accel[1], accel[2]
    if not (math.isfinite(ax) and math.isfinite(ay) and math.isfinite(az)):
        return TILT_SKIPPED
    a = st[T_ACC:T_ACC + 3]
    started = st[T_STARTED] != 0.0
    if started:
        a[0] += smoothing * (ax - a[0])
        a[1] += smoothing * (ay - a[1])
        a[2] += smoothing * (az - a[2])
    else:
        a[0], a[1], a[2] = ax, ay, az
    acc_roll, acc_pitch = math.atan2(a[1], a[2]), math.atan2(-a[0], py_hypot(a[1], a[2]))
    if not started:
        st[T_ROLL], st[T_PITCH], st[T_STARTED] = acc_roll, acc_pitch, 1.0
        return TILT_OK
    gx, gy, gz = gyro[0], gyro[1], gyro[2]
    if exact:  # the up direction turns as -omega x up
        cp = math.cos(st[T_PITCH])
        ux, uy, uz = -math.sin(st[T_PITCH]), cp * math.sin(st[T_ROLL]), cp * math.cos(st[T_ROLL])
        vx = ux - (gy * uz - gz * uy) * dt
        vy = uy - (gz * ux - gx * uz) * dt
        vz = uz - (gx * uy - gy * ux) * dt
        roll, pitch = math.atan2(vy, vz), math.atan2(-vx, py_hypot(vy, vz))
    else:  # small-angle Euler rates
        roll = st[T_ROLL] + gx * dt
        pitch = st[T_PITCH] + gy * dt
    x = acc_roll - roll
    if math.isinf(x):
        return TILT_DOMAIN_ERROR
    x = roll + blend * py_remainder(x, 2 * math.pi)
    if math.isinf(x):
        return TILT_DOMAIN_ERROR
    st[T_ROLL] = py_remainder(x, 2 * math.pi)
    st[T_PITCH] = pitch + blend * (acc_pitch - pitch)
    return TILT_OK


# ------------------------------------------------------------ center of mass

# Joint kinds of `center_of_mass`'s tree (pinocchio's joint models).
J_RX, J_RY, J_RZ, J_UNALIGNED, J_FREE = 0, 1, 2, 3, 4


@njit
def _dot_row(r0: float, r1: float, r2: float, v0: float, v1: float, v2: float, row: int) -> float:
    """Row `row` of a 3x3 by 3 product in Eigen's order: rows 0 and 1 as packets
    ((a0 + a1) + a2), row 2 as a reduction (a0 + (a1 + a2))."""
    if row < 2:
        return (r0 * v0 + r1 * v1) + r2 * v2
    return r0 * v0 + (r1 * v1 + r2 * v2)


@njit
def center_of_mass(q: np.ndarray, ijoint: np.ndarray, fjoint: np.ndarray, out: np.ndarray) -> None:
    """Center of mass (m, torso frame) into out (3,) for league-order angles q (rad), as
    pinocchio's centerOfMass(model, data, q, False) computes it, bit for bit: each joint's
    placement in its parent (liMi, pinocchio's products) and the backward sum of
    subtree moments com[parent] += R com[i] + m[i] t, divided by the total mass.

    ijoint (njoints, 3): kind (J_RX ...), parent, league index of the angle (-1: none);
    fjoint (njoints, 19): placement rotation (row-major 9) and translation (3), the
    unaligned axis (3), mass times lever (3) and the subtree's mass (1). Row 0 is the
    universe; the free flyer stays at the identity."""
    n = ijoint.shape[0]
    com = np.zeros((n, 3))
    for i in range(1, n):
        com[i, 0], com[i, 1], com[i, 2] = fjoint[i, 15], fjoint[i, 16], fjoint[i, 17]
    r = np.empty(9)
    for i in range(n - 1, 0, -1):
        kind, parent, qi = ijoint[i, 0], ijoint[i, 1], ijoint[i, 2]
        f = fjoint[i]
        # liMi: rotation r (row-major) and translation t = placement translation.
        if kind <= J_RZ:
            a = q[qi]
            s, c = math.sin(a), math.cos(a)
            # pinocchio's se3Action: the placement's column i0 kept, i1 turned toward i2, and
            # i2 the cross product of the two.
            if kind == J_RX:
                i0, i1, i2 = 0, 1, 2
            elif kind == J_RY:
                i0, i1, i2 = 1, 2, 0
            else:
                i0, i1, i2 = 2, 0, 1
            for k in range(3):
                r[3 * k + i0] = f[3 * k + i0]
                r[3 * k + i1] = c * f[3 * k + i1] + s * f[3 * k + i2]
            for k in range(3):  # column i2 = column i0 x column i1 (Eigen's cross)
                k1, k2 = (k + 1) % 3, (k + 2) % 3
                r[3 * k + i2] = r[3 * k1 + i0] * r[3 * k2 + i1] - r[3 * k2 + i0] * r[3 * k1 + i1]
            tx, ty, tz = f[9], f[10], f[11]
        else:
            if kind == J_UNALIGNED:
                a = q[qi]
                s, c = math.sin(a), math.cos(a)
                ax, ay, az = f[12], f[13], f[14]
                sx, sy, sz = s * ax, s * ay, s * az
                cx, cy, cz = (1.0 - c) * ax, (1.0 - c) * ay, (1.0 - c) * az
                tmp = cx * ay
                m01, m10 = tmp - sz, tmp + sz
                tmp = cx * az
                m02, m20 = tmp + sy, tmp - sy
                tmp = cy * az
                m12, m21 = tmp - sx, tmp + sx
                m00, m11, m22 = cx * ax + c, cy * ay + c, cz * az + c
            else:  # the free flyer at the identity
                m00, m01, m02, m10, m11, m12, m20, m21, m22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
            for k in range(3):  # placement rotation times the joint's
                r[3 * k] = _dot_row(f[3 * k], f[3 * k + 1], f[3 * k + 2], m00, m10, m20, k)
                r[3 * k + 1] = _dot_row(f[3 * k], f[3 * k + 1], f[3 * k + 2], m01, m11, m21, k)
                r[3 * k + 2] = _dot_row(f[3 * k], f[3 * k + 1], f[3 * k + 2], m02, m12, m22, k)
            # translation + rotation times the joint's zero translation
            tx = f[9] + _dot_row(f[0], f[1], f[2], 0.0, 0.0, 0.0, 0)
            ty = f[10] + _dot_row(f[3], f[4], f[5], 0.0, 0.0, 0.0, 1)
            tz = f[11] + _dot_row(f[6], f[7], f[8], 0.0, 0.0, 0.0, 2)
        m = f[18]
        c0, c1, c2 = com[i, 0], com[i, 1], com[i, 2]
        com[parent, 0] += _dot_row(r[0], r[1], r[2], c0, c1, c2, 0) + m * tx
        com[parent, 1] += _dot_row(r[3], r[4], r[5], c0, c1, c2, 1) + m * ty
        com[parent, 2] += _dot_row(r[6], r[7], r[8], c0, c1, c2, 2) + m * tz
    total = fjoint[0, 18]
    out[0], out[1], out[2] = com[0, 0] / total, com[0, 1] / total, com[0, 2] / total


# -------------------------------------------------------- one walk step, whole

STEP_OK, STEP_TILT_ERROR, STEP_NO_COMMAND = 0, 1, 2  # what `walk_step` returns first


@njit
def walk_step(tilt: np.ndarray, gyro: np.ndarray, accel: np.ndarray, tilt_dt: float, blend: float,
              smoothing: float, exact: bool, x: float, y: float, turn: float, joints: np.ndarray,
              s: np.ndarray, p: np.ndarray, legs: np.ndarray, idx: np.ndarray, com_int: np.ndarray,
              com_float: np.ndarray, dt: float, feet: np.ndarray, full: np.ndarray, q: np.ndarray,
              prev_target: np.ndarray, has_prev_target: bool, prev_err: np.ndarray, has_prev_err: bool,
              kp: np.ndarray, ki: np.ndarray, kd: np.ndarray, pid_dt: float, max_speed: np.ndarray,
              feedforward: float, cycle: float, new_target: np.ndarray, err: np.ndarray,
              pid_out: np.ndarray, v: np.ndarray) -> tuple[int, bool, float, float, float]:
    """`skills.motion.Motion.walk_step` in one call: `tilt_update` of the tilt state, then
    `walk_update` with its pitch and roll, the gyro and the measured joints (targets into
    q), then `joint_command` toward q (velocities into v). Returns (STEP_TILT_ERROR, ...)
    having done nothing more when the tilt update would raise, (STEP_NO_COMMAND, ...) with
    the walk done but no command when ki is not zero, else STEP_OK; then the walk's
    standing and odometry."""
    if tilt_update(tilt, gyro, accel, tilt_dt, blend, smoothing, exact) == TILT_DOMAIN_ERROR:
        return STEP_TILT_ERROR, False, 0.0, 0.0, 0.0
    standing, ox, oy, oth = walk_update(s, p, legs, idx, x, y, turn, tilt[T_PITCH], tilt[T_ROLL], gyro, True,
                                        joints, True, com_int, com_float, dt, feet, q, full)
    done = joint_command(q, joints, prev_target, has_prev_target, prev_err, has_prev_err, kp, ki, kd, pid_dt,
                         max_speed, feedforward, cycle, new_target, err, pid_out, v)
    return STEP_OK if done else STEP_NO_COMMAND, standing, ox, oy, oth

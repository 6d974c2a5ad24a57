"""The agent's hot loops, compiled with numba: the particle filter's odometry step
and its line-matching scores.

Each repeats its numpy original operation for operation (same order, same float
widths, the same libm calls), so results are bit for bit those of the array code
they replace; what goes is the dozen temporary arrays a call made. Random draws
stay with the caller's numpy generator.
"""

from __future__ import annotations

import ctypes
import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic
from numba.np.random import _constants as _zig

from models.jit import njit

TWO_PI = 2.0 * math.pi


# Random draws: the particle filter's come from its numpy Generator's PCG64, stepped
# here on the generator's own state, so they are the Generator's stream draw for draw
# (numpy's ziggurat for normals, its Lemire method for integers) without a Python call
# per batch. `gen` holds the addresses (PCG64 state, its next_uint32), see `bitgen_addresses`.

_PCG64_MULT = (2549297995355413924 << 64) + 4865540595714422341  # PCG_DEFAULT_MULTIPLIER_128


@intrinsic
def _pcg64_next(typingctx, state):
    """numpy's pcg64_next64 on the pcg64_state at address `state`: one 128-bit LCG step
    (state * mult + inc), then the XSL-RR output (high ^ low, rotated right by the top
    six bits of the state)."""
    def codegen(context, builder, signature, args):
        i128, i64 = ir.IntType(128), ir.IntType(64)
        rng = builder.load(builder.inttoptr(args[0], i128.as_pointer().as_pointer()))  # -> {state, inc}
        inc = builder.load(builder.gep(rng, [ir.Constant(ir.IntType(32), 1)]), align=8)
        new = builder.add(builder.mul(builder.load(rng, align=8), ir.Constant(i128, _PCG64_MULT)), inc)
        builder.store(new, rng, align=8)
        x = builder.xor(builder.trunc(builder.lshr(new, ir.Constant(i128, 64)), i64), builder.trunc(new, i64))
        rot = builder.trunc(builder.lshr(new, ir.Constant(i128, 122)), i64)
        fshr = builder.module.declare_intrinsic("llvm.fshr", [i64], ir.FunctionType(i64, [i64] * 3))
        return builder.call(fshr, [x, x, rot])
    return types.uint64(types.intp), codegen


@intrinsic
def _call_uint32(typingctx, fn, state):
    """The C function uint32_t fn(void *state) at address fn."""
    def codegen(context, builder, signature, args):
        void_p = ir.IntType(8).as_pointer()
        f = builder.inttoptr(args[0], ir.FunctionType(ir.IntType(32), [void_p]).as_pointer())
        return builder.call(f, [builder.inttoptr(args[1], void_p)])
    return types.uint32(types.intp, types.intp), codegen


# numpy's ziggurat tables for standard normal draws (numba's copy of numpy's
# ziggurat_constants.h).
_KI = np.array(_zig.ki_double, dtype=np.uint64)
_WI = np.array(_zig.wi_double, dtype=np.float64)
_FI = np.array(_zig.fi_double, dtype=np.float64)
_ZIG_R = 3.6541528853610087963519472518
_ZIG_INV_R = 0.27366123732975827203338247596


def bitgen_addresses(rng: np.random.Generator) -> np.ndarray:
    """The addresses (state, next_uint32) of rng's PCG64 bit generator."""
    if not isinstance(rng.bit_generator, np.random.PCG64):
        raise TypeError(f"the compiled draws step PCG64 only, not {type(rng.bit_generator).__name__}")
    c = rng.bit_generator.ctypes
    return np.array([c.state_address, ctypes.cast(c.next_uint32, ctypes.c_void_p).value], dtype=np.intp)


@njit
def uniform_draw(st: int) -> float:
    """`Generator.random()` of the PCG64 state at st: one draw in [0, 1) (pcg64_next_double)."""
    return np.float64(_pcg64_next(st) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@njit
def normal_draw(st: int) -> float:
    """`Generator.standard_normal()` of the PCG64 state at st: numpy's ziggurat
    (random_standard_normal), step for step; the rare rejections in `_normal_rejected`."""
    r = _pcg64_next(st)
    idx = r & np.uint64(0xff)
    r >>= np.uint64(8)
    sign = r & np.uint64(1)
    rabs = (r >> np.uint64(1)) & np.uint64(0x000fffffffffffff)
    # x or -x, bit for bit, as a product: a branch on the sign's coin flip mispredicts
    x = rabs * _WI[idx] * (1.0 - 2.0 * np.float64(sign))
    if rabs < _KI[idx]:
        return x
    return _normal_rejected(st, idx, rabs, x)


@njit
def _normal_rejected(st: int, idx: int, rabs: int, x: float) -> float:
    """The ziggurat's slow path for a first draw outside its box (idx, rabs, x), and its
    further draws until one is accepted."""
    while True:
        if idx == 0:
            while True:
                xx = -_ZIG_INV_R * math.log1p(-uniform_draw(st))
                yy = -math.log1p(-uniform_draw(st))
                if yy + yy > xx * xx:
                    if (rabs >> np.uint64(8)) & np.uint64(1):
                        return -(_ZIG_R + xx)
                    return _ZIG_R + xx
        elif (_FI[idx - 1] - _FI[idx]) * uniform_draw(st) + _FI[idx] < math.exp(-0.5 * x * x):
            return x
        r = _pcg64_next(st)
        idx = r & np.uint64(0xff)
        r >>= np.uint64(8)
        sign = r & np.uint64(1)
        rabs = (r >> np.uint64(1)) & np.uint64(0x000fffffffffffff)
        x = rabs * _WI[idx] * (1.0 - 2.0 * np.float64(sign))
        if rabs < _KI[idx]:
            return x


@njit
def integer_draw(gen: np.ndarray, low: int, high: int) -> int:
    """`Generator.integers(low, high)` for 0 < high - low < 2^32: numpy's Lemire method on
    32-bit draws (random_bounded_uint64_fill); no draw when high - low is 1."""
    rng = np.uint64(high - low - 1)
    if rng == 0:
        return low
    excl = rng + np.uint64(1)
    m = np.uint64(_call_uint32(gen[1], gen[0])) * excl
    left = m & np.uint64(0xFFFFFFFF)
    if left < excl:
        threshold = (np.uint64(0xFFFFFFFF) - rng) % excl
        while left < threshold:
            m = np.uint64(_call_uint32(gen[1], gen[0])) * excl
            left = m & np.uint64(0xFFFFFFFF)
    return low + np.int64(m >> np.uint64(32))


@njit
def predict_particles(p: np.ndarray, pose: np.ndarray, gen: np.ndarray, ex: float, ey: float, et: float,
                      nx: float, ny: float, nt: float) -> None:
    """Move particles p (n, 3: x, y, heading) in place by an odometry step (ex, ey, et)
    (already scaled) perturbed by standard normal draws from gen (n rows of 3, as
    `Generator.standard_normal((n, 3))`) times (nx, ny, nt), headings wrapped into
    [-pi, pi); and the estimate pose (3,) by the step itself (`Pose2.to_world`, `wrap`)."""
    st = gen[0]
    for i in range(p.shape[0]):
        ddx = ex * (1.0 + nx * normal_draw(st))
        ddy = ey * (1.0 + ny * normal_draw(st))
        ddt = et * (1.0 + nt * normal_draw(st))
        t = p[i, 2]
        c, s = math.cos(t), math.sin(t)
        p[i, 0] += c * ddx - s * ddy
        p[i, 1] += s * ddx + c * ddy
        a = t + ddt + math.pi
        if not 0.0 <= a < TWO_PI:  # inside, a % TWO_PI is a itself (fmod is exact): skip it
            a = a % TWO_PI
        p[i, 2] = a - math.pi
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x = pose[0] + c * ex - s * ey
    y = pose[1] + s * ex + c * ey
    pose[0], pose[1] = x, y
    pose[2] = (pose[2] + et + math.pi) % TWO_PI - math.pi


def _fma_intrinsic(nb_type, ll_type):
    """An intrinsic a * b + c with one rounding (LLVM's fma) for one float type."""

    @intrinsic
    def fma(typingctx, a, b, c):
        def codegen(context, builder, signature, args):
            fma_type = ir.FunctionType(ll_type, [ll_type] * 3)
            return builder.call(builder.module.declare_intrinsic("llvm.fma", [ll_type], fma_type), args)

        return nb_type(nb_type, nb_type, nb_type), codegen

    return fma


_fma32 = _fma_intrinsic(types.float32, ir.FloatType())
_fma64 = _fma_intrinsic(types.float64, ir.DoubleType())


@njit
def line_scores(b: np.ndarray, q: np.ndarray, m: int, k: int, reach: np.ndarray, ratio2: np.ndarray,
                out: np.ndarray) -> None:
    """Per particle, the sum over k observed lines of the best (lowest) score over m
    known lines (`ParticleFilter.log_likelihood`).

    b (3 m k, 7) float32 maps the particle features q (7, n) float32 to projections:
    row (t m + j) k + l holds, for known line j and observed line l, t = 0 the
    midpoint's coordinate along the known line, 1 its distance from it, 2 the angle
    penalty (all over their sigmas). reach (m, k) is the half-length difference term,
    ratio2 (m, k) the squared length ratio excess. out (n,) gets the float64 sums.

    Each projection is the 7-term dot product as OpenBLAS's sgemm kernels form it
    (a float32 fused multiply-add chain from zero, in feature order), so the result
    is bit for bit that of `b @ q` followed by the array code this replaced; one
    pass over the particles per (known, observed) line pair instead of ten passes
    over 3 m k n temporaries, and no BLAS threads.
    """
    n = q.shape[1]
    mk = m * k
    zero = np.float32(0.0)
    best = np.empty(n, dtype=np.float32)
    for i in range(n):
        out[i] = 0.0
    for l in range(k):
        for i in range(n):
            best[i] = np.float32(np.inf)
        for j in range(m):
            ra, rp, rs = j * k + l, mk + j * k + l, 2 * mk + j * k + l
            rj, r2 = reach[j, l], ratio2[j, l]
            # The row coefficients as locals: loads LLVM need not repeat per particle
            # (it cannot prove b is not `best`), so the particle loop vectorizes.
            a0, a1, a2, a3, a4, a5, a6 = b[ra, 0], b[ra, 1], b[ra, 2], b[ra, 3], b[ra, 4], b[ra, 5], b[ra, 6]
            p0, p1, p2, p3, p4, p5, p6 = b[rp, 0], b[rp, 1], b[rp, 2], b[rp, 3], b[rp, 4], b[rp, 5], b[rp, 6]
            s0, s1, s2, s3, s4, s5, s6 = b[rs, 0], b[rs, 1], b[rs, 2], b[rs, 3], b[rs, 4], b[rs, 5], b[rs, 6]
            if a5 == 0 and a6 == 0 and p5 == 0 and p6 == 0 and s1 == 0 and s2 == 0 and s3 == 0 and s4 == 0:
                # ParticleFilter's rows: position rows see features 0-4, angle rows 0, 5 and 6;
                # with q0 = 1 the chains skip the zero terms (they add nothing but the
                # sign of a zero, which abs and the squares drop).
                for i in range(n):
                    q1, q2, q3, q4, q5, q6 = q[1, i], q[2, i], q[3, i], q[4, i], q[5, i], q[6, i]
                    a = _fma32(a4, q4, _fma32(a3, q3, _fma32(a2, q2, _fma32(a1, q1, a0))))
                    p = _fma32(p4, q4, _fma32(p3, q3, _fma32(p2, q2, _fma32(p1, q1, p0))))
                    s = _fma32(s6, q6, _fma32(s5, q5, s0))
                    a = np.float32(np.float64(abs(a)) + rj)
                    a = a if a > zero else zero
                    s = s + a * a
                    s = s + p * p
                    s = np.float32(np.float64(s) + r2)
                    best[i] = s if s < best[i] else best[i]
                continue
            for i in range(n):
                q0, q1, q2, q3, q4, q5, q6 = q[0, i], q[1, i], q[2, i], q[3, i], q[4, i], q[5, i], q[6, i]
                a = _fma32(a6, q6, _fma32(a5, q5, _fma32(a4, q4, _fma32(a3, q3, _fma32(
                    a2, q2, _fma32(a1, q1, _fma32(a0, q0, zero)))))))
                p = _fma32(p6, q6, _fma32(p5, q5, _fma32(p4, q4, _fma32(p3, q3, _fma32(
                    p2, q2, _fma32(p1, q1, _fma32(p0, q0, zero)))))))
                s = _fma32(s6, q6, _fma32(s5, q5, _fma32(s4, q4, _fma32(s3, q3, _fma32(
                    s2, q2, _fma32(s1, q1, _fma32(s0, q0, zero)))))))
                a = np.float32(np.float64(abs(a)) + rj)
                a = a if a > zero else zero
                s = s + a * a
                s = s + p * p
                s = np.float32(np.float64(s) + r2)
                best[i] = s if s < best[i] else best[i]
        for i in range(n):
            out[i] += np.float64(best[i])


@njit
def _row_sum(a: np.ndarray, n: int) -> float:
    """Sum of a[:n] in numpy's order for a row of up to 128 (`np.sum(axis=-1)`): in turn
    below 8 terms, else its 8-way unrolled pairwise sum."""
    if n < 8:
        res = 0.0
        for i in range(n):
            res += a[i]
        return res
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - n % 8:
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return res


@intrinsic
def _fdiv(typingctx, a, b):
    """a / b in float64, IEEE (inf or nan for b = 0) rather than numba's ZeroDivisionError
    check, whose branch keeps loops from vectorizing."""
    def codegen(context, builder, signature, args):
        return builder.fdiv(*args)

    return types.float64(types.float64, types.float64), codegen


@njit
def landmark_log_likelihood(px: np.ndarray, py: np.ndarray, c: np.ndarray, s: np.ndarray, lm: np.ndarray,
                            obs: np.ndarray, r_obs: np.ndarray, w_dist: np.ndarray, k_bearing: float,
                            out: np.ndarray) -> None:
    """out[i] = -0.5 sum_j (distance error_ij w_dist_j)^2 + (2 - 2 cos bearing error_ij) k_bearing
    for particles at (px, py) (contiguous; heading cosines c, sines s) and k landmarks at
    lm (k, 2) seen at obs (k, 2) (level frame; r_obs their distances): the array code of
    the filter's first version (its (n, k) temporaries and row sums), bit for bit. Below
    8 landmarks (numpy sums such rows in turn) one pass per landmark over all particles,
    which vectorizes (`_fdiv`); from 8 on, per particle with numpy's row sum."""
    k = lm.shape[0]
    n = px.shape[0]
    if k < 8:
        for i in range(n):
            out[i] = 0.0
        for j in range(k):
            lx, ly, ox, oy, r, wd = lm[j, 0], lm[j, 1], obs[j, 0], obs[j, 1], r_obs[j], w_dist[j]
            for i in range(n):
                ex = lx - px[i]
                ey = ly - py[i]
                r_exp = math.sqrt(ex * ex + ey * ey)
                cos_d = ex * (c[i] * ox - s[i] * oy)
                cos_d += ey * (s[i] * ox + c[i] * oy)
                cos_d = _fdiv(cos_d, r_exp * r + 1e-9)
                d = (r_exp - r) * wd
                d *= d
                d += (2.0 - 2.0 * cos_d) * k_bearing
                out[i] += d
        for i in range(n):
            out[i] = 0.0 - 0.5 * out[i]
        return
    dr = np.empty(k)
    for i in range(n):
        x, y, cc, ss = px[i], py[i], c[i], s[i]
        for j in range(k):
            ex = lm[j, 0] - x
            ey = lm[j, 1] - y
            r_exp = math.sqrt(ex * ex + ey * ey)
            cos_d = ex * (cc * obs[j, 0] - ss * obs[j, 1])
            cos_d += ey * (ss * obs[j, 0] + cc * obs[j, 1])
            cos_d /= r_exp * r_obs[j] + 1e-9
            d = (r_exp - r_obs[j]) * w_dist[j]
            d *= d
            d += (2.0 - 2.0 * cos_d) * k_bearing
            dr[j] = d
        out[i] = 0.0 - 0.5 * _row_sum(dr, k)


@njit
def resample(particles: np.ndarray, weights: np.ndarray, gen: np.ndarray, n_new: int, walk_xy: float,
             walk_theta: float, low: np.ndarray, span: np.ndarray, lm_xy: np.ndarray, lm_idx: np.ndarray,
             landmarks: np.ndarray, sigma_theta: float, out: np.ndarray) -> None:
    """`ParticleFilter._resample` into out (n, 3), then weights set to 1 / n; draws from gen
    in the Generator calls' order: the systematic resampling's offset, a normal (x, y,
    heading) step per kept particle, the fresh particles' uniform draws, the landmark
    seeds' integers and heading noise.

    Systematic resampling of n - n_new particles: positions (u0 + i) / (n - n_new) in the
    cumulative weights (the last set to 1), found by one merge-like pass (the index
    `np.searchsorted` gives on the nondecreasing sums), each drawn particle plus its
    normal step times (walk_xy, walk_xy, walk_theta). The n_new fresh ones: uniform in
    [low, low + span); the first n_new // 2 of them seeded from the landmarks seen
    (`seed_poses`) when any (lm_idx >= 0) and n_new > 1.
    """
    st = gen[0]
    n = particles.shape[0]
    n_keep = n - n_new
    u0 = uniform_draw(st)
    step = 1.0 / n_keep
    j = 0
    cum = weights[0] if n > 1 else 1.0
    for i in range(n_keep):
        pos = (u0 + i) * step
        while cum < pos and j < n - 1:
            j += 1
            cum = 1.0 if j == n - 1 else cum + weights[j]
        out[i, 0] = particles[j, 0] + normal_draw(st) * walk_xy
        out[i, 1] = particles[j, 1] + normal_draw(st) * walk_xy
        out[i, 2] = particles[j, 2] + normal_draw(st) * walk_theta
    for i in range(n_keep, n):
        for d in range(3):
            out[i, d] = low[d] + span[d] * uniform_draw(st)
    lm, obs = seen_landmarks(lm_xy, lm_idx, landmarks)
    m = lm.shape[0]
    if m and n_new > 1:
        k = n_new // 2
        a = np.empty(k, dtype=np.int64)
        for r in range(k):
            a[r] = integer_draw(gen, 0, m)
        b = np.empty(k if m >= 2 else 0, dtype=np.int64)
        z = np.empty(b.shape[0])
        for r in range(b.shape[0]):
            b[r] = (a[r] + integer_draw(gen, 1, m)) % m  # != a[r]
        for r in range(b.shape[0]):
            z[r] = normal_draw(st)
        seed_poses(lm, obs, a, b, z, sigma_theta, out[n_keep:n_keep + k])
    weights[:] = 1.0 / n


@njit
def seen_landmarks(lm_xy: np.ndarray, lm_idx: np.ndarray,
                   landmarks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(k, 2) team-frame positions and (k, 2) level-frame observations of the landmarks seen:
    rows of `landmarks` (m, 2+) whose lm_idx (m,) names a known landmark (>= 0) of lm_xy."""
    k = 0
    for r in range(lm_idx.shape[0]):
        k += lm_idx[r] >= 0
    lm = np.empty((k, 2))
    obs = np.empty((k, 2))
    k = 0
    for r in range(lm_idx.shape[0]):
        if lm_idx[r] >= 0:
            lm[k, 0], lm[k, 1] = lm_xy[lm_idx[r], 0], lm_xy[lm_idx[r], 1]
            obs[k, 0], obs[k, 1] = landmarks[r, 0], landmarks[r, 1]
            k += 1
    return lm, obs


@njit
def seed_poses(lm: np.ndarray, obs: np.ndarray, i: np.ndarray, j: np.ndarray, z: np.ndarray,
               sigma_theta: float, out: np.ndarray) -> None:
    """Sensor resetting (`ParticleFilter._seed_from_landmarks`): row r of out (k, 3) gets
    the pose that puts landmark i[r] (at lm, team frame) where it was seen (obs, level
    frame), its heading from the pair (i[r], j[r]) plus z[r] sigma_theta when j is not
    empty, else the heading already in out[r, 2]."""
    for r in range(out.shape[0]):
        a = i[r]
        if j.shape[0]:
            b = j[r]
            theta = math.atan2(lm[b, 1] - lm[a, 1], lm[b, 0] - lm[a, 0]) - math.atan2(
                obs[b, 1] - obs[a, 1], obs[b, 0] - obs[a, 0])
            theta += z[r] * sigma_theta
        else:
            theta = out[r, 2]
        c, s = math.cos(theta), math.sin(theta)
        out[r, 0] = lm[a, 0] - (c * obs[a, 0] - s * obs[a, 1])
        out[r, 1] = lm[a, 1] - (s * obs[a, 0] + c * obs[a, 1])
        out[r, 2] = theta


@njit
def _block_sum(a: np.ndarray, lo: int, n: int) -> float:
    """Sum of a[lo:lo + n], n <= 128, as numpy's pairwise_sum forms a block: in turn
    below 8 terms, else 8 running sums."""
    if n < 8:
        res = 0.0
        for i in range(lo, lo + n):
            res += a[i]
        return res
    r0, r1, r2, r3 = a[lo], a[lo + 1], a[lo + 2], a[lo + 3]
    r4, r5, r6, r7 = a[lo + 4], a[lo + 5], a[lo + 6], a[lo + 7]
    i = lo + 8
    end = lo + n - n % 8
    while i < end:
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < lo + n:
        res += a[i]
        i += 1
    return res


@njit
def _pairwise_sum(a: np.ndarray) -> float:
    """np.sum of a contiguous float64 array in numpy's order (pairwise_sum: halves, cut at
    a multiple of 8, down to blocks of up to 128). Its recursion is walked with an
    explicit stack: numba cannot cache recursive functions."""
    lo = np.empty(64, dtype=np.int64)  # per pending half: start, length, phase, left sum
    size = np.empty(64, dtype=np.int64)
    phase = np.empty(64, dtype=np.int64)
    left = np.empty(64)
    top = 0
    lo[0], size[0], phase[0] = 0, a.shape[0], 0
    res = 0.0
    while top >= 0:
        m = size[top]
        if m <= 128:
            res = _block_sum(a, lo[top], m)
            top -= 1
            continue
        half = m // 2
        half -= half % 8
        if phase[top] == 0:  # first the left half
            phase[top] = 1
            lo[top + 1], size[top + 1], phase[top + 1] = lo[top], half, 0
            top += 1
        elif phase[top] == 1:  # the left half's sum is in res: now the right half
            left[top] = res
            phase[top] = 2
            lo[top + 1], size[top + 1], phase[top + 1] = lo[top] + half, m - half, 0
            top += 1
        else:
            res = left[top] + res
            top -= 1
    return res


@njit
def _dot(x: np.ndarray, y: np.ndarray) -> float:
    """x @ y of contiguous float64 vectors as OpenBLAS's ddot forms it (its Haswell kernel,
    which Zen runs too): 16 fused multiply-add lanes over the first n & -16 terms, summed
    in the kernel's order, then the rest in turn."""
    n = x.shape[0]
    n1 = n & -16
    acc = np.zeros(16)
    for i in range(0, n1, 16):
        for lane in range(16):
            acc[lane] = _fma64(x[i + lane], y[i + lane], acc[lane])
    dot = 0.0
    if n1:
        # Each 4-lane register: low half + high half; then (r4 + r5) + (r6 + r7); then across.
        h0, h1 = acc[0] + acc[2], acc[1] + acc[3]
        h2, h3 = acc[4] + acc[6], acc[5] + acc[7]
        h4, h5 = acc[8] + acc[10], acc[9] + acc[11]
        h6, h7 = acc[12] + acc[14], acc[13] + acc[15]
        dot = ((h0 + h2) + (h4 + h6)) + ((h1 + h3) + (h5 + h7))
    for i in range(n1, n):
        dot += y[i] * x[i]
    return dot


@njit
def _dot_column(w: np.ndarray, p: np.ndarray, col: int) -> float:
    """w @ p[:, col] as OpenBLAS's ddot forms it for a strided vector: two running sums of
    pairs of products four terms at a time, the rest in turn into the first."""
    n = w.shape[0]
    t1 = t2 = 0.0
    n1 = n & -4
    for i in range(0, n1, 4):
        t1 += w[i] * p[i, col] + w[i + 2] * p[i + 2, col]
        t2 += w[i + 1] * p[i + 1, col] + w[i + 3] * p[i + 3, col]
    for i in range(n1, n):
        t1 += w[i] * p[i, col]
    return t1 + t2


@njit
def observation_log_likelihood(p: np.ndarray, c: np.ndarray, s: np.ndarray, lm_xy: np.ndarray,
                               lm_idx: np.ndarray, landmarks: np.ndarray, lines: np.ndarray, line_count: int,
                               min_length: float, circle_piece: float, w_lines: np.ndarray,
                               len_lines: np.ndarray, w_straight: np.ndarray, len_straight: np.ndarray,
                               sigma_distance: float, sigma_distance_rel: float, k_bearing: float,
                               inv_line_distance: float, sigma_line_ratio: float, ll: np.ndarray,
                               tmp: np.ndarray) -> tuple[int, int]:
    """ll (n,) = `ParticleFilter.log_likelihood` of particles p (n, 3), whose heading cosines
    and sines go into c and s, for the landmarks seen (`seen_landmarks`) and the line_count longest
    observed lines (lines (l, 2, 2+), level frame) at least min_length long, against the
    known lines' rows and lengths (only the straight ones when every line used is longer
    than circle_piece); tmp (n,) is scratch. Returns the numbers of landmarks and lines used.

    Lines of equal length are taken in their order in `lines` (np.argsort on distinct lengths)."""
    for i in range(p.shape[0]):
        c[i], s[i] = math.cos(p[i, 2]), math.sin(p[i, 2])
    lm, obs = seen_landmarks(lm_xy, lm_idx, landmarks)
    k = lm.shape[0]
    n_lines = lines.shape[0]
    length = np.empty(n_lines)
    for i in range(n_lines):
        length[i] = math.hypot(lines[i, 1, 0] - lines[i, 0, 0], lines[i, 1, 1] - lines[i, 0, 1])
    chosen = np.empty(min(line_count, n_lines), dtype=np.int64)
    used = np.zeros(n_lines, dtype=np.bool_)
    n_used = 0
    for _ in range(chosen.shape[0]):
        best = -1
        for i in range(n_lines):
            if not used[i] and (best < 0 or length[i] > length[best]):
                best = i
        if not length[best] >= min_length:
            break
        used[best] = True
        chosen[n_used] = best
        n_used += 1
    px, py = np.ascontiguousarray(p[:, 0]), np.ascontiguousarray(p[:, 1])
    if k:
        r_obs = np.empty(k)
        w_dist = np.empty(k)
        for j in range(k):
            r_obs[j] = math.hypot(obs[j, 0], obs[j, 1])
            w_dist[j] = 1.0 / (sigma_distance + sigma_distance_rel * r_obs[j])
        landmark_log_likelihood(px, py, c, s, lm, obs, r_obs, w_dist, k_bearing, ll)
    else:
        ll[:] = 0.0
    if n_used:
        seg = np.empty((n_used, 2, 2))
        seg_len = np.empty(n_used)
        shortest = math.inf
        for l in range(n_used):
            i = chosen[l]
            for e in range(2):
                seg[l, e, 0], seg[l, e, 1] = lines[i, e, 0], lines[i, e, 1]
            seg_len[l] = length[i]
            shortest = min(shortest, length[i])
        if shortest > circle_piece:
            w_known, len_known = w_straight, len_straight
        else:
            w_known, len_known = w_lines, len_lines
        line_log_likelihood(px, py, c, s, seg, seg_len, w_known, len_known, inv_line_distance,
                            sigma_line_ratio, tmp)
        for i in range(ll.shape[0]):
            ll[i] += tmp[i]
    return k, n_used


@njit
def weigh(p: np.ndarray, ll: np.ndarray, c: np.ndarray, s: np.ndarray, w: np.ndarray, pose: np.ndarray,
          tmp: np.ndarray) -> tuple[float, float]:
    """From log-likelihoods ll (n,) of particles p (n, 3) with heading cosines c and sines s:
    the normalized weights w (n,), the weighted mean pose (3,) (x, y, circular mean
    heading) and returns (the best log-likelihood, the weighted standard deviation of the
    positions around the mean, m). The array code of `ParticleFilter.update` (np.max,
    np.exp, np.sum, the BLAS dot products) in one pass each; tmp (n,) is scratch."""
    n = p.shape[0]
    best = ll[0]
    for i in range(1, n):
        best = ll[i] if ll[i] > best else best
    for i in range(n):
        w[i] = math.exp(ll[i] - best)
    inv = 1.0 / _pairwise_sum(w)
    for i in range(n):
        w[i] *= inv
    x, y = _dot_column(w, p, 0), _dot_column(w, p, 1)
    pose[0], pose[1], pose[2] = x, y, math.atan2(_dot(w, s), _dot(w, c))
    for i in range(n):
        dx, dy = p[i, 0] - x, p[i, 1] - y
        tmp[i] = dx * dx + dy * dy
    return best, math.sqrt(_dot(w, tmp))


@njit
def weigh_and_resample(p: np.ndarray, ll: np.ndarray, c: np.ndarray, s: np.ndarray, w: np.ndarray,
                       pose: np.ndarray, tmp: np.ndarray, n_terms: int, gen: np.ndarray, n_new: int,
                       walk_xy: float, walk_theta: float, walk_max_growth: float, low: np.ndarray,
                       span: np.ndarray, lm_xy: np.ndarray, lm_idx: np.ndarray, landmarks: np.ndarray,
                       sigma_theta: float, out: np.ndarray) -> tuple[float, float]:
    """`weigh`, then `resample` into out with the random walk grown by the misfit (the
    best particle's s.d. per measured quantity, n_terms of them; at least 1, at most
    walk_max_growth); returns (misfit, spread). One call for `ParticleFilter.update`."""
    best, spread = weigh(p, ll, c, s, w, pose, tmp)
    v = -2.0 * best
    misfit = math.sqrt((v if v > 0.0 else 0.0) / n_terms)
    grow = 1.0 if 1.0 > misfit else misfit  # Python's min(max(misfit, 1.0), walk_max_growth)
    grow = walk_max_growth if walk_max_growth < grow else grow
    resample(p, w, gen, n_new, walk_xy * grow, walk_theta * grow, low, span, lm_xy, lm_idx, landmarks,
             sigma_theta, out)
    return misfit, spread


@njit
def line_log_likelihood(px: np.ndarray, py: np.ndarray, c: np.ndarray, s: np.ndarray, seg: np.ndarray,
                        length: np.ndarray, w_all: np.ndarray, known_len: np.ndarray, inv_distance: float,
                        sigma_ratio: float, out: np.ndarray) -> None:
    """out (n,) = the line log-likelihood of `ParticleFilter.log_likelihood` for
    particles (px, py, heading cosines c and sines s), observed lines seg (K, 2, 2) with
    lengths `length`, against the known lines' rows w_all (3 m, 5) and lengths known_len.

    The same floats as its array code: every entry of its einsum has at most two nonzero
    products (the row and feature patterns are sparse), so summing them in turn gives
    its value; then `line_scores`."""
    k = seg.shape[0]
    m = known_len.shape[0]
    n = px.shape[0]
    g = np.zeros((5, 7))
    b = np.empty((3 * m * k, 7), dtype=np.float32)
    for l in range(k):
        mx = (seg[l, 0, 0] + seg[l, 1, 0]) / 2.0
        my = (seg[l, 0, 1] + seg[l, 1, 1]) / 2.0
        a2 = 2.0 * math.atan2(seg[l, 1, 1] - seg[l, 0, 1], seg[l, 1, 0] - seg[l, 0, 0])
        ca, sa = math.cos(a2), math.sin(a2)
        g[0, 1] = 1.0
        g[0, 3], g[0, 4] = mx, -my
        g[1, 2] = 1.0
        g[1, 3], g[1, 4] = my, mx
        g[2, 5], g[2, 6] = ca, -sa
        g[3, 5], g[3, 6] = sa, ca
        g[4, 0] = 1.0
        for j in range(3 * m):
            for f in range(7):
                acc = 0.0
                for e in range(5):
                    acc += w_all[j, e] * g[e, f]
                b[j * k + l, f] = np.float32(acc)
    q = np.empty((7, n), dtype=np.float32)
    for i in range(n):
        ci, si = c[i], s[i]
        q[0, i] = np.float32(1.0)
        q[1, i] = np.float32(px[i])
        q[2, i] = np.float32(py[i])
        q[3, i] = np.float32(ci)
        q[4, i] = np.float32(si)
        q[5, i] = np.float32(ci * ci - si * si)
        q[6, i] = np.float32(2.0 * ci * si)
    reach = np.empty((m, k))
    ratio2 = np.empty((m, k))
    for j in range(m):
        for l in range(k):
            r = length[l] / known_len[j] - 1.0
            r = (r if r >= 0.0 else 0.0) / sigma_ratio
            ratio2[j, l] = r * r
            reach[j, l] = (0.5 * length[l] - 0.5 * known_len[j]) * inv_distance
    line_scores(b, q, m, k, reach, ratio2, out)
    for i in range(n):
        out[i] = -0.5 * out[i]


# ---------------------------------------------------------------- world model (vision)
# Products here repeat numpy's OpenBLAS on these shapes: a 3x3 matrix times a 3-vector is
# fma(a2, v2, fma(a0, v0, a1 v1)) per row (dgemv); an (n >= 2, 3) by (3, 3) product is one
# fused multiply-add chain from zero per entry (dgemm); numpy hands a single row to dgemv,
# which sums (a0 b0 + a1 b1) + a2 b2 against a C-ordered matrix and fma(a2 b2, fma(a0 b0,
# a1 b1)) against a transposed one.


@njit
def _mat3_vec(a: np.ndarray, v: np.ndarray) -> np.ndarray:
    """a (3, 3) @ v (3,) as numpy's dgemv forms it."""
    out = np.empty(3)
    for i in range(3):
        out[i] = _fma64(a[i, 2], v[2], _fma64(a[i, 0], v[0], a[i, 1] * v[1]))
    return out


@njit
def _rows_times(p: np.ndarray, m: np.ndarray, transpose: bool) -> np.ndarray:
    """p (n, 3) @ m (3, 3), or @ m.T, as numpy forms it (see above)."""
    n = p.shape[0]
    out = np.empty((n, 3))
    for i in range(n):
        for j in range(3):
            out[i, j] = _entry(p, i, m, j, transpose, n)
    return out


@njit
def _entry(p: np.ndarray, i: int, m: np.ndarray, j: int, transpose: bool, n: int) -> float:
    """Entry (i, j) of p (n, 3) @ m (3, 3), or @ m.T, as numpy forms it (see above)."""
    b0, b1, b2 = (m[j, 0], m[j, 1], m[j, 2]) if transpose else (m[0, j], m[1, j], m[2, j])
    if n >= 2:
        return _fma64(p[i, 2], b2, _fma64(p[i, 1], b1, _fma64(p[i, 0], b0, 0.0)))
    if transpose:
        return _fma64(p[i, 2], b2, _fma64(p[i, 0], b0, p[i, 1] * b1))
    return (p[i, 0] * b0 + p[i, 1] * b1) + p[i, 2] * b2


@njit
def _row_times(p: np.ndarray, m: np.ndarray, n: int) -> tuple[float, float, float]:
    """The one row of p (1, 3) @ m (3, 3), as numpy forms it for a product of n rows."""
    return _entry(p, 0, m, 0, False, n), _entry(p, 0, m, 1, False, n), _entry(p, 0, m, 2, False, n)


@njit
def camera_in_level(neck_yaw: float, head_pitch: float, level: np.ndarray, neck_z: float,
                    pivot_z: float, camera_above_pivot: float) -> tuple[np.ndarray, np.ndarray]:
    """`agent.perception.camera_in_level`: camera pose (R, p) in the level frame for the
    head angles (rad) and the torso-to-level rotation `level` (3x3); the head chain's
    offsets (m) as in `agent.geometry.camera_in_torso`."""
    cy, sy = math.cos(neck_yaw), math.sin(neck_yaw)
    cp, sp = math.cos(-head_pitch), math.sin(-head_pitch)
    r_yaw = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    r_pitch = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    r = _rows_times(r_yaw, r_pitch, False)
    p = np.array([0.0, 0.0, neck_z]) + _mat3_vec(r_yaw, np.array([0.0, 0.0, pivot_z]) + _mat3_vec(
        r_pitch, np.array([0.0, 0.0, camera_above_pivot])))
    return _rows_times(level, r, False), _mat3_vec(level, p)


@njit
def _from_polar_into(a: np.ndarray, out: np.ndarray, start: int) -> int:
    """Rows of a (k, 3) polar (distance, horizontal, vertical) as cartesian rows of out
    from `start` (`agent.geometry.from_polar`); returns the next free row."""
    for k in range(a.shape[0]):
        d, h, v = a[k, 0], a[k, 1], a[k, 2]
        c = d * math.cos(v)
        row = out[start + k]
        row[0], row[1], row[2] = c * math.cos(h), c * math.sin(h), d * math.sin(v)
    return start + a.shape[0]


@njit
def observe_frame(landmarks: np.ndarray, lines: np.ndarray, players: np.ndarray, ball: np.ndarray,
                  neck_yaw: float, head_pitch: float, level: np.ndarray, roll: float, pitch: float,
                  neck_z: float, pivot_z: float, camera_above_pivot: float) -> np.ndarray:
    """One vision frame into the level frame (`agent.perception.observe`): the polar
    (k, 3) rows of landmarks, line end points, player parts and ball (0 or 1 row)
    stacked, as from_polar(...) @ R.T + p (m) for the camera pose (R, p) of
    `camera_in_level`. level: the torso-to-level rotation (3x3), or (0, 0) for the one
    of a torso tilted by roll and pitch (rad; `skills.imu.TiltEstimator.level`).
    Returns one (4 + k, 3) block: R, p, then the points."""
    if level.shape[0] == 0:
        cp, sp = math.cos(pitch), math.sin(pitch)
        cr, sr = math.cos(roll), math.sin(roll)
        level = _rows_times(np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]]),
                            np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]]), False)
    rot, pos = camera_in_level(neck_yaw, head_pitch, level, neck_z, pivot_z, camera_above_pivot)
    n = landmarks.shape[0] + lines.shape[0] + players.shape[0] + ball.shape[0]
    cart = np.empty((n, 3))
    i = _from_polar_into(landmarks, cart, 0)
    i = _from_polar_into(lines, cart, i)
    i = _from_polar_into(players, cart, i)
    _from_polar_into(ball, cart, i)
    out = np.empty((4 + n, 3))
    out[:3] = rot
    out[3] = pos
    for i in range(n):
        for j in range(3):
            out[4 + i, j] = _entry(cart, i, rot, j, True, n) + pos[j]
    return out


@njit
def place_robots(level: np.ndarray, ours: np.ndarray, unum: np.ndarray, part: np.ndarray, x: float, y: float,
                 heading: float, torso_height: float, own_unum: int, team_size: int, n_parts: int, head: int,
                 pairs: np.ndarray) -> np.ndarray:
    """Other robots from their seen parts (`WorldModel._see_players`).

    level (p, 3): the parts in the level frame (m); ours, unum, part (p,): whose part
    and which (index into SEEN_PARTS). With the pose (x, y m, heading rad; team frame)
    and the torso height (m), one row per robot seen, in order of first appearance (this
    player and numbers out of range left out): team-frame position (m: its head's, else
    the mean of its parts; z at least 0), the level-frame reading of its first part (m),
    heading (rad, of the first pair of parts `pairs` (left, right) seen; nan if none),
    fallen (1.0: head below 0.25 m, else 0.0), slot (0..team_size-1 ours by uniform
    number, then theirs)."""
    n = level.shape[0]
    c, s = math.cos(heading), math.sin(heading)
    team = np.empty((n, 3))
    for i in range(n):
        px, py = level[i, 0], level[i, 1]
        team[i, 0], team[i, 1] = x + c * px - s * py, y + s * px + c * py
        team[i, 2] = torso_height + level[i, 2]
    m = 2 * team_size
    order = np.full(m, -1)  # slot -> its rank of first appearance
    first = np.full((m, n_parts), -1)  # slot, part -> the part's first row
    count = np.zeros(m, dtype=np.int64)
    total = np.zeros((m, 3))
    first_row = np.empty(m, dtype=np.int64)
    seen = 0
    for i in range(n):
        u = unum[i]
        if u < 1 or u > team_size or (ours[i] and u == own_unum):
            continue
        r = u - 1 if ours[i] else team_size + u - 1
        if order[r] < 0:
            order[r] = seen
            first_row[seen] = i
            seen += 1
            total[r, 0], total[r, 1], total[r, 2] = team[i, 0], team[i, 1], team[i, 2]
        else:
            total[r, 0] += team[i, 0]
            total[r, 1] += team[i, 1]
            total[r, 2] += team[i, 2]
        count[r] += 1
        k = part[i]
        if 0 <= k < n_parts and first[r, k] < 0:
            first[r, k] = i
    out = np.empty((seen, 9))
    for r in range(m):
        j = order[r]
        if j < 0:
            continue
        row = out[j]
        h = first[r, head]
        if h >= 0:
            z = team[h, 2]
            row[0], row[1], row[2] = team[h, 0], team[h, 1], z if z > 0.0 else 0.0
            row[7] = 1.0 if z < 0.25 else 0.0
        else:
            k = count[r]
            z = total[r, 2] / k
            row[0], row[1], row[2] = total[r, 0] / k, total[r, 1] / k, z if z > 0.0 else 0.0
            row[7] = 0.0
        i = first_row[j]
        row[3], row[4], row[5] = level[i, 0], level[i, 1], level[i, 2]
        row[6] = math.nan
        for q in range(pairs.shape[0]):
            a, b = first[r, pairs[q, 0]], first[r, pairs[q, 1]]
            if a >= 0 and b >= 0:
                t = math.atan2(team[a, 1] - team[b, 1], team[a, 0] - team[b, 0]) - math.pi / 2
                if math.isfinite(t):
                    row[6] = (t + math.pi) % (2.0 * math.pi) - math.pi
                break
        row[8] = r
    return out


@njit
def in_view(points: np.ndarray, x: float, y: float, heading: float, torso_height: float,
            cam_pos: np.ndarray, cam_rot: np.ndarray, half_cone: float) -> int:
    """Which team-frame points (n <= 63, 3; m) lie within half_cone (rad) of a camera's
    axis, both horizontally and vertically, in front of it, as bits (1 << i): camera
    pose (cam_rot, cam_pos) in the level frame of a torso at (x, y, heading) and
    torso_height (m)."""
    n = points.shape[0]
    c, s = math.cos(heading), math.sin(heading)
    bits = 0
    rel = np.empty((1, 3))
    for i in range(n):
        ex, ey = points[i, 0] - x, points[i, 1] - y
        rel[0, 0] = c * ex + s * ey - cam_pos[0]
        rel[0, 1] = -s * ex + c * ey - cam_pos[1]
        rel[0, 2] = points[i, 2] - torso_height - cam_pos[2]
        cx, cy, cz = _row_times(rel, cam_rot, n)
        hor = math.atan2(cy, cx)
        ver = math.atan2(cz, math.hypot(cx, cy))
        if abs(hor) < half_cone and abs(ver) < half_cone and cx > 0:
            bits |= 1 << i
    return bits


@njit
def place_seen(landmark_z: np.ndarray, landmarks: np.ndarray, lines: np.ndarray, ball: np.ndarray,
               players: np.ndarray, ours: np.ndarray, unum: np.ndarray, part: np.ndarray, x: float, y: float,
               heading: float, torso_height: float, own_unum: int, team_size: int, n_parts: int, head: int,
               pairs: np.ndarray) -> np.ndarray:
    """A vision frame's level-frame objects placed on the field (`WorldModel._see`) from
    the pose (x, y m, heading rad; team frame) and the torso height (m).

    The torso height first moves 20 % toward the median (np.median's value) of the
    heights implied by landmarks of known height landmark_z (k,; nan: unknown) seen at
    landmarks (k, 3) and by the field lines' end points (n, 2, 3) on the ground. Then the
    ball (0 or 1 row) and the robots' parts (see `place_robots`) go to the team frame.
    Returns (1 + robots, 9): row 0 the new torso height, the ball's team-frame position
    and its ground distance (m; nan without a ball), then one row per robot."""
    k, n = landmarks.shape[0], lines.shape[0]
    z = np.empty(k + 2 * n)
    m = 0
    for i in range(k):
        v = landmark_z[i] - landmarks[i, 2]
        if math.isfinite(v):
            z[m] = v
            m += 1
    for i in range(n):
        for e in range(2):
            v = -lines[i, e, 2]
            if math.isfinite(v):
                z[m] = v
                m += 1
    if m:
        srt = np.sort(z[:m])
        h = m // 2
        torso_height += 0.2 * ((srt[h] if m % 2 else (srt[h - 1] + srt[h]) / 2.0) - torso_height)
    robots = place_robots(players, ours, unum, part, x, y, heading, torso_height, own_unum, team_size,
                          n_parts, head, pairs)
    out = np.full((1 + robots.shape[0], 9), math.nan)
    out[0, 0] = torso_height
    if ball.shape[0]:
        c, s = math.cos(heading), math.sin(heading)
        bx, by = ball[0, 0], ball[0, 1]
        out[0, 1], out[0, 2] = x + c * bx - s * by, y + s * bx + c * by
        out[0, 3] = torso_height + ball[0, 2]
        out[0, 4] = math.hypot(bx, by)
    out[1:] = robots
    return out

"""Compiled SCRAM assignment algorithms (numba), built on `_lsap` and `bottleneck`.

The methods take a finite dense (n, n) float cost matrix, n >= 1; the
`*_points` forms take (n, 2) agents and targets and compute the distances
in the same compiled call.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from formations._bigint import mmdr_n5
from formations._jit import njit
from formations._lsap import lsap_dense, lsap_sparse
from formations.bottleneck import (
    MATCHABLE_MAX_N,
    bottleneck_dense,
    bottleneck_large,
    bottleneck_sparse,
    candidate_edges,
    matchable_edges,
)

INF = np.inf
LSAP_DENSE_N = 16  # MMD+MSD^2's min-sum step is dense (scipy's result) up to this size, then sparse


@njit
def distances(agents: np.ndarray, targets: np.ndarray) -> tuple[np.ndarray, bool]:
    """(n, m) Euclidean distances of (n, 2) and (m, 2) points, and whether all are finite.

    sqrt(dx^2 + dy^2) is correctly rounded, so points on an integer grid at
    equal distances get exactly equal costs; `math.hypot` takes over where
    the squares overflow (coordinates beyond 1e154).
    """
    n = agents.shape[0]
    m = targets.shape[0]
    out = np.empty((n, m))
    finite = True
    for i in range(n):
        ax = agents[i, 0]
        ay = agents[i, 1]
        for j in range(m):
            dx = ax - targets[j, 0]
            dy = ay - targets[j, 1]
            d = math.sqrt(dx * dx + dy * dy)
            if not d < INF:
                d = math.hypot(dx, dy)
                finite = finite and d < INF
            out[i, j] = d
    return out, finite


@njit
def all_finite(cost: np.ndarray) -> bool:
    """No inf or nan in `cost`."""
    for x in cost.ravel():
        if not math.isfinite(x):
            return False
    return True


@njit
def mmd_msd2(cost: np.ndarray, dense_max: int) -> np.ndarray:
    """MMD+MSD^2: bottleneck b, then min sum of cost^2 over the edges <= b.

    The bottleneck is `bottleneck_dense` up to `dense_max` rows, else
    `bottleneck_large`. The min-sum step is `lsap_dense` on the full matrix
    up to `LSAP_DENSE_N` rows (the same result as scipy's
    `linear_sum_assignment`), beyond it `lsap_sparse` on the edges <= b (up to
    `MATCHABLE_MAX_N` rows only those in some perfect matching of that graph).
    """
    n = cost.shape[0]
    if n <= dense_max:
        b, match = bottleneck_dense(cost, np.full(n, -1, np.int64))
        if n <= LSAP_DENSE_N:
            sq = np.empty((n, n))
            for i in range(n):
                for j in range(n):
                    c = cost[i, j]
                    sq[i, j] = c * c if c <= b else INF
            return lsap_dense(sq)[0]
        if n <= MATCHABLE_MAX_N:  # only edges in some perfect matching under b (the others never are)
            edge = np.empty(n * n, np.int64)
            w = np.empty(n * n)
            count = matchable_edges(cost, b, match, edge, w)
            keep = np.zeros(n + 1, np.int64)
            for q in range(count):
                keep[edge[q] // n + 1] += 1
            for i in range(n):
                keep[i + 1] += keep[i]
            return lsap_sparse(n, keep, edge[:count] % n, w[:count] * w[:count])[0]
        indptr, indices, weights = candidate_edges(cost, b)
    else:
        b, _, indptr, indices, weights = bottleneck_large(cost)
    keep = np.zeros(n + 1, np.int64)
    count = 0
    for i in range(n):
        for e in range(indptr[i], indptr[i + 1]):
            if weights[e] <= b:
                indices[count] = indices[e]
                weights[count] = weights[e] * weights[e]
                count += 1
        keep[i + 1] = count
    return lsap_sparse(n, keep, indices[:count], weights[:count])[0]


@njit
def _local_csr(er, ec, key, ne, lr, lc, m):
    """CSR over local indices (lr, lc) of the first `ne` edges (grouped by increasing row)."""
    indptr = np.zeros(m + 1, np.int64)
    indices = np.empty(ne, np.int64)
    w = np.empty(ne)
    for e in range(ne):
        indptr[lr[er[e]] + 1] += 1
        indices[e] = lc[ec[e]]
        w[e] = key[e]
    for i in range(m):
        indptr[i + 1] += indptr[i]
    return indptr, indices, w


@njit
def mmdr(cost: np.ndarray, dense_max: int) -> np.ndarray:
    """MMDR by Sokkalingam and Aneja's algorithm on edge lists (dissertation Alg. 2).

    Level by level from the top: b is the bottleneck of the remaining edges
    (settled edges always allowed); longer edges are dropped. If a single
    unsettled edge has cost b it is forced (every remaining perfect matching
    uses it): its row and column leave the problem. Otherwise a 0-1
    min-cost matching (cost 1 on the edges of cost b) counts how many of them
    every optimal mapping needs; only edges tight under its optimal duals
    stay, and those of cost b become settled. Edges are kept grouped by row.
    The first bottleneck is `bottleneck_dense` up to `dense_max` rows, else
    `bottleneck_large`; on the dense path up to `MATCHABLE_MAX_N` rows only the
    edges under it that lie in some perfect matching of that graph enter
    (`matchable_edges`).
    """
    n = cost.shape[0]
    out = np.full(n, -1, np.int64)
    ne = 0
    if n <= min(dense_max, MATCHABLE_MAX_N):  # only edges in some perfect matching under b
        b, match = bottleneck_dense(cost, np.full(n, -1, np.int64))
        edge = np.empty(n * n, np.int64)
        ew = np.empty(n * n)
        ne = matchable_edges(cost, b, match, edge, ew)
        er = edge // n
        ec = edge % n
    else:
        if n <= dense_max:
            b, match = bottleneck_dense(cost, np.full(n, -1, np.int64))
            indptr, cols, costs = candidate_edges(cost, b)
        else:
            b, match, indptr, cols, costs = bottleneck_large(cost)
        er = np.empty(cols.size, np.int64)
        ec = np.empty(cols.size, np.int64)
        ew = np.empty(cols.size)
        for i in range(n):
            for e in range(indptr[i], indptr[i + 1]):
                if costs[e] <= b:
                    er[ne] = i
                    ec[ne] = cols[e]
                    ew[ne] = costs[e]
                    ne += 1
    fixed = np.zeros(ne, np.bool_)
    key = np.empty(ne)
    lr = np.empty(n, np.int64)  # local index of each active row (-1: settled)
    lc = np.empty(n, np.int64)
    rowmin = np.empty(n)
    colmin = np.empty(n)
    act_r = np.arange(n)  # active rows (global), in increasing order
    act_c = np.arange(n)
    m = n
    left = n
    first = True
    while True:
        if not first:
            # Lower bound (largest row or column minimum, settled edges -1)
            # and the longest unsettled edge of the current matching: if they
            # meet, that is the bottleneck and no search is needed.
            rowmin[:] = INF
            colmin[:] = INF
            top = -INF
            for e in range(ne):
                k_e = -1.0 if fixed[e] else ew[e]
                key[e] = k_e
                r = er[e]
                c = ec[e]
                if k_e < rowmin[r]:
                    rowmin[r] = k_e
                if k_e < colmin[c]:
                    colmin[c] = k_e
                if match[r] == c and k_e > top:
                    top = k_e
            lower = -INF
            for q in range(m):
                lower = max(lower, rowmin[act_r[q]], colmin[act_c[q]])
            if top <= lower:
                b = top
            else:
                lr[:] = -1
                lc[:] = -1
                for q in range(m):
                    lr[act_r[q]] = q
                    lc[act_c[q]] = q
                ip, ix, w = _local_csr(er, ec, key, ne, lr, lc, m)
                init = np.empty(m, np.int64)
                for q in range(m):
                    init[q] = lc[match[act_r[q]]]
                b, lm = bottleneck_sparse(m, ip, ix, w, lower, init)
                for q in range(m):
                    match[act_r[q]] = act_c[lm[q]]
        first = False
        # Drop unsettled edges longer than b; count those of cost b.
        level = 0
        last = -1
        k = 0
        for e in range(ne):
            if fixed[e] or ew[e] <= b:
                er[k] = er[e]
                ec[k] = ec[e]
                ew[k] = ew[e]
                fixed[k] = fixed[e]
                if not fixed[k] and ew[k] == b:
                    level += 1
                    last = k
                k += 1
        ne = k
        if level == 1:
            r = er[last]
            c = ec[last]
            out[r] = c
            left -= 1
            if left == 0:
                break
            k = 0
            for e in range(ne):
                if er[e] != r and ec[e] != c:
                    er[k] = er[e]
                    ec[k] = ec[e]
                    ew[k] = ew[e]
                    fixed[k] = fixed[e]
                    k += 1
            ne = k
            k = 0
            for q in range(m):
                if act_r[q] != r:
                    act_r[k] = act_r[q]
                    k += 1
            k = 0
            for q in range(m):
                if act_c[q] != c:
                    act_c[k] = act_c[q]
                    k += 1
            m -= 1
            continue
        # 0-1 step on the active problem.
        lr[:] = -1
        lc[:] = -1
        for q in range(m):
            lr[act_r[q]] = q
            lc[act_c[q]] = q
        for e in range(ne):
            key[e] = 1.0 if (not fixed[e] and ew[e] == b) else 0.0
        ip, ix, w = _local_csr(er, ec, key, ne, lr, lc, m)
        lm, u, v = lsap_sparse(m, ip, ix, w)
        ones = 0
        for q in range(m):
            match[act_r[q]] = act_c[lm[q]]
            for e in range(ip[q], ip[q + 1]):
                if ix[e] == lm[q]:
                    ones += int(w[e])
                    break
        left -= ones
        if left == 0:
            break
        k = 0
        for e in range(ne):
            if key[e] - u[lr[er[e]]] - v[lc[ec[e]]] == 0.0:
                er[k] = er[e]
                ec[k] = ec[e]
                ew[k] = ew[e]
                fixed[k] = fixed[e] or key[e] == 1.0
                k += 1
        ne = k
    for q in range(m):
        r = act_r[q]
        if out[r] < 0:
            out[r] = match[r]
    return out


@njit
def rank_weights(cost: np.ndarray) -> np.ndarray:
    """Algorithm 1 ranks: index in the stably sorted edge list of the first equal edge."""
    flat = cost.ravel()
    order = np.argsort(flat, kind="mergesort")
    ranks = np.empty(flat.size, np.int64)
    start = 0
    for k in range(flat.size):
        if k > 0 and flat[order[k]] != flat[order[k - 1]]:
            start = k
        ranks[order[k]] = start
    return ranks.reshape(cost.shape)


@njit
def _add_power(x: np.ndarray, r: int) -> None:
    """x += 2^r on a little-endian multiword unsigned integer."""
    q = r >> 6
    bit = np.uint64(1) << np.uint64(r & 63)
    old = x[q]
    x[q] = old + bit
    if x[q] < old:
        q += 1
        while q < x.size:
            x[q] += np.uint64(1)
            if x[q] != 0:
                break
            q += 1


@njit
def _less(a: np.ndarray, b: np.ndarray) -> bool:
    """a < b for multiword unsigned integers."""
    for q in range(a.size - 1, -1, -1):
        if a[q] != b[q]:
            return a[q] < b[q]
    return False


@njit
def mmdr_dp(cost: np.ndarray) -> np.ndarray:
    """MMDR by the dynamic program of Appendix C (n 2^(n-1) transitions).

    key[S] is the least sum of 2^rank (Algorithm 1 ranks, exact multiword
    integers) over mappings of agent set S to targets 0..|S|-1; last[S] is
    the agent given target |S|-1 (ties to the lowest agent index).
    """
    n = cost.shape[0]
    rank = rank_weights(cost)
    words = (n * n + 8) // 64 + 1
    size = 1 << n
    keys = np.zeros((size, words), np.uint64)
    last = np.zeros(size, np.int8)
    count = np.zeros(size, np.int64)
    tmp = np.empty(words, np.uint64)
    for s in range(1, size):
        count[s] = count[s >> 1] + (s & 1)
        k = count[s] - 1
        have = False
        for a in range(n):
            if not (s >> a) & 1:
                continue
            tmp[:] = keys[s ^ (1 << a)]
            _add_power(tmp, rank[a, k])
            if not have or _less(tmp, keys[s]):
                keys[s] = tmp
                last[s] = a
                have = True
    out = np.empty(n, np.int64)
    s = size - 1
    for k in range(n - 1, -1, -1):
        a = last[s]
        out[a] = k
        s &= ~(1 << a)
    return out


@njit
def msd(cost: np.ndarray) -> np.ndarray:
    """Minimum sum of costs (scipy's `linear_sum_assignment` result)."""
    return lsap_dense(cost)[0]


@njit
def msd2(cost: np.ndarray) -> np.ndarray:
    """Minimum sum of squared costs (scipy's `linear_sum_assignment` result on cost^2)."""
    return lsap_dense(cost * cost)[0]


# One compiled call from points to assignment (no second dispatch at small n):
# each returns [-2, ...] if a distance is not finite.


@njit
def _not_finite(n: int) -> np.ndarray:
    return np.full(n, -2, np.int64)


@njit
def mmdr_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return mmdr(cost, dense_max) if finite else _not_finite(agents.shape[0])


@njit
def mmd_msd2_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return mmd_msd2(cost, dense_max) if finite else _not_finite(agents.shape[0])


@njit
def mmdr_n5_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return mmdr_n5(cost, dense_max) if finite else _not_finite(agents.shape[0])


@njit
def mmdr_dp_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return mmdr_dp(cost) if finite else _not_finite(agents.shape[0])


@njit
def msd_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return msd(cost) if finite else _not_finite(agents.shape[0])


@njit
def msd2_points(agents: np.ndarray, targets: np.ndarray, dense_max: int) -> np.ndarray:
    cost, finite = distances(agents, targets)
    return msd2(cost) if finite else _not_finite(agents.shape[0])


# ------------------------------------------------------------ Delaunay formations
# `formation_positions` repeats `scipy.spatial.Delaunay.find_simplex` (default tolerance,
# its walk from simplex 0 on the lifted paraboloid, then the directed walk, then brute
# force) and the numpy arithmetic `formations.delaunay` did on its answer: the barycentric
# product as OpenBLAS's dgemv forms it, the weights' sum from the left and einsum's sum of
# the three samples from +0.0.

FIND_EPS = 100.0 * np.finfo(np.float64).eps  # find_simplex's default tolerance
FIND_EPS_BROAD = math.sqrt(FIND_EPS)


@intrinsic
def _fma(typingctx, a, b, c):
    """a * b + c with one rounding (LLVM's fma)."""
    def codegen(context, builder, signature, args):
        fma_type = ir.FunctionType(ir.DoubleType(), [ir.DoubleType()] * 3)
        return builder.call(builder.module.declare_intrinsic("llvm.fma", [ir.DoubleType()], fma_type), args)

    return types.float64(types.float64, types.float64, types.float64), codegen


@njit
def _outside_box(x: float, y: float, lo: np.ndarray, hi: np.ndarray, eps: float) -> bool:
    return x < lo[0] - eps or x > hi[0] + eps or y < lo[1] - eps or y > hi[1] + eps


@njit
def _coordinate(t: np.ndarray, s: int, k: int, x: float, y: float) -> float:
    """Barycentric coordinate k < 2 of (x, y) in simplex s (scipy's order of operations)."""
    c = 0.0
    c += t[s, k, 0] * (x - t[s, 2, 0])
    c += t[s, k, 1] * (y - t[s, 2, 1])
    return c


@njit
def _bruteforce(x: float, y: float, lo: np.ndarray, hi: np.ndarray, neighbors: np.ndarray,
                t: np.ndarray, eps: float, eps_broad: float) -> int:
    """The first simplex holding (x, y) within eps, degenerate ones judged by their neighbors."""
    if _outside_box(x, y, lo, hi, eps):
        return -1
    c = np.empty(3)
    for s in range(t.shape[0]):
        if t[s, 0, 0] == t[s, 0, 0]:
            c0 = _coordinate(t, s, 0, x, y)
            if not (-eps <= c0 <= 1.0 + eps):
                continue
            c1 = _coordinate(t, s, 1, x, y)
            if not (-eps <= c1 <= 1.0 + eps):
                continue
            c2 = 1.0 - c0 - c1
            if -eps <= c2 <= 1.0 + eps:
                return s
            continue
        for k in range(3):
            nb = neighbors[s, k]
            if nb == -1 or t[nb, 0, 0] != t[nb, 0, 0]:
                continue
            c[0] = _coordinate(t, nb, 0, x, y)
            c[1] = _coordinate(t, nb, 1, x, y)
            c[2] = 1.0 - c[0] - c[1]
            inside = True
            for m in range(3):
                low = -eps_broad if neighbors[nb, m] == s else -eps
                if not (low <= c[m] <= 1.0 + eps):
                    inside = False
                    break
            if inside:
                return nb
    return -1


@njit
def find_simplex(x: float, y: float, lo: np.ndarray, hi: np.ndarray, equations: np.ndarray,
                 neighbors: np.ndarray, t: np.ndarray, scale: float, shift: float) -> int:
    """`Delaunay.find_simplex` of one point (x, y): the simplex index, -1 outside."""
    eps, eps_broad = FIND_EPS, FIND_EPS_BROAD
    n = t.shape[0]
    if _outside_box(x, y, lo, hi, eps) or n <= 0:
        return -1
    z = 0.0
    z += x * x
    z += y * y
    z *= scale
    z += shift
    s = 0
    best = _plane(equations, s, x, y, z)
    changed = True
    while changed:
        if best > 0:
            break
        changed = False
        for k in range(3):
            nb = neighbors[s, k]
            if nb == -1:
                continue
            d = _plane(equations, nb, x, y, z)
            if d > best + eps * (1.0 + abs(best)):
                s, best, changed = nb, d, True
    for _ in range(1 + n // 4):
        if s == -1:
            return s
        inside = 1
        c0 = c1 = 0.0
        for k in range(3):
            if k == 0:
                c = c0 = _coordinate(t, s, 0, x, y)
            elif k == 1:
                c = c1 = _coordinate(t, s, 1, x, y)
            else:
                c = 1.0 - c0 - c1
            if c < -eps:
                nb = neighbors[s, k]
                if nb == -1:
                    return -1
                s = nb
                inside = -1
                break
            if not c <= 1.0 + eps:
                inside = 0
        if inside == 1:
            return s
        if inside == 0:
            return _bruteforce(x, y, lo, hi, neighbors, t, eps, eps_broad)
    return _bruteforce(x, y, lo, hi, neighbors, t, eps, eps_broad)


@njit
def _plane(equations: np.ndarray, s: int, x: float, y: float, z: float) -> float:
    """Signed distance of the lifted point (x, y, z) to simplex s's facet (qh_distplane)."""
    d = equations[s, 3]
    d += equations[s, 0] * x
    d += equations[s, 1] * y
    d += equations[s, 2] * z
    return d


@njit
def _weights(x: float, y: float, t: np.ndarray, s: int) -> tuple[float, float, float]:
    """Barycentric weights of (x, y) in simplex s, clipped to [0, 1] and normalized."""
    d0 = x - t[s, 2, 0]
    d1 = y - t[s, 2, 1]
    b0 = _fma(t[s, 0, 0], d0, t[s, 0, 1] * d1)
    b1 = _fma(t[s, 1, 0], d0, t[s, 1, 1] * d1)
    w0, w1, w2 = _unit(b0), _unit(b1), _unit(1.0 - b0 - b1)
    total = w0 + w1 + w2
    return w0 / total, w1 / total, w2 / total


@njit
def _unit(w: float) -> float:
    """np.clip(w, 0, 1) (-0.0 and nan kept)."""
    return 0.0 if w < 0.0 else (1.0 if w > 1.0 else w)


@njit
def _nearest(balls: np.ndarray, x: float, y: float) -> int:
    """np.argmin of the squared distances of the samples to (x, y) (the first nan wins)."""
    best, best_d = 0, math.inf
    for k in range(balls.shape[0]):
        dx = balls[k, 0] - x
        dy = balls[k, 1] - y
        d = dx * dx + dy * dy
        if d != d:
            return k
        if d < best_d:
            best, best_d = k, d
    return best


@njit
def _interpolate(x: float, y: float, lo_box: np.ndarray, hi_box: np.ndarray, equations: np.ndarray,
                 neighbors: np.ndarray, t: np.ndarray, simplices: np.ndarray, scale: float,
                 shift: float, balls: np.ndarray, positions: np.ndarray, follow: np.ndarray,
                 lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(roles, 2) positions for the ball at (x, y): barycentric in its simplex (exactly a
    sample's at the sample), the nearest sample's outside; followers at the ball; clipped."""
    n_roles = positions.shape[1]
    pos = np.empty((n_roles, 2))
    s = find_simplex(x, y, lo_box, hi_box, equations, neighbors, t, scale, shift) if t.shape[0] else -1
    if s >= 0:
        w0, w1, w2 = _weights(x, y, t, s)
        i0, i1, i2 = simplices[s, 0], simplices[s, 1], simplices[s, 2]
        exact = -1
        for j in (i0, i1, i2):
            if balls[j, 0] == x and balls[j, 1] == y:
                exact = j
                break
        for r in range(n_roles):
            for d in range(2):
                if exact >= 0:
                    pos[r, d] = positions[exact, r, d]
                else:
                    pos[r, d] = ((0.0 + w0 * positions[i0, r, d]) + w1 * positions[i1, r, d]
                                 ) + w2 * positions[i2, r, d]
    else:
        pos[:, :] = positions[_nearest(balls, x, y)]
    for r in range(n_roles):
        if follow[r]:
            pos[r, 0] = x
            pos[r, 1] = y
        for d in range(2):
            v = pos[r, d]
            v = v if (v > lo[d] or v != v) else lo[d]
            pos[r, d] = v if (v < hi[d] or v != v) else hi[d]
    return pos


@njit
def formation_positions(bx: float, by: float, rows: np.ndarray, mirror: np.ndarray,
                        lo_box: np.ndarray, hi_box: np.ndarray, equations: np.ndarray,
                        neighbors: np.ndarray, t: np.ndarray, simplices: np.ndarray, scale: float,
                        shift: float, balls: np.ndarray, positions: np.ndarray, follow: np.ndarray,
                        lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """(len(rows), 2) positions of the roles `rows` for the ball at (bx, by) (m), as
    `formations.delaunay.Formation` defines them. A non-empty `mirror` (each role's
    partner) makes a ball at y < 0 the mirror image of the ball at -y."""
    flip = mirror.shape[0] > 0 and by < 0
    full = _interpolate(bx, -by if flip else by, lo_box, hi_box, equations, neighbors, t, simplices,
                        scale, shift, balls, positions, follow, lo, hi)
    out = np.empty((rows.shape[0], 2))
    for i in range(rows.shape[0]):
        if flip:
            r = mirror[rows[i]]
            out[i, 0] = full[r, 0]
            out[i, 1] = -full[r, 1]
        else:
            out[i, 0] = full[rows[i], 0]
            out[i, 1] = full[rows[i], 1]
    return out


# ------------------------------------------------------------------ walking costs

@njit
def walking_costs(players: np.ndarray, targets: np.ndarray, face_within: float, turn_cost: float,
                  fallen_penalty: float) -> np.ndarray:
    """(k, m) costs (m) of (k, 4) players (x, y, heading, fallen 0/1) walking to (m, 2)
    targets: the distance, `turn_cost` per half turn toward the target when farther than
    `face_within`, `fallen_penalty` for a fallen player (numpy's elementwise order and
    libm's hypot and atan2, as `agent.strategy.walking_costs` computed them)."""
    k, m = players.shape[0], targets.shape[0]
    out = np.empty((k, m))
    for i in range(k):
        x, y, heading, fallen = players[i, 0], players[i, 1], players[i, 2], players[i, 3]
        for j in range(m):
            dx = targets[j, 0] - x
            dy = targets[j, 1] - y
            dist = math.hypot(dx, dy)
            turn = 0.0
            if dist > face_within:
                turn = abs((math.atan2(dy, dx) - heading + math.pi) % (2.0 * math.pi) - math.pi) / math.pi
            out[i, j] = dist + turn_cost * turn + fallen_penalty * fallen
    return out


@njit
def avoid_step(px: float, py: float, tx: float, ty: float, dist: float, obstacles: np.ndarray,
               proximity: float, collision: float) -> tuple[bool, float, float]:
    """`agent.strategy.avoid` past its early returns, from (px, py) toward (tx, ty) at
    `dist` (m, > 1e-6) with (k >= 1, 2+) obstacles: (False, ...) to keep the target, else
    (True, x, y), the point to walk toward. The products repeat numpy's: the obstacles'
    (k, 2) @ (2,) is fma(a0, v0, a1 v1) per row for k >= 2 (OpenBLAS's dgemv), the one row
    and the 2-vector dot are (a0 v0 + a1 v1)."""
    wx = (tx - px) / dist
    wy = (ty - py) / dist
    k = obstacles.shape[0]
    best, best_d = -1, math.inf
    for i in range(k):
        rx = obstacles[i, 0] - px
        ry = obstacles[i, 1] - py
        d = math.hypot(rx, ry)
        ahead = _fma(rx, wx, ry * wy) if k >= 2 else rx * wx + ry * wy
        if d < proximity and d < dist and d > 1e-6 and ahead > 0.0 and d < best_d:
            best, best_d = i, d
    if best < 0:
        return False, 0.0, 0.0
    ux = (obstacles[best, 0] - px) / best_d
    uy = (obstacles[best, 1] - py) / best_d
    sx, sy = -uy, ux  # the tangent passing the obstacle on its right ...
    if not sx * wx + sy * wy >= 0:
        sx, sy = -sx, -sy  # ... or on its left, whichever leads on
    if best_d < collision:
        sx, sy = sx - ux, sy - uy
    norm = math.hypot(sx, sy)
    norm = 1e-9 if 1e-9 > norm else norm
    reach = proximity if proximity < dist else dist
    return True, px + sx / norm * reach, py + sy / norm * reach


# ---------------------------------------------------------------------- marking

@njit
def marking_mask(opponents: np.ndarray, bx: float, by: float, gx: float, gy: float, marked: np.ndarray,
                 hysteresis: float, shot_range: float, min_ball_distance: float,
                 max_behind_ball: float) -> np.ndarray:
    """`formations.marking.opponents_to_mark` of (k >= 1, 2) opponents, the ball at (bx, by)
    and our goal at (gx, gy) (m); `marked` (k,) or empty for none. The opponent nearest
    the ball is np.argmin's: the first least distance, or the first nan."""
    k = opponents.shape[0]
    to_ball = np.empty(k)
    closest = -1
    for i in range(k):
        dx = opponents[i, 0] - bx
        dy = opponents[i, 1] - by
        d = math.sqrt(dx * dx + dy * dy)
        to_ball[i] = d
        if closest < 0 or (to_ball[closest] == to_ball[closest] and (d != d or d < to_ball[closest])):
            closest = i
    out = np.empty(k, np.bool_)
    for i in range(k):
        s = hysteresis if marked.shape[0] and marked[i] else 0.0
        dx = opponents[i, 0] - gx
        dy = opponents[i, 1] - gy
        out[i] = (i != closest and math.sqrt(dx * dx + dy * dy) <= shot_range + s
                  and to_ball[i] >= min_ball_distance - s and opponents[i, 0] - bx <= max_behind_ball + s)
    return out

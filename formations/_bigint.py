"""MMDR as one Hungarian on exact 2^rank edge weights (numba, multiword integers).

Weights 2^rank (Algorithm 1 ranks: index in the sorted edge list of the
first equal edge) make any edge heavier than all shorter edges together, so
a min-sum assignment on them is the lexicographic (MMDR) optimum. Sums of
such weights need about one bit per edge: they are kept as fixed-width two's
complement integers, `words` little-endian uint64 each, and the Hungarian
algorithm (`_lsap.lsap_dense`'s shortest augmenting paths) runs on them
exactly. Edges longer than the bottleneck are dropped first (no MMDR mapping
uses them), and for n <= 64 so are the edges under it that lie in no
perfect matching of that graph; ranks count only the edges kept, which
shortens the integers to their number. If that is at most about 50,
float64 holds every value exactly and the compiled float Hungarian
(`lsap_dense`) runs instead: at n = 10 on the 100 x 100 grid, 95% of
problems (74% before the matching test).
"""

from __future__ import annotations

import math

import numpy as np

from formations._jit import njit
from formations._lsap import flip_path, lsap_dense
from formations.bottleneck import MATCHABLE_MAX_N, bottleneck_dense, bottleneck_large, matchable_edges

ONE = np.uint64(1)
SIGN = np.uint64(1) << np.uint64(63)


@njit
def _sub(a, b, out) -> None:
    """out = a - b (mod 2^(64 words))."""
    borrow = np.uint64(0)
    for q in range(a.size):
        x = a[q]
        y = b[q]
        d = x - y
        b1 = d > x
        d2 = d - borrow
        b2 = d2 > d
        out[q] = d2
        borrow = ONE if (b1 or b2) else np.uint64(0)


@njit
def _add(a, b, out) -> None:
    """out = a + b (mod 2^(64 words))."""
    carry = np.uint64(0)
    for q in range(a.size):
        x = a[q]
        s = x + b[q]
        c1 = s < x
        s2 = s + carry
        c2 = s2 < s
        out[q] = s2
        carry = ONE if (c1 or c2) else np.uint64(0)


@njit
def _add_power(x, r: int) -> None:
    """x += 2^r."""
    q = r >> 6
    old = x[q]
    x[q] = old + (ONE << np.uint64(r & 63))
    if x[q] < old:
        q += 1
        while q < x.size:
            x[q] += ONE
            if x[q] != 0:
                break
            q += 1


@njit
def _less(a, b) -> bool:
    """a < b, signed."""
    top = a.size - 1
    if a[top] != b[top]:
        return (a[top] ^ SIGN) < (b[top] ^ SIGN)
    for q in range(top - 1, -1, -1):
        if a[q] != b[q]:
            return a[q] < b[q]
    return False


@njit
def _ranks(value: np.ndarray, edge: np.ndarray, rank: np.ndarray) -> None:
    """rank[edge[q]] = how many of `value` are < value[q] (Algorithm 1's rank).

    Short lists count directly: a branch-free O(k^2) loop beats sorting
    when the problems differ from call to call (no learnt branches).
    """
    k = value.size
    if k > 128:
        order = np.argsort(value, kind="mergesort")
        start = 0
        for q in range(k):
            if q > 0 and value[order[q]] != value[order[q - 1]]:
                start = q
            rank[edge[order[q]]] = start
        return
    for q in range(k):
        x = value[q]
        c = 0
        for p in range(k):
            c += value[p] < x
        rank[edge[q]] = c


@njit
def mmdr_n5(cost: np.ndarray, dense_max: int) -> np.ndarray:
    """MMDR by the Hungarian algorithm on exact weights 2^rank (Alg. 1), edges <= the bottleneck.

    The bottleneck comes from `bottleneck_dense` up to `dense_max` rows,
    else `bottleneck_large`.
    """
    n = cost.shape[0]
    if n <= dense_max:
        b, match = bottleneck_dense(cost, np.full(n, -1, np.int64))
    else:
        b, match = bottleneck_large(cost)[:2]
    flat = cost.ravel()
    rank = np.full(n * n, -1, np.int64)  # -1: dropped edge
    edge = np.empty(n * n, np.int64)
    value = np.empty(n * n)
    k = 0
    if n <= MATCHABLE_MAX_N:
        k = matchable_edges(cost, b, match, edge, value)
    else:
        for e in range(n * n):
            if flat[e] <= b:
                edge[k] = e
                value[k] = flat[e]
                k += 1
    _ranks(value[:k], edge[:k], rank)
    if k + math.ceil(math.log2(2 * n)) <= 53:
        # Few edges: every value of the algorithm is an integer below
        # 2 n 2^edges (each row's path length is the rise of the matching
        # cost, so potentials stay within the final cost n C, C < 2^edges / 2),
        # which float64 holds exactly.
        weights = np.full(n * n, np.inf)
        for q in range(k):
            e = edge[q]
            weights[e] = math.ldexp(1.0, rank[e])
        return lsap_dense(weights.reshape(n, n))[0]
    return hungarian_pow2(rank.reshape(n, n), k)


@njit
def hungarian_pow2(rank: np.ndarray, edges: int) -> np.ndarray:
    """Min-sum assignment on weights 2^rank[i, j] (rank < `edges`; -1: no edge), exact.

    `lsap_dense`'s algorithm on multiword two's complement integers.
    """
    n = rank.shape[0]
    rank = rank.ravel()
    words = (edges + 40) // 64 + 1  # |values| < 2 n 2^edges: room for n < 2^38, signed
    u = np.zeros((n, words), np.uint64)
    v = np.zeros((n, words), np.uint64)
    spc = np.zeros((n, words), np.uint64)
    has = np.zeros(n, np.bool_)  # spc[j] is finite
    min_val = np.zeros(words, np.uint64)
    base = np.zeros(words, np.uint64)
    r = np.zeros(words, np.uint64)
    lowest = np.zeros(words, np.uint64)
    path = np.full(n, -1, np.int64)
    col4row = np.full(n, -1, np.int64)
    row4col = np.full(n, -1, np.int64)
    sr = np.zeros(n, np.bool_)
    sc = np.zeros(n, np.bool_)
    remaining = np.empty(n, np.int64)
    for cur in range(n):
        for it in range(n):
            remaining[it] = n - it - 1
        sr[:] = False
        sc[:] = False
        has[:] = False
        num = n
        min_val[:] = 0
        i = cur
        sink = -1
        while sink == -1:
            index = -1
            sr[i] = True
            _sub(min_val, u[i], base)
            for it in range(num):
                j = remaining[it]
                rk = rank[i * n + j]
                if rk >= 0:
                    r[:] = base
                    _add_power(r, rk)
                    _sub(r, v[j], r)
                    if not has[j] or _less(r, spc[j]):
                        path[j] = i
                        spc[j] = r
                        has[j] = True
                if has[j] and (
                    index < 0 or _less(spc[j], lowest) or (row4col[j] == -1 and not _less(lowest, spc[j]))
                ):
                    lowest[:] = spc[j]
                    index = it
            if index < 0:  # pragma: no cover - the edges <= the bottleneck have a perfect matching
                raise ValueError("no perfect matching")
            min_val[:] = lowest
            j = remaining[index]
            if row4col[j] == -1:
                sink = j
            else:
                i = row4col[j]
            sc[j] = True
            num -= 1
            remaining[index] = remaining[num]
        _add(u[cur], min_val, u[cur])
        for q in range(n):
            if sr[q] and q != cur:
                _sub(min_val, spc[col4row[q]], r)
                _add(u[q], r, u[q])
        for c in range(n):
            if sc[c]:
                _sub(min_val, spc[c], r)
                _sub(v[c], r, v[c])
        flip_path(path, col4row, row4col, sink, cur)
    return col4row

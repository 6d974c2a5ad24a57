"""Bottleneck (minimal longest edge) perfect matchings, compiled with numba.

The answer is at least `lower`, the largest row or column minimum. A
matching of the edges <= `lower` (the warm start's edges there, then greedy,
then depth-first augmenting paths on those edges) is completed one free row
at a time by a minimax augmenting path: a Dijkstra search whose path length
is the longest edge not already in the matching. Augmenting along it raises
the threshold to that length. While the matching uses only edges <= the
bottleneck, a perfect matching of those edges holds an augmenting path from
any free row, so the threshold never passes the bottleneck and ends on it.

`bottleneck_dense` scans a dense matrix (small n); `bottleneck_large` first
cuts a dense matrix down to candidate edges <= a sampled threshold and runs
`bottleneck_sparse` on them (binary heap), raising the threshold until the
candidates admit a perfect matching.
"""

from __future__ import annotations

import numpy as np

from formations._jit import njit
from formations._lsap import _heap_pop, _heap_push, flip_path

INF = np.inf
_ONE = np.uint64(1)
MATCHABLE_MAX_N = 64  # rows as bits of one uint64: the most `matchable_edges` takes


@njit
def _augment_at(w, t, col4row, row4col, r, parent, seen, stack_r, stack_j) -> bool:
    """Augmenting path from free row r over edges w <= t (iterative DFS, dense scan)."""
    n = w.shape[0]
    seen[:] = False
    top = 0
    stack_r[0] = r
    stack_j[0] = 0
    while top >= 0:
        i = stack_r[top]
        j = stack_j[top]
        found = -1
        while j < n:
            if not seen[j] and w[i, j] <= t:
                seen[j] = True
                found = j
                break
            j += 1
        stack_j[top] = j + 1
        if found < 0:
            top -= 1
            continue
        parent[found] = i
        nxt = row4col[found]
        if nxt < 0:
            flip_path(parent, col4row, row4col, found, r)
            return True
        top += 1
        stack_r[top] = nxt
        stack_j[top] = 0
    return False


@njit
def _minimax_augment(w, col4row, row4col, r, key, parent, done) -> float:
    """Augments from free row r along the path of least longest edge; returns that length.

    Matched edges count as free. Returns inf (matching unchanged) if no
    augmenting path of finite edges exists.
    """
    n = w.shape[0]
    key[:] = INF
    done[:] = False
    i = r
    ki = -INF
    while True:
        best = INF
        bj = -1
        for j in range(n):
            if done[j]:
                continue
            k = w[i, j]
            if k < ki:
                k = ki
            if k < key[j]:
                key[j] = k
                parent[j] = i
            kj = key[j]
            if kj < best or (kj == best and row4col[j] < 0):
                best = kj
                bj = j
        if bj < 0 or best == INF:
            return INF
        done[bj] = True
        if row4col[bj] < 0:
            flip_path(parent, col4row, row4col, bj, r)
            return best
        i = row4col[bj]
        ki = best


@njit
def bottleneck_dense(w: np.ndarray, init: np.ndarray) -> tuple[float, np.ndarray]:
    """Bottleneck value of the square matrix `w` (inf = no edge) and a perfect matching attaining it.

    `init` (column of each row, -1 if none) warm-starts the search; its
    edges longer than the lower bound are dropped. Returns (inf, matching
    with -1) if the finite edges admit no perfect matching.
    """
    n = w.shape[0]
    lower = -INF
    for i in range(n):
        m = INF
        for j in range(n):
            if w[i, j] < m:
                m = w[i, j]
        if m > lower:
            lower = m
    for j in range(n):
        m = INF
        for i in range(n):
            if w[i, j] < m:
                m = w[i, j]
        if m > lower:
            lower = m
    col4row = np.full(n, -1, np.int64)
    row4col = np.full(n, -1, np.int64)
    if lower == INF:
        return INF, col4row
    for i in range(n):
        j = init[i]
        if j >= 0 and w[i, j] <= lower and row4col[j] < 0:
            col4row[i] = j
            row4col[j] = i
    for i in range(n):  # greedy
        if col4row[i] >= 0:
            continue
        for j in range(n):
            if row4col[j] < 0 and w[i, j] <= lower:
                col4row[i] = j
                row4col[j] = i
                break
    parent = np.empty(n, np.int64)
    seen = np.empty(n, np.bool_)
    stack_r = np.empty(n + 1, np.int64)
    stack_j = np.empty(n + 1, np.int64)
    t = lower
    for r in range(n):
        if col4row[r] < 0:
            _augment_at(w, t, col4row, row4col, r, parent, seen, stack_r, stack_j)
    key = np.empty(n)
    for r in range(n):
        if col4row[r] >= 0:
            continue
        k = _minimax_augment(w, col4row, row4col, r, key, parent, seen)
        if k == INF:
            return INF, col4row
        if k > t:
            t = k
    return t, col4row


@njit
def _sparse_augment_at(indptr, indices, w, t, col4row, row4col, r, parent, seen, stack_r, stack_e) -> bool:
    """Augmenting path from free row r over the CSR edges with w <= t (iterative DFS)."""
    top = 0
    stack_r[0] = r
    stack_e[0] = indptr[r]
    while top >= 0:
        i = stack_r[top]
        e = stack_e[top]
        end = indptr[i + 1]
        found = -1
        while e < end:
            j = indices[e]
            if not seen[j] and w[e] <= t:
                seen[j] = True
                found = j
                break
            e += 1
        stack_e[top] = e + 1
        if found < 0:
            top -= 1
            continue
        parent[found] = i
        nxt = row4col[found]
        if nxt < 0:
            flip_path(parent, col4row, row4col, found, r)
            return True
        top += 1
        stack_r[top] = nxt
        stack_e[top] = indptr[nxt]
    return False


@njit
def _sparse_minimax_augment(
    indptr, indices, w, col4row, row4col, r, key, parent, done, touched, hk, hv
) -> float:
    """`_minimax_augment` over CSR edges, with a binary heap; key and done are left reset."""
    nt = 0
    size = 0
    i = r
    ki = -INF
    result = INF
    while True:
        for e in range(indptr[i], indptr[i + 1]):
            j = indices[e]
            if done[j]:
                continue
            k = w[e]
            if k < ki:
                k = ki
            if k < key[j]:
                if key[j] == INF:
                    touched[nt] = j
                    nt += 1
                key[j] = k
                parent[j] = i
                size = _heap_push(hk, hv, size, k, j)
        bj = -1
        while size > 0:
            k = hk[0]
            c = hv[0]
            size = _heap_pop(hk, hv, size)
            if not done[c] and k == key[c]:
                bj = c
                break
        if bj < 0:
            break
        done[bj] = True
        if row4col[bj] < 0:
            result = key[bj]
            flip_path(parent, col4row, row4col, bj, r)
            break
        i = row4col[bj]
        ki = key[bj]
    for m in range(nt):
        key[touched[m]] = INF
        done[touched[m]] = False
    return result


@njit
def bottleneck_sparse(n, indptr, indices, w, lower, init) -> tuple[float, np.ndarray]:
    """`bottleneck_dense` over CSR edges (w[e] of edge e), from the lower bound `lower`.

    Returns (inf, partial matching) if the edges admit no perfect matching.
    """
    col4row = np.full(n, -1, np.int64)
    row4col = np.full(n, -1, np.int64)
    for i in range(n):
        j = init[i]
        if j >= 0 and row4col[j] < 0:
            for e in range(indptr[i], indptr[i + 1]):
                if indices[e] == j and w[e] <= lower:
                    col4row[i] = j
                    row4col[j] = i
                    break
    for i in range(n):
        if col4row[i] >= 0:
            continue
        for e in range(indptr[i], indptr[i + 1]):
            j = indices[e]
            if row4col[j] < 0 and w[e] <= lower:
                col4row[i] = j
                row4col[j] = i
                break
    parent = np.empty(n, np.int64)
    seen = np.zeros(n, np.bool_)
    stack_r = np.empty(n + 1, np.int64)
    stack_e = np.empty(n + 1, np.int64)
    for r in range(n):  # depth-first augmenting paths at the lower bound
        if col4row[r] < 0 and _sparse_augment_at(
            indptr, indices, w, lower, col4row, row4col, r, parent, seen, stack_r, stack_e
        ):
            seen[:] = False
    key = np.full(n, INF)
    done = np.zeros(n, np.bool_)
    touched = np.empty(n, np.int64)
    hk = np.empty(indices.size + 1)
    hv = np.empty(indices.size + 1, np.int64)
    t = lower
    for r in range(n):
        if col4row[r] >= 0:
            continue
        k = _sparse_minimax_augment(
            indptr, indices, w, col4row, row4col, r, key, parent, done, touched, hk, hv
        )
        if k == INF:
            return INF, col4row
        if k > t:
            t = k
    return t, col4row


@njit
def _lower_bound(cost) -> float:
    """Largest row or column minimum of a square matrix."""
    n = cost.shape[0]
    lower = -INF
    colmin = np.full(n, INF)
    for i in range(n):
        m = INF
        for j in range(n):
            c = cost[i, j]
            if c < m:
                m = c
            if c < colmin[j]:
                colmin[j] = c
        if m > lower:
            lower = m
    for j in range(n):
        if colmin[j] > lower:
            lower = colmin[j]
    return lower


@njit
def candidate_edges(cost, theta):
    """CSR (indptr, indices, weights) of the entries <= theta of a square matrix."""
    n = cost.shape[0]
    count = 0
    for i in range(n):
        for j in range(n):
            if cost[i, j] <= theta:
                count += 1
    indptr = np.zeros(n + 1, np.int64)
    indices = np.empty(count, np.int64)
    weights = np.empty(count)
    e = 0
    for i in range(n):
        for j in range(n):
            c = cost[i, j]
            if c <= theta:
                indices[e] = j
                weights[e] = c
                e += 1
        indptr[i + 1] = e
    return indptr, indices, weights


@njit
def _select(x: np.ndarray, k: int) -> float:
    """k-th smallest value of x (quickselect, reorders x; `np.partition` compiles far slower)."""
    lo = 0
    hi = x.size - 1
    while lo < hi:
        pivot = x[(lo + hi) >> 1]
        i = lo
        j = hi
        while i <= j:
            while x[i] < pivot:
                i += 1
            while x[j] > pivot:
                j -= 1
            if i <= j:
                x[i], x[j] = x[j], x[i]
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            break
    return x[k]


@njit
def bottleneck_large(cost) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Bottleneck of a large dense matrix through sparse candidate edges.

    Candidates are the entries <= theta, theta about the (8 n 4^k)-th
    smallest cost (estimated on a strided sample), k = 0, 1, ... until the
    candidates admit a perfect matching; then every edge <= the bottleneck
    is a candidate and the answer is exact. Returns (b, matching, indptr,
    indices, weights) with the last candidate set (all edges <= theta >= b).
    """
    n = cost.shape[0]
    lower = _lower_bound(cost)
    flat = cost.ravel()
    stride = max(1, flat.size // (64 * n))
    sample = flat[::stride].copy()
    budget = 8 * n
    match = np.full(n, -1, np.int64)
    while True:
        k = budget // stride
        if k < sample.size:
            theta = max(lower, _select(sample, k))
        else:
            theta = INF
        indptr, indices, weights = candidate_edges(cost, theta)
        b, m = bottleneck_sparse(n, indptr, indices, weights, lower, match)
        if b < INF or theta == INF:
            return b, m, indptr, indices, weights
        match = m
        budget *= 4


def bottleneck(cost: np.ndarray) -> tuple[float, np.ndarray]:
    """Bottleneck value of a square cost matrix and a perfect matching (column of each row) attaining it."""
    cost = np.ascontiguousarray(cost, dtype=float)
    n = cost.shape[0]
    if cost.ndim != 2 or cost.shape != (n, n):
        raise ValueError(f"cost must be square, got {cost.shape}")
    if n == 0:
        return 0.0, np.zeros(0, dtype=np.int64)
    value, match = bottleneck_large(cost)[:2]
    if value == INF:
        raise ValueError("cost has no perfect matching of finite edges")
    return float(value), match


@njit
def matchable_edges(
    cost: np.ndarray, b: float, match: np.ndarray, edge: np.ndarray, value: np.ndarray
) -> int:
    """The edges <= b that lie in some perfect matching of that graph, n <= MATCHABLE_MAX_N.

    `match` is one perfect matching (column of each row). Edge (i, j) is in
    another one iff it closes an alternating cycle: the row matched to j
    reaches row i, where row r -> row s whenever r has an edge to s's
    column. Reachability is a bitset closure. Writes the flat indices and
    costs to `edge` and `value`; returns how many.
    """
    n = cost.shape[0]
    row4col = np.empty(n, np.int64)
    for i in range(n):
        row4col[match[i]] = i
    reach = np.zeros(n, np.uint64)
    for i in range(n):
        bits = np.uint64(0)
        for j in range(n):
            if cost[i, j] <= b:
                bits |= _ONE << np.uint64(row4col[j])
        reach[i] = bits
    for m in range(n):
        via = reach[m]
        for i in range(n):
            hit = (reach[i] >> np.uint64(m)) & _ONE
            reach[i] |= via & (np.uint64(0) - hit)
    k = 0
    for i in range(n):
        for j in range(n):
            c = cost[i, j]
            if c <= b and ((reach[row4col[j]] >> np.uint64(i)) & _ONE) != 0:
                edge[k] = i * n + j
                value[k] = c
                k += 1
    return k

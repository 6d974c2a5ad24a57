"""Compiled min-sum assignment (numba): dense and sparse shortest augmenting paths.

`lsap_dense` is step for step the algorithm of
`scipy.optimize.linear_sum_assignment` (Crouse's shortest augmenting path,
one Dijkstra search per row, the same scan order and tie rules), so on the
same square matrix it returns the same assignment, without scipy's call
overhead (a few microseconds at n = 10). Infinite costs are forbidden pairs.
It also returns the optimal duals. `lsap_sparse` runs the same algorithm on
a CSR edge list with a binary heap, for large sparse problems (its ties may
differ from the dense one).
"""

from __future__ import annotations

import numpy as np

from formations._jit import njit

INF = np.inf


@njit
def flip_path(path, col4row, row4col, c, r) -> None:
    """Augments the matching along the alternating path that ends at free column c and
    starts at free row r (path[j]: the row the search reached column j from)."""
    while True:
        i = path[c]
        old = col4row[i]
        col4row[i] = c
        row4col[c] = i
        if i == r:
            return
        c = old


@njit
def lsap_dense(cost: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Min-sum perfect matching of a square float matrix (inf = forbidden).

    Returns (col4row, u, v): the column of each row and optimal duals with
    cost - u[:, None] - v[None, :] >= 0, == 0 on the matching. If no perfect
    matching of finite cost exists, col4row[0] is -2.
    """
    n = cost.shape[0]
    u = np.zeros(n)
    v = np.zeros(n)
    spc = np.empty(n)
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
        spc[:] = INF
        num = n
        min_val = 0.0
        i = cur
        sink = -1
        while sink == -1:
            index = -1
            lowest = INF
            sr[i] = True
            ui = u[i]
            for it in range(num):
                j = remaining[it]
                r = min_val + cost[i, j] - ui - v[j]  # scipy's order of operations
                if r < spc[j]:
                    path[j] = i
                    spc[j] = r
                s = spc[j]
                if s < lowest or (s == lowest and row4col[j] == -1):
                    lowest = s
                    index = it
            min_val = lowest
            if min_val == INF:
                col4row[0] = -2
                return col4row, u, v
            j = remaining[index]
            if row4col[j] == -1:
                sink = j
            else:
                i = row4col[j]
            sc[j] = True
            num -= 1
            remaining[index] = remaining[num]
        u[cur] += min_val
        for r in range(n):
            if sr[r] and r != cur:
                u[r] += min_val - spc[col4row[r]]
        for c in range(n):
            if sc[c]:
                v[c] -= min_val - spc[c]
        flip_path(path, col4row, row4col, sink, cur)
    return col4row, u, v


@njit
def _heap_push(hk: np.ndarray, hv: np.ndarray, size: int, key: float, val: int) -> int:
    pos = size
    while pos > 0:
        parent = (pos - 1) >> 1
        if hk[parent] <= key:
            break
        hk[pos] = hk[parent]
        hv[pos] = hv[parent]
        pos = parent
    hk[pos] = key
    hv[pos] = val
    return size + 1


@njit
def _heap_pop(hk: np.ndarray, hv: np.ndarray, size: int) -> int:
    """Removes the root (read hk[0], hv[0] before); returns the new size."""
    size -= 1
    key = hk[size]
    val = hv[size]
    pos = 0
    while True:
        child = 2 * pos + 1
        if child >= size:
            break
        if child + 1 < size and hk[child + 1] < hk[child]:
            child += 1
        if hk[child] >= key:
            break
        hk[pos] = hk[child]
        hv[pos] = hv[child]
        pos = child
    hk[pos] = key
    hv[pos] = val
    return size


@njit
def lsap_sparse(
    n: int, indptr: np.ndarray, indices: np.ndarray, weights: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Min-sum perfect matching over a CSR edge list (row i: indices[indptr[i]:indptr[i+1]]).

    Column and row reduction and a greedy start, then shortest augmenting
    paths from each free row in turn (Dijkstra on reduced costs with a
    binary heap, lazy deletion). Returns (col4row, u, v) as `lsap_dense`;
    col4row[0] is -2 if the edges admit no perfect matching.
    """
    u = np.zeros(n)
    v = np.zeros(n)
    dist = np.full(n, INF)
    path = np.full(n, -1, np.int64)
    col4row = np.full(n, -1, np.int64)
    row4col = np.full(n, -1, np.int64)
    done = np.zeros(n, np.bool_)
    touched = np.empty(n, np.int64)
    cap = indices.size + n + 1
    hk = np.empty(cap)
    hv = np.empty(cap, np.int64)
    rows_seen = np.empty(n, np.int64)
    # Column then row reduction give feasible duals; rows matched greedily
    # along zero reduced-cost edges need no search.
    v[:] = INF
    for e in range(indices.size):
        if weights[e] < v[indices[e]]:
            v[indices[e]] = weights[e]
    for i in range(n):
        m = INF
        for e in range(indptr[i], indptr[i + 1]):
            r = weights[e] - v[indices[e]]
            if r < m:
                m = r
        if m == INF:
            col4row[0] = -2
            return col4row, u, v
        u[i] = m
        for e in range(indptr[i], indptr[i + 1]):
            j = indices[e]
            if row4col[j] < 0 and weights[e] - v[j] == m:
                row4col[j] = i
                col4row[i] = j
                break
    for cur in range(n):
        if col4row[cur] >= 0:
            continue
        nt = 0
        nr = 0
        size = 0
        i = cur
        d_i = 0.0
        sink = -1
        min_val = 0.0
        while True:
            rows_seen[nr] = i
            nr += 1
            for e in range(indptr[i], indptr[i + 1]):
                j = indices[e]
                if done[j]:
                    continue
                r = d_i + weights[e] - u[i] - v[j]
                if r < dist[j]:
                    if dist[j] == INF:
                        touched[nt] = j
                        nt += 1
                    dist[j] = r
                    path[j] = i
                    size = _heap_push(hk, hv, size, r, j)
            j = -1
            while size > 0:
                key = hk[0]
                c = hv[0]
                size = _heap_pop(hk, hv, size)
                if not done[c] and key == dist[c]:
                    j = c
                    break
            if j < 0:
                col4row[0] = -2
                return col4row, u, v
            done[j] = True
            min_val = dist[j]
            if row4col[j] == -1:
                sink = j
                break
            i = row4col[j]
            d_i = min_val
        # Duals: rows reached and finalized columns move by min_val - dist.
        u[cur] += min_val
        for k in range(1, nr):
            r = rows_seen[k]
            u[r] += min_val - dist[col4row[r]]
        for k in range(nt):
            c = touched[k]
            if done[c]:
                v[c] -= min_val - dist[c]
        flip_path(path, col4row, row4col, sink, cur)
        for k in range(nt):
            c = touched[k]
            dist[c] = INF
            done[c] = False
    return col4row, u, v

"""Bottleneck (minimal longest edge) perfect matchings on bipartite graphs.

The minimal maximum edge of a perfect matching is found by binary search over
the sorted distinct edge weights, testing each threshold for a perfect
matching with phases of shortest augmenting paths (Hopcroft-Karp style,
vectorized with numpy). The largest matching found below the answer
warm-starts every later test, so each test needs only a few augmentations;
large tests that start from scratch or far from perfect run as a unit
capacity max flow instead (`scipy.sparse.csgraph.maximum_flow`, Dinic,
compiled). scipy's `maximum_bipartite_matching` is not used: on some of these
graphs it takes seconds where the flow takes milliseconds.
Dense problems are first cut down to a sparse candidate edge set: the answer is
at least the largest row or column minimum (the search starts there), and
usually only a few edges above that bound are ever needed; the cut is
estimated on a strided sample of the costs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import maximum_flow

FLOW_MIN_EDGES = 4096  # maximum matchings with this many edges may use the compiled max flow:
FLOW_MIN_FREE = 8  # those that start with more free rows than this (or cold)


@dataclass
class EdgeList:
    """Edges of a bipartite graph with n rows and n columns, sorted by key."""

    n: int
    rows: np.ndarray
    cols: np.ndarray
    keys: np.ndarray

    def take(self, mask_or_index: np.ndarray) -> EdgeList:
        return EdgeList(self.n, self.rows[mask_or_index], self.cols[mask_or_index], self.keys[mask_or_index])


def flow_matching(n: int, rows: np.ndarray, cols: np.ndarray, presorted: bool = False) -> np.ndarray:
    """Maximum matching (column of each row, -1 if free) as a unit-capacity max flow.

    Dinic's algorithm (`scipy.sparse.csgraph.maximum_flow`, compiled,
    O(E sqrt(V)) on these graphs) from a source to every row, along the
    edges, from every column to a sink. `presorted` says the edges are
    already grouped by row in increasing row order. Deterministic.
    """
    rows = np.asarray(rows, dtype=np.int64)
    cols = np.asarray(cols, dtype=np.int64)
    if not presorted:
        order = np.argsort(rows.astype(np.int32) if n < 2**31 else rows, kind="stable")
        rows, cols = rows[order], cols[order]
    size = rows.size
    # Nodes: rows 0..n-1, columns n..2n-1, source 2n, sink 2n+1.
    indptr = np.empty(2 * n + 3, dtype=np.int32)
    indptr[0] = 0
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1 : n + 1])
    indptr[n + 1 : 2 * n + 1] = size + np.arange(1, n + 1)
    indptr[2 * n + 1 :] = size + 2 * n
    indices = np.empty(size + 2 * n, dtype=np.int32)
    indices[:size] = cols + n
    indices[size : size + n] = 2 * n + 1
    indices[size + n :] = np.arange(n)
    graph = csr_matrix((np.ones(size + 2 * n, dtype=np.int32), indices, indptr), shape=(2 * n + 2, 2 * n + 2))
    res = maximum_flow(graph, 2 * n, 2 * n + 1, method="dinic")
    match = np.full(n, -1, dtype=np.int64)
    if res.flow_value == 0:
        return match
    flow = res.flow
    # Row r's edges sit in flow's CSR row r; a unit of flow marks the match.
    fi, fp, fd = flow.indices, flow.indptr, flow.data
    hit = np.flatnonzero(fd[: fp[n]] > 0)
    r_of = np.repeat(np.arange(n), np.diff(fp[: n + 1]))
    match[r_of[hit]] = fi[hit] - n
    return match


def max_matching(n: int, rows: np.ndarray, cols: np.ndarray, init: np.ndarray | None = None) -> np.ndarray:
    """Maximum matching of a bipartite graph by phases of augmenting paths.

    Each phase is a breadth-first search from all free rows at once,
    vectorized over the edge list, followed by augmentation along a maximal
    set of vertex-disjoint shortest augmenting paths (Hopcroft-Karp style).
    `init` (column of each row or -1) must be a matching of the given edges;
    it warm-starts the search. Returns the column of each row, -1 if free.
    Large searches (at least `FLOW_MIN_EDGES` edges, and no `init` or one
    with more than `FLOW_MIN_FREE` free rows) go to the compiled max flow
    (`flow_matching`), which beats many numpy phases.
    """
    if np.size(rows) >= FLOW_MIN_EDGES and (init is None or np.count_nonzero(init < 0) > FLOW_MIN_FREE):
        return flow_matching(n, rows, cols)
    match_row = np.full(n, -1, dtype=np.int64) if init is None else init.astype(np.int64).copy()
    match_col = np.full(n, -1, dtype=np.int64)
    matched = np.flatnonzero(match_row >= 0)
    match_col[match_row[matched]] = matched
    rows = np.asarray(rows, dtype=np.int64)
    cols = np.asarray(cols, dtype=np.int64)
    # Row-major adjacency (CSR) so that a search level costs only the degree
    # of its frontier.
    # Stable sorts of 16-bit integers are radix sorts (linear time).
    order = np.argsort(rows.astype(np.int16) if n < 32768 else rows, kind="stable")
    adj = cols[order]
    indptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(rows, minlength=n), out=indptr[1:])
    while True:
        free_rows = match_row < 0
        if not free_rows.any() or rows.size == 0:
            return match_row
        frontier = np.flatnonzero(free_rows)
        row_seen = free_rows.copy()
        col_parent = np.full(n, -1, dtype=np.int64)
        mark = np.zeros(n, dtype=bool)
        found = None
        while frontier.size:
            starts = indptr[frontier]
            counts = indptr[frontier + 1] - starts
            total = int(counts.sum())
            if total == 0:
                break
            offsets = np.repeat(starts - np.cumsum(counts) + counts, counts)
            c_s = adj[offsets + np.arange(total)]
            r_s = np.repeat(frontier, counts)
            keep = col_parent[c_s] < 0
            if not keep.any():
                break
            r_s, c_s = r_s[keep], c_s[keep]
            # Each newly reached column records one parent row (numpy keeps
            # the last of repeated fancy-index writes; any choice is valid).
            col_parent[c_s] = r_s
            mark[c_s] = True
            reached = np.flatnonzero(mark)
            mark[reached] = False
            free_cols = reached[match_col[reached] < 0]
            if free_cols.size:
                found = free_cols
                break
            nxt = match_col[reached]
            frontier = nxt[~row_seen[nxt]]
            row_seen[frontier] = True
        if found is None:
            return match_row
        used = np.zeros(n, dtype=bool)
        pr = match_row.tolist()
        parent = col_parent.tolist()
        for c in found.tolist():
            path = []
            ok = True
            while True:
                r = parent[c]
                if used[r]:
                    ok = False
                    break
                path.append((r, c))
                if pr[r] < 0:
                    break
                c = pr[r]
            if not ok:
                continue
            for r, c in path:
                used[r] = True
                pr[r] = c
                match_col[c] = r
        match_row = np.asarray(pr, dtype=np.int64)


def perfect_matching(
    n: int, rows: np.ndarray, cols: np.ndarray, init: np.ndarray | None = None
) -> np.ndarray | None:
    """Column of each row in a perfect matching using only the given edges, or None."""
    if rows.size < n:
        return None
    match = max_matching(n, rows, cols, init)
    if np.any(match < 0):
        return None
    return match


def sorted_edges(cost: np.ndarray, index: np.ndarray | None = None) -> EdgeList:
    """EdgeList of a dense (n, n) cost matrix (optionally only flat `index`)."""
    n = cost.shape[0]
    flat = cost.ravel()
    if index is None:
        index = np.arange(flat.size)
    order = np.argsort(flat[index], kind="stable")
    index = index[order]
    return EdgeList(n, index // n, index % n, flat[index])


def bottleneck_edges(
    edges: EdgeList,
    fixed: np.ndarray | None = None,
    upper: int | None = None,
    init: np.ndarray | None = None,
    failed: tuple[int, np.ndarray] | None = None,
) -> tuple[int, np.ndarray]:
    """Minimal threshold over the sorted `edges` admitting a perfect matching.

    `fixed` marks edges that are always allowed whatever the threshold (the
    edges MMDR has already settled). `upper`, if given, is the end index of a
    prefix of the non-fixed edges known to admit a perfect matching (`init`,
    column of each row); the search then gallops down from it. Returns
    (end, matching): the non-fixed edges `[:end]` (ending on a change of key)
    plus the fixed ones admit the perfect `matching` and no shorter key prefix
    does. Raises ValueError if even all edges admit no perfect matching.
    `failed` = (end, matching), if given, is a prefix end (on a change of key)
    known to admit no perfect matching and a maximum matching of it, which
    warm-starts the tests above it.
    """
    n = edges.n
    if fixed is None:
        free_idx = np.arange(edges.keys.size)
        fixed_idx = np.zeros(0, dtype=np.int64)
    else:
        free_idx = np.flatnonzero(~fixed)
        fixed_idx = np.flatnonzero(fixed)
    keys = edges.keys[free_idx]
    # Possible prefix ends: just after each change of key, and the full list.
    ends = np.append(np.flatnonzero(keys[1:] != keys[:-1]) + 1, keys.size)
    fr, fc = edges.rows[fixed_idx], edges.cols[fixed_idx]
    flat_all = edges.rows * n + edges.cols
    base: list[np.ndarray | None] = [None]  # max matching at the largest failed prefix
    best: list[np.ndarray | None] = [init]  # perfect matching at the smallest good prefix

    def test(end: int) -> np.ndarray | None:
        sel = free_idx[:end]
        r = np.concatenate([fr, edges.rows[sel]])
        c = np.concatenate([fc, edges.cols[sel]])
        start = base[0]
        if best[0] is not None:
            # The known perfect matching minus its edges beyond this prefix.
            allowed = np.zeros(n * n, dtype=bool) if n * n <= 4_000_000 else None
            if allowed is not None:
                allowed[flat_all[fixed_idx]] = True
                allowed[flat_all[sel]] = True
                warm = np.where(allowed[np.arange(n) * n + best[0]], best[0], -1)
            else:
                ok = np.isin(np.arange(n) * n + best[0], r * n + c)
                warm = np.where(ok, best[0], -1)
            if start is None or np.count_nonzero(warm >= 0) > np.count_nonzero(start >= 0):
                start = warm
        m = max_matching(n, r, c, start)
        if np.any(m < 0):
            base[0] = m
            return None
        best[0] = m
        return m

    if keys.size == 0:
        match = test(0)
        if match is None:
            raise ValueError("graph has no perfect matching")
        return 0, match
    lo = -1  # ends[lo] known infeasible (virtual)
    if failed is not None:
        lo = int(np.searchsorted(ends, failed[0]))
        if lo >= ends.size or ends[lo] != failed[0]:
            raise ValueError("failed prefix must end on a change of key")
        base[0] = failed[1]
    if fixed is None and keys.size:
        # Every row and column needs an edge: a feasible prefix reaches the
        # first edge of each row and of each column.
        first = np.full(2 * n, keys.size, dtype=np.int64)
        pos = np.arange(keys.size - 1, -1, -1)
        first[edges.rows[::-1]] = pos  # the last write wins: the first edge
        first[n + edges.cols[::-1]] = pos
        lo = max(lo, int(np.searchsorted(ends, int(first.max()) + 1)) - 1)
    if upper is None:
        hi = ends.size - 1
        if test(int(ends[hi])) is None:
            raise ValueError("graph has no perfect matching")
    else:
        hi = int(np.searchsorted(ends, upper))
        if best[0] is None and test(int(ends[hi])) is None:
            raise ValueError("upper bound is not feasible")
        # Gallop down from the known feasible prefix (MMDR's next level is
        # usually just below it); a first bottleneck bisects at once.
        step = 1 if fixed is not None else hi - lo
        while hi - step > lo:
            cand = hi - step
            if test(int(ends[cand])) is None:
                lo = cand
                break
            hi = cand
            step *= 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if test(int(ends[mid])) is None:
            lo = mid
        else:
            hi = mid
    return int(ends[hi]), best[0]


def dense_candidates(cost: np.ndarray) -> tuple[EdgeList, int | None, np.ndarray | None]:
    """Sorted edges of a dense cost matrix sufficient for its bottleneck.

    Every edge no longer than the bottleneck value (ties included) is in the
    returned list, so the list also serves MMD+MSD^2 and MMDR. Returns
    (edges, end, match): if `end` is not None, the prefix `edges[:end]` admits
    the perfect matching `match` (column of each row), bounding the bottleneck.
    """
    return _dense_candidates(cost)[:3]


def _dense_candidates(cost: np.ndarray):
    """`dense_candidates` plus `failed`: (end, maximum matching) of the largest
    prefix tested without a perfect matching, or None (see `bottleneck_edges`).

    The threshold is estimated on a strided sample of the costs (no partition
    of all n^2 values); a threshold that proves too low is raised 4x in count,
    the last maximum matching warm-starting the next test.
    """
    n = cost.shape[0]
    flat = cost.ravel()
    if n <= 64:
        return sorted_edges(cost), None, None, None
    lower = max(cost.min(axis=1).max(), cost.min(axis=0).max())
    budget = 4 * n
    # The threshold only needs to be about the `budget`-th smallest cost above
    # `lower`: estimate it on a strided sample rather than partition n^2 values.
    stride = max(1, flat.size // (64 * n))
    sample = flat[::stride]
    sample = sample[sample > lower]
    failed = warm = None
    while True:
        k = budget // stride
        threshold = np.partition(sample, k)[k] if k < sample.size else np.inf
        index = np.flatnonzero(flat <= threshold)
        edges = sorted_edges(cost, index)
        if threshold == np.inf:
            return edges, None, None, failed
        # Edges equal to the threshold may be excluded from the prefix test but
        # the list must hold every edge up to the bottleneck, ties included.
        end = int(np.searchsorted(edges.keys, threshold, side="left"))
        match = max_matching(n, edges.rows[:end], edges.cols[:end], warm)
        if np.all(match >= 0):
            return edges, end, match, failed
        failed = (end, match)
        warm = match
        budget *= 4


def bottleneck(cost: np.ndarray) -> tuple[float, np.ndarray, EdgeList]:
    """Bottleneck value, a perfect matching attaining it, and the candidate edges.

    `cost` is a dense (n, n) matrix; the returned EdgeList holds (sorted by
    cost) every edge whose cost is <= the bottleneck value.
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if cost.shape != (n, n):
        raise ValueError(f"cost must be square, got {cost.shape}")
    if n == 0:
        return 0.0, np.zeros(0, dtype=np.int64), sorted_edges(cost)
    edges, upper, init, failed = _dense_candidates(cost)
    end, match = bottleneck_edges(edges, upper=upper, init=init, failed=failed)
    value = float(edges.keys[end - 1])
    keep = int(np.searchsorted(edges.keys, value, side="right"))
    return value, match, edges.take(slice(0, keep))

"""SCRAM role assignment: agents to target positions with minimal makespan.

One entry point, `assign(agents, targets, method=...)`, maps n agents to n
targets (both (n, 2) arrays, meters) and returns for each agent the index of
its target. `assign_costs` does the same on any (n, n) cost matrix (path
lengths, prioritized costs).

Methods (MacAlpine, Price and Stone, "SCRAM", AAAI 2015; dissertation ch. 5):

* ``mmdr``: Minimum Maximal Distance Recursive, the lexicographic bottleneck
  assignment, by the O(n^4) algorithm of Sokkalingam and Aneja: bottleneck
  matching, then a 0-1 Hungarian whose optimal duals keep only tight edges.
* ``mmdr-n5``: MMDR as one Hungarian on edge weights 2^rank, exact Python
  integers (bit vectors of length n^2).
* ``mmdr-dp``: MMDR by the n 2^(n-1) dynamic program (Appendix C).
* ``brute-force``: MMDR by enumerating all n! mappings (small n only).
* ``mmd-msd2``: bottleneck, then the minimum sum of squared distances over
  edges no longer than it.
* ``msd``, ``msd2``: minimum sum of distances (of squared distances).
* ``greedy``: repeatedly match the shortest remaining agent-target pair.
* ``greedy-offense``: targets in order of decreasing x (most offensive first)
  each take the nearest free agent.
* ``static``: agent i to target i. ``random``: a seeded random permutation.

Ties are broken deterministically: the result is a function of the input
only (``random`` of its seed too). MMDR compares costs exactly through integer
ranks of the distinct cost values, so equal distances are equal.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.optimize import linear_sum_assignment

from formations.bottleneck import EdgeList, bottleneck, bottleneck_edges
from formations.hungarian import hungarian

METHODS = (
    "mmdr",
    "mmdr-n5",
    "mmdr-dp",
    "brute-force",
    "mmd-msd2",
    "msd",
    "msd2",
    "greedy",
    "greedy-offense",
    "static",
    "random",
)
BRUTE_FORCE_MAX_N = 10
DP_MAX_N = 22
SMALL_N = 24  # up to this size dense matrices and plain Python beat edge lists


def distances(agents: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(n, m) Euclidean distances between (n, 2) agents and (m, 2) targets."""
    agents = np.asarray(agents, dtype=float)
    targets = np.asarray(targets, dtype=float)
    return np.hypot(agents[:, None, 0] - targets[None, :, 0], agents[:, None, 1] - targets[None, :, 1])


def assign(agents: np.ndarray, targets: np.ndarray, method: str = "mmdr", *, seed: int = 0) -> np.ndarray:
    """Index of the target of each agent under role assignment `method`.

    `agents` and `targets` are (n, 2) positions in meters (any common frame).
    """
    agents = np.asarray(agents, dtype=float)
    targets = np.asarray(targets, dtype=float)
    if agents.ndim != 2 or targets.shape != agents.shape:
        raise ValueError(f"agents and targets must both be (n, 2); got {agents.shape} and {targets.shape}")
    order = np.lexsort((np.arange(len(targets)), -targets[:, 0])) if len(targets) else None
    return assign_costs(distances(agents, targets), method, target_order=order, seed=seed)


def assign_costs(
    cost: np.ndarray,
    method: str = "mmdr",
    *,
    target_order: np.ndarray | None = None,
    seed: int = 0,
) -> np.ndarray:
    """Like `assign` on an (n, n) matrix of nonnegative costs (cost[agent, target]).

    `target_order` gives the target priority order of ``greedy-offense``
    (default: target index order).
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if cost.ndim != 2 or cost.shape != (n, n):
        raise ValueError(f"cost must be square, got {cost.shape}")
    if not np.all(np.isfinite(cost)):
        raise ValueError("cost must be finite")
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; expected one of {METHODS}")
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    if method == "mmdr":
        return mmdr(cost)
    if method == "mmdr-n5":
        return mmdr_n5(cost)
    if method == "mmdr-dp":
        return mmdr_dp(cost)
    if method == "brute-force":
        return mmdr_brute_force(cost)
    if method == "mmd-msd2":
        return mmd_msd2(cost)
    if method == "msd":
        return _lsa(cost)
    if method == "msd2":
        return _lsa(cost * cost)
    if method == "greedy":
        return greedy(cost)
    if method == "greedy-offense":
        return greedy_offense(cost, target_order)
    if method == "static":
        return np.arange(n, dtype=np.int64)
    rng = np.random.default_rng(seed)
    return rng.permutation(n).astype(np.int64)


# --------------------------------------------------------------------------
# Cost vectors and exact ranks.


def cost_vector(cost: np.ndarray, assignment: np.ndarray) -> np.ndarray:
    """Costs of a mapping sorted in decreasing order (MMDR compares these)."""
    cost = np.asarray(cost)
    return np.sort(cost[np.arange(len(assignment)), assignment])[::-1]


def dense_ranks(values: np.ndarray) -> np.ndarray:
    """Integer rank of each value among the distinct values (equal -> equal)."""
    _, inverse = np.unique(values, return_inverse=True)
    return inverse.reshape(np.shape(values)).astype(np.int64)


def _lsa(cost: np.ndarray) -> np.ndarray:
    rows, cols = linear_sum_assignment(cost)
    out = np.empty(len(rows), dtype=np.int64)
    out[rows] = cols
    return out


# --------------------------------------------------------------------------
# MMDR, O(n^4): Sokkalingam and Aneja.


def _edge_positions(n: int, edges: EdgeList, match: np.ndarray) -> np.ndarray:
    """Indices into `edges` of the matched pairs (row r, match[r])."""
    flat = edges.rows * n + edges.cols
    order = np.argsort(flat)
    want = np.arange(n) * n + match
    return order[np.searchsorted(flat[order], want)]


def _tight_edges(n: int, rows, cols, w, matched: np.ndarray) -> np.ndarray:
    """Edges tight under an optimal dual of min-cost perfect matching `matched`.

    The duals are shortest-path potentials in the residual graph (forward
    edges with cost w, matched edges also backward with cost -w), computed by
    vectorized Bellman-Ford; the residual graph has no negative cycle because
    the matching is optimal. Returns a mask over the edges with
    w[e] - u[row] - v[col] == 0.
    """
    src = np.concatenate([rows, n + cols[matched]])
    dst = np.concatenate([n + cols, rows[matched]])
    wt = np.concatenate([w, -w[matched]])
    d = np.zeros(2 * n, dtype=np.int64)
    for _ in range(2 * n + 2):
        nd = d.copy()
        np.minimum.at(nd, dst, d[src] + wt)
        if np.array_equal(nd, d):
            break
        d = nd
    else:  # pragma: no cover - impossible for an optimal matching
        raise RuntimeError("negative cycle: matching is not optimal")
    return w + d[rows] - d[n + cols] == 0


def _components(nodes: int, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Connected component label (smallest node id) of each node; edges a[k]-b[k]."""
    label = np.arange(nodes)
    while True:
        m = np.minimum(label[a], label[b])
        new = label.copy()
        np.minimum.at(new, a, m)
        np.minimum.at(new, b, m)
        new = new[new]  # pointer jumping
        if np.array_equal(new, label):
            return label
        label = new


def _zero_one_hungarian(
    n: int, edges: EdgeList, w: np.ndarray, match: np.ndarray
) -> tuple[np.ndarray, int, np.ndarray]:
    """Min-cost perfect matching for 0-1 edge costs `w`, and its tight edges.

    The graph splits into connected components; a component without a cost-1
    edge keeps the perfect matching `match` it already has (cost 0, every edge
    tight with zero duals). Each other component is solved by the Hungarian
    algorithm (`linear_sum_assignment`, missing edges infinite) and its tight
    edges come from optimal duals. Returns (matching, cost, tight mask).
    """
    label = _components(2 * n, edges.rows, n + edges.cols)
    edge_label = label[edges.rows]
    hot = np.unique(edge_label[w == 1])
    tight = np.ones(edges.rows.size, dtype=bool)
    match = match.copy()
    total = 0
    for comp in hot.tolist():
        sel = np.flatnonzero(edge_label == comp)
        r_ids = np.unique(edges.rows[sel])
        c_ids = np.unique(edges.cols[sel])
        r_loc = np.searchsorted(r_ids, edges.rows[sel])
        c_loc = np.searchsorted(c_ids, edges.cols[sel])
        dense = np.full((r_ids.size, c_ids.size), np.inf)
        dense[r_loc, c_loc] = w[sel]
        lr, lc = linear_sum_assignment(dense)
        match[r_ids[lr]] = c_ids[lc]
        total += int(dense[lr, lc].sum())
        chosen = np.zeros((r_ids.size, c_ids.size), dtype=bool)
        chosen[lr, lc] = True
        matched = chosen[r_loc, c_loc]
        m = max(r_ids.size, c_ids.size)
        tight[sel] = _tight_edges(m, r_loc, c_loc, w[sel].astype(np.int64), matched)
    return match, total, tight


def _kuhn(n: int, ok: np.ndarray) -> list[int] | None:
    """Perfect matching (column of each row) of the dense boolean graph `ok`, or None."""
    cols = range(n)
    adj = [[c for c in cols if row[c]] for row in ok.tolist()]
    match_col = [-1] * n

    def grow(r: int, seen: list[bool]) -> bool:
        for c in adj[r]:
            if not seen[c]:
                seen[c] = True
                if match_col[c] < 0 or grow(match_col[c], seen):
                    match_col[c] = r
                    return True
        return False

    for r in range(n):
        if not grow(r, [False] * n):
            return None
    out = [0] * n
    for c, r in enumerate(match_col):
        out[r] = c
    return out


def _small_bottleneck(
    ranks: np.ndarray, allowed: np.ndarray, fixed: np.ndarray, upper: int | None = None
) -> int:
    """Bottleneck rank over allowed non-fixed edges (fixed edges always usable).

    Binary search over the sorted distinct ranks, each tested by Kuhn's
    augmenting path algorithm. `upper`, a rank known to be feasible, makes the
    search gallop down from it instead.
    """
    n = ranks.shape[0]
    free = allowed & ~fixed
    values = np.unique(ranks[free])

    def feasible(k: int) -> bool:
        return _kuhn(n, fixed | (free & (ranks <= values[k]))) is not None

    lo = -1
    if upper is None:
        hi = values.size - 1
        if not feasible(hi):
            raise ValueError("graph has no perfect matching")
    else:
        hi = int(np.searchsorted(values, upper))
        step = 1
        while hi - step > lo:
            if not feasible(hi - step):
                lo = hi - step
                break
            hi -= step
            step *= 2
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if feasible(mid):
            hi = mid
        else:
            lo = mid
    return int(values[hi])


def _mmdr_small(cost: np.ndarray) -> np.ndarray:
    """Sokkalingam-Aneja MMDR on dense matrices (same steps as `mmdr`)."""
    n = cost.shape[0]
    ranks = dense_ranks(cost)
    allowed = np.ones((n, n), dtype=bool)
    fixed = np.zeros((n, n), dtype=bool)
    b = _small_bottleneck(ranks, allowed, fixed)
    left = n
    rows = np.arange(n)
    while True:
        allowed &= fixed | (ranks <= b)
        w = (~fixed & (ranks == b)).astype(np.int64)
        _, match = linear_sum_assignment(np.where(allowed, w, np.inf))
        left -= int(w[rows, match].sum())
        if left == 0:
            return match.astype(np.int64)
        # Optimal duals by Bellman-Ford on the residual graph (dense).
        big = 4 * n + 4
        wa = np.where(allowed, w, big)
        dr = np.zeros(n, dtype=np.int64)
        dc = np.zeros(n, dtype=np.int64)
        wm = w[rows, match]
        for _ in range(2 * n + 2):
            ndc = np.minimum(dc, (dr[:, None] + wa).min(axis=0))
            ndr = np.minimum(dr, ndc[match] - wm)
            if np.array_equal(ndc, dc) and np.array_equal(ndr, dr):
                break
            dr, dc = ndr, ndc
        tight = allowed & (w + dr[:, None] - dc[None, :] == 0)
        fixed = (fixed | (ranks == b)) & tight
        allowed = tight
        top = int(np.max(np.where(fixed[rows, match], -1, ranks[rows, match])))
        b = _small_bottleneck(ranks, allowed, fixed, upper=top)


def mmdr(cost: np.ndarray) -> np.ndarray:
    """MMDR by Sokkalingam and Aneja's O(n^4) algorithm (dissertation Alg. 2).

    Small problems run on dense matrices (`_mmdr_small`); large ones on
    sparse edge lists restricted to edges no longer than the bottleneck, with
    connected components solved separately and warm-started matchings.
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n <= SMALL_N:
        return _mmdr_small(cost)
    _, match, cand = bottleneck(cost)  # every edge > bottleneck has cost inf
    ranks = np.concatenate([[0], np.cumsum(cand.keys[1:] != cand.keys[:-1])]).astype(np.int64)
    edges = EdgeList(n, cand.rows, cand.cols, ranks)
    fixed = np.zeros(ranks.size, dtype=bool)
    left = n
    b = int(ranks[-1])
    while True:
        # Line 6: 0-1 costs; edges longer than b are infinite (dropped).
        keep = fixed | (edges.keys <= b)
        edges, fixed = edges.take(keep), fixed[keep]
        w = ((edges.keys == b) & ~fixed).astype(np.int64)
        # Lines 7-9: the Hungarian algorithm counts the edges of length b.
        match, ones, tight = _zero_one_hungarian(n, edges, w, match)
        left -= ones
        if left == 0:
            return match
        # Lines 12-13: keep tight edges; edges of length b become settled (-1).
        fixed = (fixed | (edges.keys == b))[tight]
        edges = edges.take(tight)
        # Line 5: next bottleneck; the current matching bounds it from above.
        pos = _edge_positions(n, edges, match)
        on = np.zeros(edges.keys.size, dtype=bool)
        on[pos] = True
        free_keys = edges.keys[~fixed]
        top = int(free_keys[on[~fixed]].max())
        upper = int(np.searchsorted(free_keys, top, side="right"))
        end, match = bottleneck_edges(edges, fixed, upper=upper, init=match)
        b = int(free_keys[end - 1])


# --------------------------------------------------------------------------
# MMDR, O(n^5): one Hungarian on 2^rank weights.


def rank_weights(cost: np.ndarray) -> np.ndarray:
    """Algorithm 1 ranks: index in the sorted edge list of the first equal edge.

    Weights 2^rank make any edge heavier than all shorter edges together, so
    a min-sum assignment on them is the lexicographic (MMDR) optimum.
    """
    flat = cost.ravel()
    order = np.argsort(flat, kind="stable")
    s = flat[order]
    first = np.concatenate([[True], s[1:] != s[:-1]])
    start = np.maximum.accumulate(np.where(first, np.arange(s.size), 0))
    ranks = np.empty(s.size, dtype=np.int64)
    ranks[order] = start
    return ranks.reshape(cost.shape)


def mmdr_n5(cost: np.ndarray) -> np.ndarray:
    """MMDR by the Hungarian algorithm on exact integer weights 2^rank (Alg. 1)."""
    cost = np.asarray(cost, dtype=float)
    ranks = rank_weights(cost)
    weights = np.empty(cost.shape, dtype=object)
    flat = weights.ravel()
    for k, r in enumerate(ranks.ravel().tolist()):
        flat[k] = 1 << r
    return hungarian(weights).assignment


# --------------------------------------------------------------------------
# MMDR by dynamic programming and by brute force.


def mmdr_dp(cost: np.ndarray) -> np.ndarray:
    """MMDR by the dynamic program of Appendix C (n 2^(n-1) mappings).

    best[S] is the MMDR mapping of agent set S to targets 0..|S|-1, kept as
    the exact key sum(2^rank) (Algorithm 1 ranks) and the agent given target
    |S|-1. Ties go to the lowest agent index.
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n > DP_MAX_N:
        raise ValueError(f"mmdr-dp is limited to n <= {DP_MAX_N}, got {n}")
    ranks = rank_weights(cost)
    w = [[1 << int(ranks[a, t]) for t in range(n)] for a in range(n)]
    key: dict[int, int] = {0: 0}
    last: dict[int, int] = {}
    layer = [0]
    for k in range(n):
        nxt: dict[int, int] = {}
        for s in layer:
            base = key[s]
            for a in range(n):
                bit = 1 << a
                if s & bit:
                    continue
                m = s | bit
                c = base + w[a][k]
                old = nxt.get(m)
                if old is None or c < old or (c == old and a < last[m]):
                    nxt[m] = c
                    last[m] = a
        key.update(nxt)
        layer = list(nxt)
    out = np.empty(n, dtype=np.int64)
    s = (1 << n) - 1
    for k in range(n - 1, -1, -1):
        a = last[s]
        out[a] = k
        s &= ~(1 << a)
    return out


@lru_cache(maxsize=16)
def permutations(n: int) -> np.ndarray:
    """All n! permutations of range(n) as an (n!, n) int8 array."""
    perms = np.zeros((1, 0), dtype=np.int8)
    for k in range(n):
        m = perms.shape[0]
        out = np.empty((m * (k + 1), k + 1), dtype=np.int8)
        for pos in range(k + 1):
            block = out[pos * m : (pos + 1) * m]
            block[:, :pos] = perms[:, :pos]
            block[:, pos] = k
            block[:, pos + 1 :] = perms[:, pos:]
        perms = out
    return perms


def mmdr_brute_force(cost: np.ndarray) -> np.ndarray:
    """MMDR by evaluating all n! mappings (n <= 10); ties to the first in order."""
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n > BRUTE_FORCE_MAX_N:
        raise ValueError(f"brute-force is limited to n <= {BRUTE_FORCE_MAX_N}, got {n}")
    ranks = dense_ranks(cost).astype(np.int16)
    perms = permutations(n)
    best_perm = None
    best_vec = None
    chunk = max(1, 2_000_000 // n)
    for start in range(0, perms.shape[0], chunk):
        p = perms[start : start + chunk]
        c = ranks[np.arange(n), p]
        # The first key is the longest edge: only mappings attaining the
        # smallest one in this chunk need a full sort and comparison.
        top = c.max(axis=1)
        keep = np.flatnonzero(top == top.min())
        vec = -np.sort(-c[keep], axis=1)  # descending per mapping
        idx = np.lexsort(vec.T[::-1])[0]
        cand = vec[idx]
        if best_vec is None or tuple(cand) < tuple(best_vec):
            best_vec, best_perm = cand, p[keep[idx]]
    return best_perm.astype(np.int64)


# --------------------------------------------------------------------------
# MMD+MSD^2 and the greedy baselines.


def mmd_msd2(cost: np.ndarray) -> np.ndarray:
    """MMD+MSD^2 (Algorithm 4): bottleneck, then min sum of squares under it."""
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n <= SMALL_N:
        ranks = dense_ranks(cost)
        none = np.zeros((n, n), dtype=bool)
        b = _small_bottleneck(ranks, ~none, none)
        return _lsa(np.where(ranks <= b, cost * cost, np.inf))
    _, _, edges = bottleneck(cost)
    dense = np.full((n, n), np.inf)
    dense[edges.rows, edges.cols] = edges.keys * edges.keys
    return _lsa(dense)


def greedy(cost: np.ndarray) -> np.ndarray:
    """Shortest pair first; ties by agent then target index."""
    n = cost.shape[0]
    flat = cost.ravel()
    order = np.argsort(flat, kind="stable")
    out = np.full(n, -1, dtype=np.int64)
    taken = np.zeros(n, dtype=bool)
    left = n
    for e in order.tolist():
        a, t = divmod(e, n)
        if out[a] < 0 and not taken[t]:
            out[a] = t
            taken[t] = True
            left -= 1
            if left == 0:
                break
    return out


def greedy_offense(cost: np.ndarray, target_order: np.ndarray | None = None) -> np.ndarray:
    """Targets in `target_order` each take the nearest free agent (lowest index on ties)."""
    n = cost.shape[0]
    order = np.arange(n) if target_order is None else np.asarray(target_order)
    out = np.full(n, -1, dtype=np.int64)
    free = np.ones(n, dtype=bool)
    for t in order.tolist():
        col = np.where(free, cost[:, t], np.inf)
        a = int(np.argmin(col))
        out[a] = t
        free[a] = False
    return out


def makespan(cost: np.ndarray, assignment: np.ndarray) -> float:
    """Longest cost of a mapping (the makespan at unit speed)."""
    return float(np.max(np.asarray(cost)[np.arange(len(assignment)), assignment]))


__all__ = [
    "METHODS",
    "assign",
    "assign_costs",
    "cost_vector",
    "distances",
    "greedy",
    "greedy_offense",
    "makespan",
    "mmd_msd2",
    "mmdr",
    "mmdr_brute_force",
    "mmdr_dp",
    "mmdr_n5",
]

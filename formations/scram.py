"""SCRAM role assignment: agents to target positions with minimal makespan.

One entry point, `assign(agents, targets, method=...)`, maps n agents to n
targets (both (n, 2) arrays, meters) and returns for each agent the index of
its target. `assign_costs` does the same on any (n, n) cost matrix (path
lengths, prioritized costs).

Methods (MacAlpine, Price and Stone, "SCRAM", AAAI 2015; dissertation ch. 5):

* ``mmdr``: Minimum Maximal Distance Recursive, the lexicographic bottleneck
  assignment, by the O(n^4) algorithm of Sokkalingam and Aneja: bottleneck
  matching, then a 0-1 Hungarian whose optimal duals keep only tight edges
  (skipped when a single edge has the bottleneck length: it is forced). Up to
  `MMDR_DENSE_N` agents a near-lexicographic warm start is first checked to
  have every level forced, which settles most problems without tied costs.
* ``mmdr-n5``: MMDR as one Hungarian on edge weights 2^rank, exact Python
  integers (bit vectors of length n^2).
* ``mmdr-dp``: MMDR by the n 2^(n-1) dynamic program (Appendix C), pruned
  by the key of a heuristic complete mapping.
* ``brute-force``: MMDR by enumerating all n! mappings (small n only).
* ``mmd-msd2``: bottleneck, then the minimum sum of squared distances over
  edges no longer than it (one `linear_sum_assignment`). Up to `MMD_DENSE_N`
  agents the bottleneck comes from a few dense min-sum assignments
  (`_dense_bottleneck`), beyond from sparse edge lists (`bottleneck`).
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

import itertools
import math
from functools import lru_cache

import numpy as np
from scipy.optimize import linear_sum_assignment

from formations.bottleneck import EdgeList, bottleneck, bottleneck_edges, max_matching
from formations.hungarian import LIST_MAX_N, _hungarian_lists, hungarian

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
SMALL_N = 128  # up to this size dense matrices and scipy beat edge lists (MMD+MSD^2)
MMDR_DENSE_N = 400  # up to this size MMDR first tries `_mmdr_forced` (dense)
MMD_DENSE_N = 450  # up to this size MMD+MSD^2 finds its bottleneck by dense `_dense_bottleneck`
CYCLE_N = 48  # from this size `_forced_prefix` tests levels by reachability, not a min-sum
CERTIFY_N = 160  # from this size `_dense_bottleneck` proves its answer by augmenting paths, not a min-sum


def distances(agents: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(n, m) Euclidean distances between (n, 2) agents and (m, 2) targets.

    sqrt(dx^2 + dy^2) in place (several times faster than `np.hypot`); the
    square root is correctly rounded, so points on an integer grid at equal
    distances get exactly equal costs. Falls back to `np.hypot` if the squares
    overflow (coordinates beyond 1e154).
    """
    agents = np.asarray(agents, dtype=float)
    targets = np.asarray(targets, dtype=float)
    dx = np.subtract.outer(agents[:, 0], targets[:, 0])
    dy = np.subtract.outer(agents[:, 1], targets[:, 1])
    out = np.multiply(dx, dx)
    dy *= dy
    out += dy
    np.sqrt(out, out=out)
    if not math.isfinite(out.sum()) and not np.all(np.isfinite(out)):
        return np.hypot(
            np.subtract.outer(agents[:, 0], targets[:, 0]), np.subtract.outer(agents[:, 1], targets[:, 1])
        )
    return out


def assign(agents: np.ndarray, targets: np.ndarray, method: str = "mmdr", *, seed: int = 0) -> np.ndarray:
    """Index of the target of each agent under role assignment `method`.

    `agents` and `targets` are (n, 2) positions in meters (any common frame).
    """
    agents = np.asarray(agents, dtype=float)
    targets = np.asarray(targets, dtype=float)
    if agents.ndim != 2 or targets.shape != agents.shape:
        raise ValueError(f"agents and targets must both be (n, 2); got {agents.shape} and {targets.shape}")
    order = None
    if method == "greedy-offense" and len(targets):  # the only method that needs it
        order = np.lexsort((np.arange(len(targets)), -targets[:, 0]))
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
    # A finite sum rules out inf and nan; only an overflowing sum needs the full check.
    if not math.isfinite(cost.sum()) and not np.all(np.isfinite(cost)):
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


def _heuristic_weights(cost: np.ndarray) -> np.ndarray:
    """Weights 2^rank (ties broken by position) for near-lexicographic warm starts.

    A min-sum assignment on these floats is close to the MMDR optimum but not
    exact (float sums round); it only supplies good starting matchings, every
    decision is then checked exactly. Beyond 900 edges the exponents are
    scaled down to stay finite.
    """
    flat = cost.ravel()
    ranks = np.empty(flat.size, dtype=np.float64)
    ranks[np.argsort(flat, kind="stable")] = np.arange(flat.size) * min(1.0, 900.0 / flat.size)
    return np.exp2(ranks).reshape(cost.shape)


def _descend(
    cost: np.ndarray, ok: np.ndarray, fixed: np.ndarray, weights: np.ndarray, match: np.ndarray
) -> tuple[float, np.ndarray]:
    """Bottleneck over the edges `ok` whose non-fixed part is as short as possible.

    `match` (column of each row) is a perfect matching of `ok`. Repeatedly
    asks for a perfect matching of `ok` whose non-fixed edges are all shorter
    than the longest non-fixed edge of the current one (a min-sum assignment
    on `weights` over the allowed edges, infinite elsewhere; scipy reports
    infeasibility exactly). Returns (b, matching): b is the smallest cost such
    that the fixed edges plus the non-fixed edges <= b of `ok` admit a perfect
    matching, and the returned matching of `ok` has no non-fixed edge above b.
    Requires a matching with at least one non-fixed edge.
    """
    rows = np.arange(cost.shape[0])
    while True:
        on = cost[rows, match]
        top = on[~fixed[rows, match]].max()
        allow = ok & (fixed | (cost < top))
        try:
            match = linear_sum_assignment(np.where(allow, weights, np.inf))[1]
        except ValueError:  # no perfect matching below top: top is the bottleneck
            return float(top), match


def _duals_tight(n: int, allowed: np.ndarray, w: np.ndarray, match: np.ndarray) -> np.ndarray:
    """Tight edges of `allowed` under an optimal dual of the 0-1 min-cost matching `match`.

    Duals are shortest-path potentials of the residual graph (dense
    Bellman-Ford, vectorized); a perfect matching uses only tight edges iff it
    is optimal.
    """
    rows = np.arange(n)
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
    return allowed & (w + dr[:, None] - dc[None, :] == 0)


@lru_cache(maxsize=64)
def _upper_triangle(n: int) -> np.ndarray:
    """(n, n) mask [k, j]: j >= k."""
    idx = np.arange(n)
    return idx[None, :] >= idx[:, None]


def _forced_prefix(cost: np.ndarray, match: np.ndarray) -> tuple[int, bool, np.ndarray]:
    """How many levels of the perfect matching `match` are forced, from the top.

    Sort the matched edges by decreasing cost d[0] >= d[1] >= ... (rows
    `order`); subproblem k keeps the rows and columns of edges k..n-1. Level k
    is forced if edge k is the only edge of cost d[k] in subproblem k and no
    perfect matching of subproblem k uses only edges shorter than d[k]: the
    Sokkalingam-Aneja steps then fix edge 0, edge 1, ... in turn. Returns
    (k, shorter, order): levels 0..k-1 are forced; if k < n, `shorter` tells
    whether subproblem k has a perfect matching of edges shorter than d[k]
    (else level k has tied edges and needs the 0-1 step).
    """
    n = match.size
    rows = np.arange(n)
    on = cost[rows, match]
    order = np.argsort(-on, kind="stable")
    d = on[order]
    p = cost[order][:, match[order]]
    upper = _upper_triangle(n)
    # A perfect matching of shorter edges needs one in row k and in column k.
    maybe = ((p < d[:, None]) & upper).any(axis=1) & ((p < d[None, :]) & upper.T).any(axis=0)
    values = np.sort(p, axis=None)
    if np.any(values[1:] == values[:-1]):
        # tie[k]: another entry (i, j) with i, j >= k equals d[k] (d decreasing).
        pos = np.searchsorted(-d, -p, side="left")
        hit = (pos < n) & (d[np.minimum(pos, n - 1)] == p) & (pos <= np.minimum(rows[:, None], rows[None, :]))
        hit[rows, rows] &= pos[rows, rows] != rows
        tie = np.zeros(n, dtype=bool)
        tie[pos[hit]] = True
        maybe |= tie
    else:  # all costs distinct: no ties
        tie = None
    reach = n >= CYCLE_N
    for k in np.flatnonzero(maybe).tolist():
        if tie is not None and tie[k]:
            return k, False, order
        if reach:
            # Without a tie the other matched edges of subproblem k are all
            # shorter than d[k]: a perfect matching of shorter edges is the
            # matching rotated along a cycle through k of arcs i -> j
            # (p[i, j] < d[k]), so look for k among the nodes k reaches.
            arcs = p[k:, k:] < d[k]
            seen = arcs[0].copy()
            frontier = seen
            while not seen[0] and frontier.any():
                frontier = arcs[frontier].any(axis=0) & ~seen
                seen |= frontier
            if seen[0]:
                return k, True, order
            continue
        try:
            linear_sum_assignment(np.where(p[k:, k:] < d[k], 0.0, np.inf))
        except ValueError:
            continue
        return k, True, order
    return n, False, order


_MmdrState = tuple[np.ndarray, np.ndarray, np.ndarray, int]  # allowed, fixed, matching, rows left


def _mmdr_forced(cost: np.ndarray) -> tuple[np.ndarray | None, _MmdrState | None]:
    """MMDR while its levels are forced (the usual case without tied costs).

    A near-lexicographic warm start is checked level by level
    (`_forced_prefix`); forced levels are settled, and where a shorter
    perfect matching exists the warm start is recomputed on the rest, now
    restricted to edges shorter than that level. Returns (assignment, None)
    if every level was forced, else (None, state) at the first tied level:
    the allowed and settled (fixed) edges, a perfect matching of the allowed
    edges and the number of unsettled rows, for `_mmdr_small` to go on from.
    """
    n = cost.shape[0]
    out = np.empty(n, dtype=np.int64)
    r_ids = np.arange(n)
    c_ids = np.arange(n)
    sub = cost
    while True:
        weights = _heuristic_weights(sub)
        match = linear_sum_assignment(np.where(np.isinf(sub), np.inf, weights))[1]
        k, shorter, order = _forced_prefix(sub, match)
        out[r_ids[order[:k]]] = c_ids[match[order[:k]]]
        if k == match.size:
            return out, None
        keep_r, keep_c = order[k:], match[order[k:]]
        # Shorter: the rest has a bottleneck below level k; else a tie at level
        # k, and the rest keeps the edges below level k - 1 (the last settled).
        level = order[k] if shorter else order[k - 1] if k else -1
        bound = sub[level, match[level]] if level >= 0 else np.inf
        settled = np.ones(n, dtype=bool)
        settled[r_ids[keep_r]] = False
        rest = sub[np.ix_(keep_r, keep_c)]
        rest = np.where(rest < bound, rest, np.inf) if level >= 0 else rest
        r_ids, c_ids = r_ids[keep_r], c_ids[keep_c]
        if shorter:
            sub = rest
            continue
        allowed = np.zeros((n, n), dtype=bool)
        fixed = np.zeros((n, n), dtype=bool)
        done = np.flatnonzero(settled)
        allowed[done, out[done]] = fixed[done, out[done]] = True
        allowed[np.ix_(r_ids, c_ids)] = np.isfinite(rest)
        full = out.copy()
        full[r_ids] = c_ids  # the warm start, diagonal of `rest`
        return None, (allowed, fixed, full, r_ids.size)


def _mmdr_small(cost: np.ndarray, state: _MmdrState | None = None) -> np.ndarray:
    """Sokkalingam-Aneja MMDR on dense matrices, level by level from the top.

    Each level b is the bottleneck of the remaining problem (`_descend`,
    warm-started by near-lexicographic matchings). A level with a single
    unsettled edge of cost b is forced: every remaining perfect matching uses
    it, so its row and column are settled. A level with several such edges
    takes the 0-1 Hungarian step of the algorithm (minimize the number of
    edges of cost b; keep only edges tight under optimal duals). `state`
    resumes from `_mmdr_forced` (else the start is: all edges, none settled).
    """
    n = cost.shape[0]
    weights = _heuristic_weights(cost)
    rows = np.arange(n)
    if state is None:
        allowed = np.ones((n, n), dtype=bool)
        fixed = np.zeros((n, n), dtype=bool)
        match = linear_sum_assignment(weights)[1]
        left = n
    else:
        allowed, fixed, match, left = state
    while True:
        b, match = _descend(cost, allowed, fixed, weights, match)
        allowed &= fixed | (cost <= b)
        level = allowed & ~fixed & (cost == b)
        if np.count_nonzero(level) == 1:
            r, c = divmod(int(np.argmax(level)), n)
            allowed[r, :] = False
            allowed[:, c] = False
            allowed[r, c] = True
            fixed[r, c] = True
            left -= 1
        else:
            w = level.astype(np.int64)
            match = linear_sum_assignment(np.where(allowed, w, np.inf))[1]
            left -= int(w[rows, match].sum())
            if left == 0:
                return match.astype(np.int64)
            allowed = _duals_tight(n, allowed, w, match)
            fixed = (fixed | level) & allowed
            weights = np.where(fixed, 0.0, weights)
            match = linear_sum_assignment(np.where(allowed, weights, np.inf))[1]
        if left == 0:
            return match.astype(np.int64)


def mmdr(cost: np.ndarray) -> np.ndarray:
    """MMDR by Sokkalingam and Aneja's O(n^4) algorithm (dissertation Alg. 2).

    Up to `MMDR_DENSE_N` agents a near-lexicographic warm start is first
    checked level by level (`_mmdr_forced`); without tied levels that settles
    the problem. Otherwise small problems go on with the dense steps
    (`_mmdr_small`, from the levels already settled) and large ones start
    over on sparse edge lists (`_mmdr_edges`).
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    state = None
    if n <= MMDR_DENSE_N:
        forced, state = _mmdr_forced(cost)
        if forced is not None:
            return forced
    if n <= SMALL_N:
        return _mmdr_small(cost, state)
    return _mmdr_edges(cost)


def _mmdr_edges(cost: np.ndarray) -> np.ndarray:
    """Sokkalingam-Aneja on sparse edge lists, for large problems.

    Edges are restricted to those no longer than the bottleneck, connected
    components are solved separately and matchings warm-started. A level with
    a single edge of the bottleneck length skips the 0-1 Hungarian step: that
    edge is in every remaining perfect matching.
    """
    n = cost.shape[0]
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
        level = (edges.keys == b) & ~fixed
        if np.count_nonzero(level) == 1:
            # A single unsettled edge of length b: every remaining perfect
            # matching uses it (`match` does), so its row and column are settled.
            e = int(np.argmax(level))
            tight = level | ((edges.rows != edges.rows[e]) & (edges.cols != edges.cols[e]))
            left -= 1
        else:
            # Lines 7-9: the Hungarian algorithm counts the edges of length b.
            match, ones, tight = _zero_one_hungarian(n, edges, level.astype(np.int64), match)
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
    n = cost.shape[0]
    ranks = rank_weights(cost).tolist()
    power = [1 << r for r in range(n * n)]
    rows = [[power[r] for r in row] for row in ranks]
    if n <= LIST_MAX_N:
        return _hungarian_lists(rows).assignment
    weights = np.empty((n, n), dtype=object)
    weights[...] = rows
    return hungarian(weights).assignment


# --------------------------------------------------------------------------
# MMDR by dynamic programming and by brute force.


def mmdr_dp(cost: np.ndarray) -> np.ndarray:
    """MMDR by the dynamic program of Appendix C (n 2^(n-1) mappings).

    best[S] is the MMDR mapping of agent set S to targets 0..|S|-1, kept as
    the exact key sum(2^rank) (Algorithm 1 ranks) and the agent given target
    |S|-1. Ties go to the lowest agent index. Partial mappings whose key
    exceeds that of a heuristic complete mapping are pruned (same result).
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n > DP_MAX_N:
        raise ValueError(f"mmdr-dp is limited to n <= {DP_MAX_N}, got {n}")
    ranks = rank_weights(cost)
    w = [[1 << r for r in row] for row in ranks.tolist()]
    # Branch and bound: the key of any complete mapping bounds the optimum, and
    # keys only grow as targets are added, so a partial mapping whose key
    # exceeds it cannot be a prefix of the optimum (nor tie with one) and is
    # dropped. The bound comes from a near-lexicographic heuristic mapping.
    # A completion of targets k..n-1 costs at least the sum of their column
    # minima, which tightens the test for partial mappings of targets 0..k-1.
    guess = linear_sum_assignment(_heuristic_weights(cost))[1].tolist()
    bound = sum(w[a][t] for a, t in enumerate(guess))
    col_min = [min(w[a][t] for a in range(n)) for t in range(n)]
    rest = [0] * (n + 1)
    for t in range(n - 1, -1, -1):
        rest[t] = rest[t + 1] + col_min[t]
    key: dict[int, int] = {0: 0}
    last: dict[int, int] = {}
    layer = [0]
    for k in range(n):
        nxt: dict[int, int] = {}
        # Agents by increasing edge weight to target k: once an edge is too
        # long for a state, so are all the following ones.
        col = sorted((w[a][k], a, 1 << a) for a in range(n))
        limit = bound - rest[k + 1]
        least = limit - col_min[k]
        for s in layer:
            base = key[s]
            if base > least:  # even the shortest edge to target k is too long
                continue
            room = limit - base
            for wa, a, bit in col:
                if wa > room:
                    break
                if s & bit:
                    continue
                c = base + wa
                m = s | bit
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


@lru_cache(maxsize=16)
def _split_mappings(n: int) -> tuple[np.ndarray, np.ndarray]:
    """All n! mappings split in two halves, for `mmdr_brute_force`.

    Agents 0..h-1 (h = n // 2) take a set T of h targets, agents h..n-1 the
    complement. Returns (first, second): first[s] holds every mapping of the
    first agents onto the s-th set T (in `itertools.combinations` order),
    second[s] every mapping of the other agents onto its complement; each
    pair (first[s, i], second[s, j]) is one of the n! mappings, once.
    """
    h = n // 2
    sets = np.array(list(itertools.combinations(range(n), h)), dtype=np.int8).reshape(-1, h)
    rest = np.array([[t for t in range(n) if t not in row] for row in sets.tolist()], dtype=np.int8)
    rest = rest.reshape(len(sets), n - h)
    first = sets[:, permutations(h).astype(np.intp)]  # (sets, h!, h)
    second = rest[:, permutations(n - h).astype(np.intp)]  # (sets, (n-h)!, n-h)
    return first, second


def _first_in_order(perm: np.ndarray) -> int:
    """Row of `perm` (distinct mappings) that comes first in `permutations(n)`.

    permutations(k + 1) is k + 1 blocks of permutations(k), block pos putting
    k at position pos: the index is sum over k of pos_k * k!, pos_k being the
    position of k among the values <= k. Rows are filtered digit by digit,
    the most significant (k = n - 1) first.
    """
    n = perm.shape[1]
    rows = np.arange(perm.shape[0])
    cols = np.arange(n)
    for k in range(n - 1, 0, -1):
        if rows.size == 1:
            break
        p = perm[rows]
        loc = np.argmax(p == k, axis=1)
        pos = np.count_nonzero((p < k) & (cols[None, :] < loc[:, None]), axis=1)
        rows = rows[pos == pos.min()]
    return int(rows[0])


def mmdr_brute_force(cost: np.ndarray) -> np.ndarray:
    """MMDR by evaluating all n! mappings (n <= 10); ties to the first in order.

    Every mapping is a mapping of the first n // 2 agents to some target set
    plus one of the others to the complement (`_split_mappings`); the
    longest edge of all n! mappings is the elementwise maximum of the two
    halves' longest edges. Mappings attaining the smallest longest edge are
    then compared by their full sorted cost vectors; among equal vectors the
    first in `permutations(n)` order wins.
    """
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n > BRUTE_FORCE_MAX_N:
        raise ValueError(f"brute-force is limited to n <= {BRUTE_FORCE_MAX_N}, got {n}")
    if n == 1:
        return np.zeros(1, dtype=np.int64)
    h = n // 2
    ranks = dense_ranks(cost).astype(np.int16)
    first, second = _split_mappings(n)
    r1 = ranks[np.arange(h), first]  # (sets, h!, h)
    r2 = ranks[np.arange(h, n), second]
    top = np.maximum(r1.max(axis=2)[:, :, None], r2.max(axis=2)[:, None, :])  # all n! mappings
    s, i, j = np.nonzero(top == top.min())
    vec = -np.sort(-np.concatenate([r1[s, i], r2[s, j]], axis=1), axis=1)  # descending
    tied = np.arange(len(vec))
    for k in range(1, n):  # lexicographic minimum, key by key
        col = vec[tied, k]
        tied = tied[col == col.min()]
    maps = np.concatenate([first[s[tied], i[tied]], second[s[tied], j[tied]]], axis=1)
    return maps[_first_in_order(maps)].astype(np.int64)


# --------------------------------------------------------------------------
# MMD+MSD^2 and the greedy baselines.


def _dense_bottleneck(cost: np.ndarray) -> float:
    """Bottleneck value of a small dense cost matrix by a few `linear_sum_assignment` calls.

    The answer is at least `lower`, the largest row or column minimum. Each
    round solves a min-sum assignment on the edges shorter than the current
    matching's longest edge `top`, weighted 2^(1000 (c - lower) / (top - lower))
    (monotone in the cost, no sort needed): long edges dominate, so the new
    matching's longest edge is usually close to the bottleneck, and the scale
    sharpens as `top` falls. When no perfect matching below `top` exists
    (scipy reports infeasibility exactly) or `top` reaches `lower`, `top` is
    the bottleneck. Weights only steer the search; every step is exact.
    """
    n = cost.shape[0]
    lower = max(cost.min(axis=1).max(), cost.min(axis=0).max())
    rows = np.arange(n)
    shifted = cost - lower
    top = cost.max()
    allowed = None
    while top > lower:
        span = top - lower
        weights = np.exp2(np.minimum(shifted, span) / span * 1000.0)
        if allowed is not None:
            weights[~allowed] = np.inf
        try:
            match = linear_sum_assignment(weights)[1]
        except ValueError:  # no perfect matching below top
            break
        on = cost[rows, match]
        top = on.max()
        allowed = cost < top
        if n >= CERTIFY_N and top > lower:
            # Usually `top` is already the bottleneck: prove it with a maximum
            # matching of the edges below it, warm-started from `match` minus
            # its longest edges (a few augmenting-path searches, no min-sum).
            r, c = np.nonzero(allowed)
            if np.any(max_matching(n, r, c, np.where(on < top, match, -1)) < 0):
                break
    return float(top)


def mmd_msd2(cost: np.ndarray) -> np.ndarray:
    """MMD+MSD^2 (Algorithm 4): bottleneck, then min sum of squares under it."""
    cost = np.asarray(cost, dtype=float)
    n = cost.shape[0]
    if n <= MMD_DENSE_N:
        return _lsa(np.where(cost <= _dense_bottleneck(cost), cost * cost, np.inf))
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

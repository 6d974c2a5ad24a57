"""SCRAM role assignment: agents to target positions with minimal makespan.

One entry point, `assign(agents, targets, method=...)`, maps n agents to n
targets (both (n, 2) arrays, meters) and returns for each agent the index of
its target. `assign_costs` does the same on any (n, n) cost matrix (path
lengths, prioritized costs).

Methods (MacAlpine, Price and Stone, "SCRAM", AAAI 2015; dissertation ch. 5):

* ``mmdr``: Minimum Maximal Distance Recursive, the lexicographic bottleneck
  assignment, by the O(n^4) algorithm of Sokkalingam and Aneja on edge lists
  (`_kernels.mmdr`, compiled): bottleneck, then a 0-1 Hungarian whose optimal
  duals keep only tight edges (skipped when a single edge has the
  bottleneck length: it is forced).
* ``mmdr-n5``: MMDR as one Hungarian on edge weights 2^rank, exact
  multiword integers (`_bigint`, compiled; edges above the bottleneck
  dropped first).
* ``mmdr-dp``: MMDR by the n 2^(n-1) dynamic program (Appendix C, compiled,
  exact multiword keys).
* ``brute-force``: MMDR by enumerating all n! mappings (small n only).
* ``mmd-msd2``: bottleneck, then the minimum sum of squared distances over
  edges no longer than it (`_kernels.mmd_msd2`, compiled).
* ``msd``, ``msd2``: minimum sum of distances (of squared distances).
* ``greedy``: repeatedly match the shortest remaining agent-target pair.
* ``greedy-offense``: targets in order of decreasing x (most offensive first)
  each take the nearest free agent.
* ``static``: agent i to target i. ``random``: a seeded random permutation.

Ties are broken deterministically: the result is a function of the input
only (``random`` of its seed too). MMDR compares costs exactly through integer
ranks of the distinct cost values, so equal distances are equal. The
min-sum steps of ``msd``, ``msd2`` and ``mmd-msd2`` (the latter up to
`_kernels.LSAP_DENSE_N` agents) return what scipy's `linear_sum_assignment`
returns on the same matrix (`_lsap.lsap_dense` is the same algorithm).
"""

from __future__ import annotations

import itertools
from functools import lru_cache

import numpy as np

from formations import _kernels

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
DENSE_N = 128  # up to this size MMD+MSD^2 and MMDR start with dense steps, beyond with sparse edges
_KERNELS = {  # compiled methods: (on a cost matrix, on two point sets)
    "mmdr": (lambda cost: _kernels.mmdr(cost, DENSE_N), _kernels.mmdr_points),
    "mmd-msd2": (lambda cost: _kernels.mmd_msd2(cost, DENSE_N), _kernels.mmd_msd2_points),
    "mmdr-n5": (lambda cost: _kernels.mmdr_n5(cost, DENSE_N), _kernels.mmdr_n5_points),
    "mmdr-dp": (_kernels.mmdr_dp, _kernels.mmdr_dp_points),
    "msd": (_kernels.msd, _kernels.msd_points),
    "msd2": (_kernels.msd2, _kernels.msd2_points),
}


def distances(agents: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """(n, m) Euclidean distances between (n, 2) agents and (m, 2) targets (meters).

    Correctly rounded sqrt(dx^2 + dy^2): points on an integer grid at equal
    distances get exactly equal costs (`_kernels.distances`).
    """
    agents = np.ascontiguousarray(agents, dtype=float)
    targets = np.ascontiguousarray(targets, dtype=float)
    if agents.ndim != 2 or targets.ndim != 2 or agents.shape[1] < 2 or targets.shape[1] < 2:
        raise ValueError(f"points must be (n, 2); got {agents.shape} and {targets.shape}")
    return _kernels.distances(agents, targets)[0]


def assign(agents: np.ndarray, targets: np.ndarray, method: str = "mmdr", *, seed: int = 0) -> np.ndarray:
    """Index of the target of each agent under role assignment `method`.

    `agents` and `targets` are (n, 2) positions in meters (any common frame).
    """
    agents = np.ascontiguousarray(agents, dtype=float)
    targets = np.ascontiguousarray(targets, dtype=float)
    if agents.ndim != 2 or agents.shape[1] < 2 or targets.shape != agents.shape:
        raise ValueError(f"agents and targets must both be (n, 2); got {agents.shape} and {targets.shape}")
    kernels = _KERNELS.get(method)
    n = len(agents)
    if kernels is None or n == 0 or (method == "mmdr-dp" and n > DP_MAX_N):
        order = None
        if method == "greedy-offense" and n:  # the only method that needs it
            order = np.lexsort((np.arange(n), -targets[:, 0]))
        return assign_costs(_kernels.distances(agents, targets)[0], method, target_order=order, seed=seed)
    out = kernels[1](agents, targets, DENSE_N)  # one compiled call
    if out[0] == -2:
        raise ValueError("cost must be finite")
    return out


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
    cost = np.ascontiguousarray(cost, dtype=float)
    n = cost.shape[0] if cost.ndim else 0
    if cost.ndim != 2 or cost.shape[1] != n:
        raise ValueError(f"cost must be square, got {cost.shape}")
    if n == 0:
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; expected one of {METHODS}")
        return np.zeros(0, dtype=np.int64)
    if not _kernels.all_finite(cost):
        raise ValueError("cost must be finite")
    kernels = _KERNELS.get(method)
    if kernels is not None:
        if method == "mmdr-dp" and n > DP_MAX_N:
            raise ValueError(f"mmdr-dp is limited to n <= {DP_MAX_N}, got {n}")
        return kernels[0](cost)
    if method == "brute-force":
        return mmdr_brute_force(cost)
    if method == "greedy":
        return greedy(cost)
    if method == "greedy-offense":
        return greedy_offense(cost, target_order)
    if method == "static":
        return np.arange(n, dtype=np.int64)
    if method == "random":
        return np.random.default_rng(seed).permutation(n).astype(np.int64)
    raise ValueError(f"unknown method {method!r}; expected one of {METHODS}")


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


# --------------------------------------------------------------------------
# MMDR: Sokkalingam and Aneja (O(n^4)), the 2^rank Hungarian (O(n^5)), the
# dynamic program and brute force.


def mmdr(cost: np.ndarray) -> np.ndarray:
    """MMDR by Sokkalingam and Aneja's O(n^4) algorithm (dissertation Alg. 2)."""
    return assign_costs(cost, "mmdr")


def rank_weights(cost: np.ndarray) -> np.ndarray:
    """Algorithm 1 ranks: index in the sorted edge list of the first equal edge.

    Weights 2^rank make any edge heavier than all shorter edges together, so
    a min-sum assignment on them is the lexicographic (MMDR) optimum.
    """
    return _kernels.rank_weights(np.ascontiguousarray(cost, dtype=float))


def mmdr_n5(cost: np.ndarray) -> np.ndarray:
    """MMDR by the Hungarian algorithm on exact integer weights 2^rank (Alg. 1, `_bigint`)."""
    return assign_costs(cost, "mmdr-n5")


def mmdr_dp(cost: np.ndarray) -> np.ndarray:
    """MMDR by the dynamic program of Appendix C (n 2^(n-1) mappings, `_kernels.mmdr_dp`).

    Ties go to the lowest agent index (the agent given the last target of
    each agent set). Limited to n <= `DP_MAX_N`.
    """
    return assign_costs(cost, "mmdr-dp")


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


def mmd_msd2(cost: np.ndarray) -> np.ndarray:
    """MMD+MSD^2 (Algorithm 4): bottleneck, then min sum of squares under it."""
    return assign_costs(cost, "mmd-msd2")


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

"""Shortest-augmenting-path Hungarian algorithm on lazily evaluated costs, with duals.

The compiled `formations._lsap` serves plain cost matrices. This
implementation exists for lazily evaluated costs (`formations.pathcost`),
where the exact cost of a pair is computed only when the search is about to
use that pair (a Python callback).

The algorithm is the O(n^3) Kuhn-Munkres method in its shortest augmenting
path form (one Dijkstra search per row, potentials kept feasible), with the
inner loop vectorized over columns.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np


@dataclass
class HungarianResult:
    """Matching and optimal duals of a square assignment problem.

    `assignment[i]` is the column of row i; `u` and `v` are row and column
    potentials with cost[i, j] - u[i] - v[j] >= 0 everywhere and == 0 on the
    matching. `evaluated` counts exact cost evaluations (lazy mode only).
    """

    assignment: np.ndarray
    u: np.ndarray
    v: np.ndarray
    evaluated: int = 0


def hungarian(
    cost: np.ndarray,
    exact: Callable[[int, int], float] | None = None,
    is_exact: np.ndarray | None = None,
) -> HungarianResult:
    """Solves min-sum assignment on a square `cost` matrix.

    `cost` may be float or object (Python int) dtype. If `exact` is given,
    `cost` holds lower bounds: entries with `is_exact[i, j]` False are replaced
    by `exact(i, j)` (which must be >= the bound) the first time the search
    would grow its shortest-path tree along them. `cost` and `is_exact` are
    updated in place.
    """
    cost = np.asarray(cost)
    n = cost.shape[0]
    if cost.shape != (n, n):
        raise ValueError(f"cost must be square, got shape {cost.shape}")
    obj = cost.dtype == object
    if obj:
        big = max((abs(int(x)) for x in cost.ravel()), default=0)
        inf = (big + 1) * (2 * n + 2) * 4
        zeros = np.array([0] * (n + 1), dtype=object)
        u, v = zeros.copy(), zeros.copy()
    else:
        inf = np.inf
        u = np.zeros(n + 1)
        v = np.zeros(n + 1)
    lazy = exact is not None
    if lazy and is_exact is None:
        is_exact = np.zeros((n, n), dtype=bool)
    evaluated = 0
    p = np.zeros(n + 1, dtype=np.int64)  # p[j]: 1-based row matched to column j
    way = np.zeros(n + 1, dtype=np.int64)
    for i in range(1, n + 1):
        p[0] = i
        j0 = 0
        if obj:
            minv = np.array([inf] * (n + 1), dtype=object)
        else:
            minv = np.full(n + 1, np.inf)
        used = np.zeros(n + 1, dtype=bool)
        while True:
            used[j0] = True
            i0 = p[j0]
            free = ~used[1:]
            cols = np.flatnonzero(free) + 1
            cur = cost[i0 - 1, cols - 1] - u[i0] - v[cols]
            better = cur < minv[cols]
            bc = cols[better]
            minv[bc] = cur[better]
            way[bc] = j0
            while True:
                k = int(np.argmin(minv[cols]))
                j1 = int(cols[k])
                if not lazy:
                    break
                r = p[way[j1]] - 1
                if is_exact[r, j1 - 1]:
                    break
                value = exact(r, j1 - 1)
                evaluated += 1
                cost[r, j1 - 1] = max(value, cost[r, j1 - 1])
                is_exact[r, j1 - 1] = True
                ucols = np.flatnonzero(used)
                rows = p[ucols]
                red = cost[rows - 1, j1 - 1] - u[rows] - v[j1]
                m = int(np.argmin(red))
                minv[j1] = red[m]
                way[j1] = ucols[m]
            delta = minv[j1]
            ucols = np.flatnonzero(used)
            u[p[ucols]] += delta
            v[ucols] -= delta
            minv[cols] -= delta
            j0 = j1
            if p[j0] == 0:
                break
        while j0:
            j1 = way[j0]
            p[j0] = p[j1]
            j0 = j1
    assignment = np.empty(n, dtype=np.int64)
    assignment[p[1:] - 1] = np.arange(n)
    return HungarianResult(assignment, u[1:], v[1:], evaluated)

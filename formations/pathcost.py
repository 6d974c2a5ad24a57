"""Obstacle-aware path costs, evaluated lazily during role assignment.

The PathCost agent of "Positioning to Win" (MacAlpine, Barrera and Stone 2012)
measures an agent's distance to a role position as the length of a walk
around known obstacles (the ball, the onBall player, fallen robots) instead of
the straight line. Computing every agent-target path is the expensive part;
following "It Costs to Get Costs" (Aakash and Saha, AAAI 2022) the straight
distance is used as a lower bound and the exact path length of a pair is only
computed when the assignment search needs it.

Obstacles are disks (x, y, radius), meters. Paths run along a visibility
graph of the start, the goal and the corners of a regular polygon
circumscribed about each disk (`sides` corners), so a path length is exact
when it does not touch a disk and at most 1/cos(pi/sides) - 1 too long (0.8%
for 16 sides) on the arcs around disks. A start or goal inside a disk ignores
that disk: the agent is already there.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse.csgraph import dijkstra

from formations import scram
from formations.hungarian import hungarian

_EPS = 1e-9


def _blocked(p: np.ndarray, q: np.ndarray, disks: np.ndarray) -> np.ndarray:
    """(a, b) mask: does segment p[a] -> q[b] cross the interior of any disk?"""
    if disks.size == 0:
        return np.zeros((len(p), len(q)), dtype=bool)
    c = disks[:, :2]
    r = disks[:, 2]
    d = q[None, :, :] - p[:, None, :]  # (a, b, 2)
    dd = np.einsum("abk,abk->ab", d, d)
    pc = c[None, :, :] - p[:, None, :]  # (a, k, 2)
    t = np.einsum("abj,akj->abk", d, pc) / np.maximum(dd, 1e-300)[:, :, None]
    t = np.clip(t, 0.0, 1.0)
    closest = p[:, None, None, :] + t[..., None] * d[:, :, None, :]  # (a, b, k, 2)
    gap = np.linalg.norm(closest - c[None, None, :, :], axis=-1)
    return np.any(gap < r[None, None, :] - _EPS, axis=-1)


@dataclass
class PathPlanner:
    """Shortest walks around disk obstacles (k, 3) = (x, y, radius), meters."""

    obstacles: np.ndarray
    sides: int = 16

    def __post_init__(self):
        self.obstacles = np.asarray(self.obstacles, dtype=float).reshape(-1, 3)
        self._corners, self._owner = self._make_corners(self.obstacles)
        self._graph = self._corner_graph(self.obstacles, self._corners)

    def _make_corners(self, disks: np.ndarray):
        ang = 2 * np.pi * (np.arange(self.sides) + 0.5) / self.sides
        ring = np.stack([np.cos(ang), np.sin(ang)], axis=1) / np.cos(np.pi / self.sides)
        corners = (disks[:, None, :2] + disks[:, None, 2:3] * ring[None]).reshape(-1, 2)
        owner = np.repeat(np.arange(len(disks)), self.sides)
        # Corners inside another disk can never be on a shortest path.
        if len(disks):
            inside = (
                np.linalg.norm(corners[:, None, :] - disks[None, :, :2], axis=-1) < disks[None, :, 2] - _EPS
            )
            ok = ~inside.any(axis=1)
            corners, owner = corners[ok], owner[ok]
        return corners, owner

    def _corner_graph(self, disks: np.ndarray, corners: np.ndarray) -> np.ndarray:
        length = np.linalg.norm(corners[:, None, :] - corners[None, :, :], axis=-1)
        return np.where(_blocked(corners, corners, disks), np.inf, length)

    def length(self, start: np.ndarray, goal: np.ndarray) -> float:
        """Length (m) of the shortest walk from `start` to `goal` around the disks."""
        start = np.asarray(start, dtype=float)
        goal = np.asarray(goal, dtype=float)
        disks = self.obstacles
        active = np.ones(len(disks), dtype=bool)
        if len(disks):
            for p in (start, goal):
                active &= np.linalg.norm(disks[:, :2] - p, axis=1) >= disks[:, 2] - _EPS
        direct = float(np.linalg.norm(goal - start))
        if not active.any() or not _blocked(start[None], goal[None], disks[active])[0, 0]:
            return direct
        if active.all():
            corners, graph = self._corners, self._graph
        else:
            sub = disks[active]
            corners, _ = self._make_corners(sub)
            graph = self._corner_graph(sub, corners)
        act = disks[active]
        ends = np.stack([start, goal])
        m = len(corners)
        full = np.full((m + 2, m + 2), np.inf)
        full[:m, :m] = graph
        link = np.linalg.norm(ends[:, None, :] - corners[None, :, :], axis=-1)
        link = np.where(_blocked(ends, corners, act), np.inf, link)
        full[m : m + 2, :m] = link
        full[:m, m : m + 2] = link.T
        np.fill_diagonal(full, 0.0)
        finite = np.isfinite(full)
        weights = np.where(finite, np.maximum(full, 1e-12), 0.0)
        dist = dijkstra(weights, directed=False, indices=m)
        return float(dist[m + 1])


@dataclass
class LazyCosts:
    """Agent-target costs known as lower bounds until evaluated exactly.

    `lower` (n, n) holds straight-line distances; `exact(i, j)` returns the
    path length. `evaluated` counts exact evaluations.
    """

    lower: np.ndarray
    exact_fn: Callable[[int, int], float]

    def __post_init__(self):
        self.cost = np.array(self.lower, dtype=float)
        self.known = np.zeros(self.cost.shape, dtype=bool)
        self.evaluated = 0

    @classmethod
    def around(
        cls, agents: np.ndarray, targets: np.ndarray, obstacles: np.ndarray, sides: int = 16
    ) -> LazyCosts:
        agents = np.asarray(agents, dtype=float)
        targets = np.asarray(targets, dtype=float)
        planner = PathPlanner(obstacles, sides)
        return cls(
            scram.distances(agents, targets),
            lambda i, j: planner.length(agents[i], targets[j]),
        )

    def exact(self, i: int, j: int) -> float:
        if not self.known[i, j]:
            self.cost[i, j] = max(self.cost[i, j], float(self.exact_fn(i, j)))
            self.known[i, j] = True
            self.evaluated += 1
        return float(self.cost[i, j])

    def full(self) -> np.ndarray:
        """Evaluates every pair (the eager baseline) and returns the matrix."""
        n, m = self.cost.shape
        for i in range(n):
            for j in range(m):
                self.exact(i, j)
        return self.cost


@dataclass
class LazyResult:
    """Assignment (target of each agent) and how many pair costs were evaluated."""

    assignment: np.ndarray
    evaluated: int
    pairs: int


def lazy_assign(costs: LazyCosts, method: str = "msd") -> LazyResult:
    """Assignment on path costs evaluating only the pairs the search needs.

    ``msd`` runs the Hungarian algorithm on the lower bounds and evaluates a
    pair exactly when it would enter the shortest-path tree (the demand-driven
    scheme of Aakash and Saha). Other `scram.METHODS` with a monotone
    objective (``mmdr``, ``mmd-msd2``, ``msd2``, ...) iterate: solve on the
    current costs, evaluate the pairs of the solution still at their bound,
    and stop when the solution uses exact costs only; its true cost is then
    no worse than any other mapping's bound, hence optimal.
    """
    n = costs.cost.shape[0]
    if method == "msd":
        # The search raises `cost` and sets `known` in place as it evaluates.
        res = hungarian(costs.cost, costs.exact_fn, costs.known)
        costs.evaluated += res.evaluated
        return LazyResult(res.assignment, costs.evaluated, n * n)
    if method not in ("mmdr", "mmdr-n5", "mmdr-dp", "brute-force", "mmd-msd2", "msd2"):
        raise ValueError(f"method {method!r} has no lazy form")
    while True:
        a = scram.assign_costs(costs.cost, method)
        pending = [(i, int(j)) for i, j in enumerate(a) if not costs.known[i, j]]
        if not pending:
            return LazyResult(a, costs.evaluated, n * n)
        for i, j in pending:
            costs.exact(i, j)

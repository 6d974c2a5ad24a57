"""Prioritized SCRAM role assignment (dissertation chapter 6).

A target j with priority value P[j] > 0 and priority distance D[j] costs
``d + P[j]`` to an agent farther than D[j] from it and ``d`` otherwise. With P
larger than any distance, SCRAM first brings agents within D of every high
priority target as fast as possible, then assigns the rest; agents inside D
may still swap targets, which preserves collision avoidance. Several priority
levels are several P values (e.g. supporter P = 10000 over marking P = 100).
"""

from __future__ import annotations

import numpy as np

from formations import scram


def prioritized_costs(dist: np.ndarray, priority: np.ndarray, priority_distance: np.ndarray) -> np.ndarray:
    """(n, m) costs from (n, m) distances (m) and per-target P (m) and D (m), meters."""
    dist = np.asarray(dist, dtype=float)
    priority = np.broadcast_to(np.asarray(priority, dtype=float), dist.shape[1:])
    priority_distance = np.broadcast_to(np.asarray(priority_distance, dtype=float), dist.shape[1:])
    return dist + np.where(dist > priority_distance[None, :], priority[None, :], 0.0)


def assign(
    agents: np.ndarray,
    targets: np.ndarray,
    priority: np.ndarray | float = 0.0,
    priority_distance: np.ndarray | float = 0.0,
    method: str = "mmdr",
    *,
    seed: int = 0,
) -> np.ndarray:
    """Prioritized assignment; returns the index of each agent's target.

    `agents`, `targets`: (n, 2) positions in meters. `priority` (P) and
    `priority_distance` (D, meters) are per-target arrays or scalars; P = 0
    means normal priority. Any `scram.METHODS` entry is accepted.
    """
    agents = np.asarray(agents, dtype=float)
    targets = np.asarray(targets, dtype=float)
    n = len(targets)
    priority = np.broadcast_to(np.asarray(priority, dtype=float), (n,))
    priority_distance = np.broadcast_to(np.asarray(priority_distance, dtype=float), (n,))
    cost = prioritized_costs(scram.distances(agents, targets), priority, priority_distance)
    order = np.lexsort((np.arange(n), -targets[:, 0])) if n else None
    return scram.assign_costs(cost, method, target_order=order, seed=seed)


def time_to_reach(dist: np.ndarray, priority_distance: np.ndarray | float = 0.0) -> np.ndarray:
    """Distance still to travel before being within D of the target (>= 0), meters."""
    return np.maximum(np.asarray(dist, dtype=float) - priority_distance, 0.0)

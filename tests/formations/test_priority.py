"""Prioritized SCRAM: high-priority targets are reached first."""

from __future__ import annotations

import itertools

import numpy as np

from formations import priority, scram


def per_target(dist, assignment):
    """Distance travelled to each target under `assignment` (agent -> target)."""
    out = np.empty(len(assignment))
    out[assignment] = dist[np.arange(len(assignment)), assignment]
    return out


def brute_min_high_makespan(dist, high, d):
    n = len(dist)
    best = np.inf
    for p in itertools.permutations(range(n)):
        c = per_target(dist, np.array(p))
        best = min(best, float(np.max(np.maximum(c[high] - d, 0.0))))
    return best


def test_prioritized_reaches_high_priority_targets_first():
    rng = np.random.default_rng(61)
    for _ in range(150):
        n = int(rng.integers(2, 7))
        agents = rng.uniform(0, 100, (n, 2))
        targets = rng.uniform(0, 100, (n, 2))
        high = rng.permutation(n)[: max(1, n // 2)]
        pri = np.zeros(n)
        pri[high] = 99_999.0
        dd = np.zeros(n)
        dd[high] = 1.0
        dist = scram.distances(agents, targets)
        best = brute_min_high_makespan(dist, high, 1.0)
        for method in ("mmdr", "mmd-msd2", "mmdr-n5", "brute-force"):
            a = priority.assign(agents, targets, pri, dd, method)
            reach = priority.time_to_reach(per_target(dist, a)[high], 1.0)
            assert reach.max() <= best + 1e-9, method
        # Without priorities the high-priority makespan is never better.
        a = scram.assign(agents, targets, "mmdr")
        plain = priority.time_to_reach(per_target(dist, a)[high], 1.0).max()
        assert plain >= best - 1e-9


def test_several_priority_levels():
    rng = np.random.default_rng(62)
    for _ in range(100):
        n = 6
        agents = rng.uniform(0, 50, (n, 2))
        targets = rng.uniform(0, 50, (n, 2))
        pri = np.array([10_000.0, 100.0, 100.0, 0, 0, 0])
        dd = np.array([1.5, 3.0, 3.0, 0, 0, 0])
        a = priority.assign(agents, targets, pri, dd, "mmdr")
        dist = scram.distances(agents, targets)
        # Top level: the single highest target gets its nearest agent.
        top = np.maximum(dist[:, 0] - 1.5, 0)
        assert np.maximum(per_target(dist, a)[0] - 1.5, 0) == top.min()
        # Second level is optimal among mappings optimal for the first.
        best = np.inf
        for p in itertools.permutations(range(n)):
            p = np.array(p)
            c = per_target(dist, p)
            if max(c[0] - 1.5, 0) > top.min():
                continue
            lvl2 = np.maximum(c[1:3] - 3.0, 0).max()
            best = min(best, lvl2)
        got = np.maximum(per_target(dist, a)[1:3] - 3.0, 0).max()
        assert got <= best + 1e-9


def test_priority_distance_allows_swaps_and_no_collision():
    # Figure 6.3: inside D of H the agents swap rather than collide.
    agents = np.array([[0.0, 0.0], [1.0, 0.0]])
    targets = np.array([[2.0, 0.0], [-1.0, 0.0]])  # H at x=2 (high), L at x=-1
    pri = np.array([99_999.0, 0.0])
    a = priority.assign(agents, targets, pri, np.array([1.5, 0.0]))
    assert a.tolist() == [1, 0]
    costs = priority.prioritized_costs(scram.distances(agents, targets), pri, [1.5, 0.0])
    assert costs[0, 0] == 2.0 + 99_999.0 and costs[1, 0] == 1.0

"""Path costs around obstacles, evaluated lazily."""

from __future__ import annotations

import numpy as np
from scipy.optimize import linear_sum_assignment

from formations import pathcost, scram


def test_single_disk_matches_geometry():
    pl = pathcost.PathPlanner(np.array([[0.0, 0.0, 1.0]]), sides=64)
    # Tangent lengths plus the arc between tangent points.
    L = 3.0
    tangent = np.sqrt(L * L - 1.0)
    arc = np.pi - 2 * np.arccos(1.0 / L)
    exact = 2 * tangent + arc
    got = pl.length([-L, 0.0], [L, 0.0])
    assert exact <= got <= exact * (1 / np.cos(np.pi / 64))
    assert pl.length([-3.0, 2.0], [3.0, 2.0]) == 6.0  # clear line
    assert pl.length([0.5, 0.0], [3.0, 0.0]) == 2.5  # start inside: disk ignored


def test_no_obstacles_is_euclidean():
    pl = pathcost.PathPlanner(np.zeros((0, 3)))
    assert pl.length([0.0, 0.0], [3.0, 4.0]) == 5.0


def test_lazy_equals_eager_and_saves_evaluations():
    rng = np.random.default_rng(81)
    saved = []
    for _ in range(25):
        n = 11
        agents = rng.uniform([-15, -10], [15, 10], (n, 2))
        targets = rng.uniform([-15, -10], [15, 10], (n, 2))
        obstacles = np.concatenate(
            [rng.uniform([-10, -6], [10, 6], (3, 2)), rng.uniform(0.3, 1.0, (3, 1))], axis=1
        )
        full = pathcost.LazyCosts.around(agents, targets, obstacles).full()
        assert np.all(full >= scram.distances(agents, targets) - 1e-12)
        lazy = pathcost.LazyCosts.around(agents, targets, obstacles)
        res = pathcost.lazy_assign(lazy, "msd")
        r, c = linear_sum_assignment(full)
        assert abs(full[np.arange(n), res.assignment].sum() - full[r, c].sum()) < 1e-9
        assert res.evaluated == lazy.known.sum() <= n * n
        saved.append(res.evaluated)
        for method in ("mmdr", "mmd-msd2"):
            lazy = pathcost.LazyCosts.around(agents, targets, obstacles)
            res = pathcost.lazy_assign(lazy, method)
            ref = scram.assign_costs(full, method)
            np.testing.assert_allclose(
                scram.cost_vector(full, res.assignment)[:1], scram.cost_vector(full, ref)[:1]
            )
            if method == "mmdr":
                np.testing.assert_allclose(
                    scram.cost_vector(full, res.assignment), scram.cost_vector(full, ref)
                )
            assert res.evaluated < n * n
    assert np.mean(saved) < 0.5 * 121

"""Role assignment methods against brute force and the SCRAM properties."""

from __future__ import annotations

import itertools
from functools import cache

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linear_sum_assignment

from formations import _bigint, _kernels, _lsap, scram
from formations import bottleneck as bn
from formations.bottleneck import bottleneck

EXACT_MMDR = ("mmdr", "mmdr-n5", "mmdr-dp", "brute-force")


@cache
def all_mappings(n):
    return np.array(list(itertools.permutations(range(n))), dtype=np.int64).reshape(-1, n)


def reference(cost):
    """Brute-force optima: lexicographic vector, (makespan, sumsq), sum, sumsq."""
    n = len(cost)
    perms = all_mappings(n)
    c = cost[np.arange(n), perms]
    vecs = -np.sort(-c, axis=1)
    lex = min(map(tuple, vecs))
    mk = c.max(axis=1)
    sq = (c * c).sum(axis=1)
    best_mk = mk.min()
    return {
        "lex": np.array(lex),
        "makespan": best_mk,
        "sumsq_at_makespan": sq[mk == best_mk].min(),
        "sum": c.sum(axis=1).min(),
        "sumsq": sq.min(),
    }


def random_problem(rng, n):
    kind = rng.integers(3)
    if kind == 0:  # continuous positions, no ties
        return rng.uniform(-10, 10, (n, 2)), rng.uniform(-10, 10, (n, 2))
    # small integer grids: many equal distances (ties)
    side = 3 if kind == 1 else 6
    a = rng.choice(side * side, n, replace=False)
    t = rng.choice(side * side, n, replace=False)
    grid = lambda k: np.stack([k // side, k % side], axis=1).astype(float)  # noqa: E731
    return grid(a), grid(t)


def check_all_methods(agents, targets):
    n = len(agents)
    cost = scram.distances(agents, targets)
    ref = reference(cost)
    for method in scram.METHODS:
        a = scram.assign(agents, targets, method)
        assert sorted(a.tolist()) == list(range(n)), method
    for method in EXACT_MMDR:
        a = scram.assign(agents, targets, method)
        np.testing.assert_array_equal(scram.cost_vector(cost, a), ref["lex"], err_msg=method)
    a = scram.assign(agents, targets, "mmd-msd2")
    c = cost[np.arange(n), a]
    assert c.max() == ref["makespan"]
    assert (c * c).sum() <= ref["sumsq_at_makespan"] + 1e-9
    a = scram.assign(agents, targets, "msd")
    assert cost[np.arange(n), a].sum() <= ref["sum"] + 1e-9
    a = scram.assign(agents, targets, "msd2")
    assert (cost[np.arange(n), a] ** 2).sum() <= ref["sumsq"] + 1e-9


def test_thousands_of_small_problems_against_brute_force():
    rng = np.random.default_rng(20150125)
    for _ in range(2000):
        n = int(rng.integers(1, 7))
        check_all_methods(*random_problem(rng, n))


points = st.lists(st.tuples(st.integers(-4, 4), st.integers(-4, 4)), min_size=1, max_size=6, unique=True)


@settings(max_examples=100, deadline=None, derandomize=True, database=None)
@given(st.data())
def test_hypothesis_grid_problems(data):
    agents = data.draw(points)
    targets = data.draw(
        st.lists(
            st.tuples(st.integers(-4, 4), st.integers(-4, 4)),
            min_size=len(agents),
            max_size=len(agents),
            unique=True,
        )
    )
    check_all_methods(np.array(agents, float), np.array(targets, float))


@pytest.mark.parametrize("n", [7, 8, 9])
def test_mmdr_algorithms_agree_beyond_brute_force_size(n):
    rng = np.random.default_rng(n)
    for _ in range(5):
        agents, targets = random_problem(rng, n)
        cost = scram.distances(agents, targets)
        vecs = [scram.cost_vector(cost, scram.assign(agents, targets, m)) for m in EXACT_MMDR]
        for v in vecs[1:]:
            np.testing.assert_array_equal(v, vecs[0])


@pytest.mark.parametrize("n", [30, 150])
def test_large_problems_consistent(n):
    rng = np.random.default_rng(n)
    agents = rng.integers(0, n * n, (n, 2)).astype(float)
    targets = rng.integers(0, n * n, (n, 2)).astype(float)
    cost = scram.distances(agents, targets)
    value, match = bottleneck(cost)
    assert cost[np.arange(n), match].max() == value
    mmdr = scram.assign(agents, targets, "mmdr")
    n5 = scram.assign(agents, targets, "mmdr-n5")
    np.testing.assert_array_equal(scram.cost_vector(cost, mmdr), scram.cost_vector(cost, n5))
    mmd = scram.assign(agents, targets, "mmd-msd2")
    assert scram.makespan(cost, mmd) == value == scram.makespan(cost, mmdr)
    # No mapping under the bottleneck beats MMD+MSD^2 on squares; MSD^2 is a bound.
    msd2 = scram.assign(agents, targets, "msd2")
    sq = lambda a: float((cost[np.arange(n), a] ** 2).sum())  # noqa: E731
    assert sq(msd2) <= sq(mmd) + 1e-6
    if scram.makespan(cost, msd2) <= value:
        assert sq(mmd) <= sq(msd2) + 1e-6


def min_distance_over_time(agents, targets, assignment, steps=400):
    """Minimum pairwise distance of agents moving at equal unit speed."""
    goal = targets[assignment]
    d = goal - agents
    length = np.linalg.norm(d, axis=1)
    unit = np.divide(d, length[:, None], out=np.zeros_like(d), where=length[:, None] > 0)
    best = np.inf
    for t in np.linspace(0.0, length.max(), steps):
        pos = agents + unit * np.minimum(t, length)[:, None]
        gap = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
        gap[np.diag_indices(len(pos))] = np.inf
        best = min(best, gap.min())
    return best


def pairwise_closest_approach(agents, targets, assignment):
    """Exact minimum distance between every pair over the whole motion."""
    goal = targets[assignment]
    d = goal - agents
    length = np.linalg.norm(d, axis=1)
    unit = np.divide(d, length[:, None], out=np.zeros_like(d), where=length[:, None] > 0)
    n = len(agents)
    best = np.inf
    # Piecewise linear relative motion; breakpoints when an agent arrives.
    times = np.unique(np.concatenate([[0.0], length]))

    def rel(i, j, t):
        return (agents[i] + unit[i] * min(t, length[i])) - (agents[j] + unit[j] * min(t, length[j]))

    for i in range(n):
        for j in range(i + 1, n):
            for t0, t1 in zip(times[:-1], times[1:]):
                a, b = rel(i, j, t0), rel(i, j, t1)
                v = b - a
                vv = v @ v
                s = 0.0 if vv == 0 else np.clip(-(a @ v) / vv, 0.0, 1.0)
                best = min(best, float(np.linalg.norm(a + s * v)))
            best = min(best, float(np.linalg.norm(goal[i] - goal[j])))
    return best


def test_no_collisions_for_cm_valid_methods():
    rng = np.random.default_rng(7)
    crossings = 0
    for _ in range(150):
        n = int(rng.integers(2, 8))
        agents = rng.uniform(0, 10, (n, 2))
        targets = rng.uniform(0, 10, (n, 2))
        for method in ("mmdr", "mmd-msd2"):
            a = scram.assign(agents, targets, method)
            assert pairwise_closest_approach(agents, targets, a) > 1e-6, method
        # Sanity: the checker does see collisions of non-CM-valid mappings.
        rand = scram.assign(agents, targets, "random", seed=int(rng.integers(1000)))
        crossings += pairwise_closest_approach(agents, targets, rand) < 1e-6
    assert crossings == 0 or crossings > 0  # random crossings are possible, not required
    collide = np.array([[0.0, 0.0], [2.0, 0.0]])
    goals = np.array([[2.0, 1.0], [0.0, 1.0]])
    assert pairwise_closest_approach(collide, goals, np.array([0, 1])) < 1e-9
    assert pairwise_closest_approach(collide, goals, scram.assign(collide, goals)) > 0.5


def test_sampled_motion_keeps_distance():
    rng = np.random.default_rng(8)
    for _ in range(20):
        agents = rng.uniform(0, 10, (6, 2))
        targets = rng.uniform(0, 10, (6, 2))
        a = scram.assign(agents, targets, "mmdr")
        assert min_distance_over_time(agents, targets, a) > 0


def test_mmdr_is_dynamically_consistent():
    rng = np.random.default_rng(9)
    for _ in range(60):
        n = int(rng.integers(2, 9))
        agents = rng.uniform(0, 20, (n, 2))
        targets = rng.uniform(0, 20, (n, 2))
        a = scram.assign(agents, targets, "mmdr")
        goal = targets[a]
        d = goal - agents
        length = np.linalg.norm(d, axis=1)
        unit = d / length[:, None]
        for t in np.linspace(0, length.max(), 8)[1:-1]:
            pos = agents + unit * np.minimum(t, length)[:, None]
            # Agents that arrived sit on their targets; MMDR must not change.
            np.testing.assert_array_equal(scram.assign(pos, targets, "mmdr"), a)


def test_msd2_not_dynamically_consistent_example():
    # Appendix B.3: MSD^2 switches as agents move; MMDR does not.
    targets = np.array([[0.0, 0.0], [1.0, 0.0]])
    agents = np.array([[3.0, 0.0], [2.0, 999.0]])
    first = scram.assign(agents, targets, "msd2")
    assert first.tolist() == [1, 0]
    a1 = agents[0] + 2 * (targets[1] - agents[0]) / np.linalg.norm(targets[1] - agents[0])
    a2 = agents[1] + 2 * (targets[0] - agents[1]) / np.linalg.norm(targets[0] - agents[1])
    later = scram.assign(np.array([a1, a2]), targets, "msd2")
    assert later.tolist() == [0, 1]


def test_paper_three_agent_example():
    # Figure 5.2 ordering: the MMDR mapping has cost (sqrt2, sqrt2, 1).
    agents = np.array([[0.0, 1.0], [1.0, 1.0], [2.0, 1.0]])
    targets = np.array([[0.0, 0.0], [2.0, 2.0], [3.0, 0.0]])
    cost = scram.distances(agents, targets)
    for m in EXACT_MMDR:
        v = scram.cost_vector(cost, scram.assign(agents, targets, m))
        np.testing.assert_allclose(v, reference(cost)["lex"])


def test_baselines():
    rng = np.random.default_rng(3)
    agents = rng.uniform(0, 10, (6, 2))
    targets = rng.uniform(0, 10, (6, 2))
    assert scram.assign(agents, targets, "static").tolist() == list(range(6))
    r1 = scram.assign(agents, targets, "random", seed=1)
    assert np.array_equal(r1, scram.assign(agents, targets, "random", seed=1))
    cost = scram.distances(agents, targets)
    g = scram.assign(agents, targets, "greedy")
    # greedy takes the globally shortest pair first
    i, j = np.unravel_index(np.argmin(cost), cost.shape)
    assert g[i] == j
    go = scram.assign(agents, targets, "greedy-offense")
    first = int(np.argmax(targets[:, 0]))
    assert go[int(np.argmin(cost[:, first]))] == first


def test_deterministic_ties_and_edge_cases():
    agents = np.array([[0.0, 0.0], [0.0, 0.0 + 2.0]])
    targets = np.array([[1.0, 1.0], [-1.0, 1.0]])  # all four distances equal
    for m in scram.METHODS:
        a = scram.assign(agents, targets, m)
        assert np.array_equal(a, scram.assign(agents, targets, m)), m
    for m in scram.METHODS:
        assert scram.assign(np.zeros((0, 2)), np.zeros((0, 2)), m).size == 0
        assert scram.assign([[1.0, 2.0]], [[3.0, 4.0]], m).tolist() == [0]
    with pytest.raises(ValueError, match="unknown method"):
        scram.assign(agents, targets, "hungarian-ish")
    with pytest.raises(ValueError):
        scram.assign(agents, targets[:1])
    with pytest.raises(ValueError):
        scram.assign_costs(np.array([[np.nan]]))


def test_sparse_paths_against_brute_force():
    # Large problems use the sparse forms (candidate edges, heap searches);
    # run them on small problems too (ties included) to compare with brute force.
    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(1, 7))
        cost = scram.distances(*random_problem(rng, n))
        ref = reference(cost)
        b = _kernels.mmd_msd2(cost, 0)
        c = cost[np.arange(n), b]
        assert c.max() == ref["makespan"]
        assert (c * c).sum() <= ref["sumsq_at_makespan"] + 1e-9
        value, match = bottleneck(cost)
        assert value == ref["makespan"] == cost[np.arange(n), match].max()
        np.testing.assert_array_equal(scram.cost_vector(cost, _kernels.mmdr(cost, 0)), ref["lex"])


def test_many_ties_large_n():
    rng = np.random.default_rng(12)
    n = 40
    grid = np.stack(np.meshgrid(np.arange(8), np.arange(8)), -1).reshape(-1, 2).astype(float)
    agents = grid[rng.choice(64, n, replace=False)]
    targets = grid[rng.choice(64, n, replace=False)] + [0.0, 3.0]
    cost = scram.distances(agents, targets)
    ref = scram.cost_vector(cost, scram.mmdr_n5(cost))
    np.testing.assert_array_equal(scram.cost_vector(cost, scram.mmdr(cost)), ref)
    sub = cost[:14, :14]
    np.testing.assert_array_equal(
        scram.cost_vector(sub, scram.mmdr_dp(sub)), scram.cost_vector(sub, scram.mmdr(sub))
    )


@pytest.mark.parametrize("n", [12, 20, 40, 150])
def test_mmdr_and_mmd_agree_at_medium_n(n):
    # Sokkalingam-Aneja (forced levels and 0-1 steps on ties) against the
    # exact 2^rank Hungarian; MMD+MSD^2's dense and sparse forms agree on value.
    rng = np.random.default_rng(100 + n)
    for _ in range(4):
        side = n // 4 if rng.integers(2) else 4 * n  # many ties, or few
        k = rng.choice(side * side, 2 * n, replace=2 * n > side * side)
        pts = np.stack([k // side, k % side], axis=1).astype(float)
        cost = scram.distances(pts[:n], pts[n:])
        ref = scram.cost_vector(cost, scram.mmdr_n5(cost))
        np.testing.assert_array_equal(scram.cost_vector(cost, scram.mmdr(cost)), ref)
        dense, sparse = _kernels.mmd_msd2(cost, n), _kernels.mmd_msd2(cost, 0)
        rows = np.arange(n)
        assert cost[rows, dense].max() == cost[rows, sparse].max() == ref[0]
        np.testing.assert_allclose(
            (cost[rows, dense] ** 2).sum(), (cost[rows, sparse] ** 2).sum(), rtol=1e-12
        )


def test_bottleneck_kernels_against_brute_force():
    # Dense and candidate-edge bottlenecks on seeded random problems,
    # continuous and on small integer grids (many tied distances).
    rng = np.random.default_rng(14)
    for _ in range(400):
        n = int(rng.integers(1, 7))
        cost = scram.distances(*random_problem(rng, n))
        value, match = bn.bottleneck_dense(cost, np.full(n, -1, np.int64))
        assert value == reference(cost)["makespan"] == cost[np.arange(n), match].max()
    for n in (20, 60, 150, 400):
        for side in (n // 4, 4 * n):
            k = rng.choice(side * side, 2 * n, replace=2 * n > side * side)
            pts = np.stack([k // side, k % side], axis=1).astype(float)
            cost = scram.distances(pts[:n], pts[n:])
            value, match, indptr, _, weights = bn.bottleneck_large(cost)
            assert value == bn.bottleneck_dense(cost, np.full(n, -1, np.int64))[0]
            assert cost[np.arange(n), match].max() == value
            assert np.count_nonzero(weights <= value) == np.count_nonzero(cost <= value)


def test_matchable_edges_are_those_of_some_bottleneck_matching():
    # mmdr-n5 keeps only the edges <= the bottleneck that lie in some perfect
    # matching of that graph; brute force enumerates every such matching.
    rng = np.random.default_rng(15)
    for _ in range(300):
        n = int(rng.integers(1, 7))
        cost = scram.distances(*random_problem(rng, n))
        b, match = bn.bottleneck_dense(cost, np.full(n, -1, np.int64))
        edge = np.empty(n * n, np.int64)
        value = np.empty(n * n)
        k = bn.matchable_edges(cost, b, match, edge, value)
        expected = {
            i * n + p[i]
            for p in itertools.permutations(range(n))
            if all(cost[i, p[i]] <= b for i in range(n))
            for i in range(n)
        }
        assert set(edge[:k].tolist()) == expected
        np.testing.assert_array_equal(value[:k], cost.ravel()[edge[:k]])


def test_distances_exact_on_integer_grids():
    # Equal distances on integer points are exactly equal (ties stay ties).
    a = np.array([[0.0, 0.0], [3.0, 4.0], [1e6, 0.0]])
    t = np.array([[3.0, 4.0], [5.0, 0.0], [0.0, 5.0], [1e6 + 3.0, -4.0]])
    d = scram.distances(a, t)
    assert d[0, 0] == d[0, 1] == d[0, 2] == 5.0
    assert d[2, 3] == 5.0
    np.testing.assert_allclose(d, np.hypot(a[:, None, 0] - t[None, :, 0], a[:, None, 1] - t[None, :, 1]))


def test_brute_force_tie_order():
    # The split evaluation of all n! mappings keeps the documented tie rule:
    # the first lexicographically optimal mapping in `permutations(n)` order.
    rng = np.random.default_rng(16)
    for _ in range(150):
        n = int(rng.integers(1, 8))
        cost = scram.distances(*random_problem(rng, n))
        perms = scram.permutations(n).astype(np.int64)
        vecs = -np.sort(-scram.dense_ranks(cost)[np.arange(n), perms], axis=1)
        first = np.lexsort(vecs.T[::-1])[0]  # stable: the first among equal vectors
        np.testing.assert_array_equal(scram.mmdr_brute_force(cost), perms[first])


costs_matrix = st.integers(1, 9).flatmap(
    lambda n: st.lists(
        st.lists(st.sampled_from([0.0, 1.0, 2.0, 2.5, 3.0, np.inf]), min_size=n, max_size=n),
        min_size=n,
        max_size=n,
    )
)


@settings(max_examples=300, deadline=None, derandomize=True, database=None)
@given(costs_matrix)
def test_compiled_lsap_is_scipys_algorithm(rows):
    # `lsap_dense` returns scipy's assignment (ties included) and optimal
    # duals; `lsap_sparse` an assignment of the same cost; both report
    # infeasibility (inf = forbidden pair).
    cost = np.array(rows, dtype=float)
    n = len(cost)
    col4row, u, v = _lsap.lsap_dense(cost)
    finite = np.isfinite(cost)
    r, c = np.nonzero(finite)
    indptr = np.searchsorted(r, np.arange(n + 1))
    sparse = _lsap.lsap_sparse(n, indptr, c.astype(np.int64), cost[r, c])[0]
    try:
        ref = linear_sum_assignment(cost)[1]
    except ValueError:
        assert col4row[0] == -2 and sparse[0] == -2
        return
    np.testing.assert_array_equal(col4row, ref)
    reduced = cost - u[:, None] - v[None, :]
    assert (reduced[finite] >= -1e-9).all()
    np.testing.assert_allclose(reduced[np.arange(n), col4row], 0.0, atol=1e-9)
    assert sorted(sparse.tolist()) == list(range(n))
    assert cost[np.arange(n), sparse].sum() == cost[np.arange(n), ref].sum()


def test_scipy_identical_min_sum_on_grid_squares():
    # The min-sum steps (msd, msd2, mmd-msd2 up to LSAP_DENSE_N) match scipy's
    # linear_sum_assignment on the same matrices, rounding of squares included.
    rng = np.random.default_rng(18)
    for _ in range(300):
        n = int(rng.integers(2, 10))  # random_problem's 3 x 3 grid holds 9 points
        agents, targets = random_problem(rng, n)
        cost = scram.distances(agents, targets)
        for method, matrix in (("msd", cost), ("msd2", cost * cost)):
            np.testing.assert_array_equal(
                scram.assign(agents, targets, method), linear_sum_assignment(matrix)[1]
            )
        value = bottleneck(cost)[0]
        expected = linear_sum_assignment(np.where(cost <= value, cost * cost, np.inf))[1]
        np.testing.assert_array_equal(scram.assign(agents, targets, "mmd-msd2"), expected)


def test_inputs_any_layout_and_bad_inputs():
    rng = np.random.default_rng(19)
    agents, targets = rng.uniform(0, 10, (6, 2)), rng.uniform(0, 10, (6, 2))
    ref = {m: scram.assign(agents, targets, m) for m in scram.METHODS}
    wide = np.hstack([agents, np.zeros((6, 1))])[:, :2]  # a non-contiguous view
    frozen = targets.copy()
    frozen.flags.writeable = False
    for m in scram.METHODS:
        np.testing.assert_array_equal(scram.assign(wide, frozen, m), ref[m])
        np.testing.assert_array_equal(scram.assign(agents.tolist(), targets.tolist(), m), ref[m])
    cost = scram.distances(agents, targets)
    np.testing.assert_array_equal(scram.assign_costs(cost.T.copy().T, "mmdr"), ref["mmdr"])
    for bad in ([1.0, 2.0], np.zeros((3, 1)), np.zeros((2, 2, 2))):
        with pytest.raises(ValueError):
            scram.assign(bad, bad)
    with pytest.raises(ValueError, match="finite"):
        scram.assign([[0.0, np.inf]], [[0.0, 0.0]])
    with pytest.raises(ValueError, match="square"):
        scram.assign_costs(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="square"):
        scram.assign_costs(np.float64(1.0))
    with pytest.raises(ValueError, match="limited"):
        scram.assign_costs(np.zeros((DP_N := scram.DP_MAX_N + 1, DP_N)), "mmdr-dp")


def test_kernels_compile_in_memory_without_a_cache_location(monkeypatch):
    # A read-only install without a writable home: numba cannot cache, so
    # the kernels are compiled in memory (one warning), not an import error.
    import numba

    from formations import _jit

    real = numba.njit

    def no_locator(*args, **kwargs):
        if kwargs.get("cache"):
            raise RuntimeError("cannot cache function 'f': no locator available for file 'f.py'")
        return real(*args, **kwargs)

    monkeypatch.setattr(_jit.numba, "njit", no_locator)
    monkeypatch.setattr(_jit, "_warned", False)
    with pytest.warns(RuntimeWarning, match="not cached"):
        double = _jit.njit(lambda x: 2 * x)
    assert double(21) == 42


@settings(max_examples=150, deadline=None, derandomize=True, database=None)
@given(st.data())
def test_hypothesis_sparse_and_multiword_kernels(data):
    # The forms large problems take (candidate edges, heap searches, sparse
    # min-sum, multiword 2^rank Hungarian) on small grid problems with ties.
    agents = np.array(data.draw(points), float)
    n = len(agents)
    targets = np.array(data.draw(st.permutations(range(81)))[:n], float)
    targets = np.stack([targets // 9 - 4, targets % 9 - 4], axis=1)
    cost = scram.distances(agents, targets)
    ref = reference(cost)
    rows = np.arange(n)
    assert bn.bottleneck_large(cost)[0] == ref["makespan"]
    np.testing.assert_array_equal(scram.cost_vector(cost, _kernels.mmdr(cost, 0)), ref["lex"])
    exact = _bigint.hungarian_pow2(_kernels.rank_weights(cost), n * n)
    np.testing.assert_array_equal(scram.cost_vector(cost, exact), ref["lex"])
    mmd = cost[rows, _kernels.mmd_msd2(cost, 0)]
    assert mmd.max() == ref["makespan"]
    assert (mmd * mmd).sum() <= ref["sumsq_at_makespan"] + 1e-9

"""Marking: whom to mark, where, which roles they replace, hysteresis."""

from __future__ import annotations

import numpy as np

from formations import field, marking
from formations.delaunay import Formation


def test_marking_position_is_toward_our_goal():
    opp = np.array([[-8.0, 3.0], [-14.0, 0.5]])
    pos = marking.marking_positions(opp, 1.5)
    np.testing.assert_allclose(np.linalg.norm(pos[0] - opp[0]), 1.5)
    to_goal = field.OWN_GOAL - opp[0]
    step = pos[0] - opp[0]
    np.testing.assert_allclose(step[0] * to_goal[1] - step[1] * to_goal[0], 0.0, atol=1e-12)
    assert np.linalg.norm(field.OWN_GOAL - pos[0]) < np.linalg.norm(to_goal)
    assert np.all(field.inside_field(pos))


def test_whom_to_mark_rules_and_hysteresis():
    p = marking.MarkingParams()
    ball = np.array([-3.0, 0.0])
    opp = np.array(
        [
            [-3.5, 0.0],  # closest to ball -> onBall handles it
            [-8.0, 4.0],  # dangerous, marked
            [0.0, 0.0],  # too far from goal
            [-6.0, -8.0],  # out of shot range
            [-4.0, 1.0],  # too close to the ball
        ]
    )
    m = marking.opponents_to_mark(opp, ball, params=p)
    assert m.tolist() == [False, True, False, False, False]
    # Just outside the shot range: not marked, unless marked before (0.25 m).
    r = p.shot_range + 0.1
    edge = np.array([[-3.5, 0.0], [-15 + r * np.cos(0.5), r * np.sin(0.5)]])
    assert not marking.opponents_to_mark(edge, ball, params=p)[1]
    assert marking.opponents_to_mark(edge, ball, marked=[False, True], params=p)[1]
    r = p.shot_range + 0.3
    far = np.array([[-3.5, 0.0], [-15 + r * np.cos(0.5), r * np.sin(0.5)]])
    assert not marking.opponents_to_mark(far, ball, marked=[False, True], params=p)[1]
    # Far behind the ball (opponents attack toward -x): not marked.
    behind = np.array([[-3.5, 0.0], [-3.0 + p.max_behind_ball + 0.5, 0.0]])
    assert not marking.opponents_to_mark(behind, ball, params=p)[1]


def test_role_selection_hungarian_and_one_meter_rule():
    formation = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0], [0.0, 5.0]])
    replaceable = np.array([False, True, True, True])
    marks = {7: np.array([4.0, 0.0]), 9: np.array([9.0, 1.0])}
    sel = marking.select_roles(formation, replaceable, marks)
    assert sel.pairs == {7: 1, 9: 2}
    # A previous selection survives unless the new one saves >= 1 m.
    prev = marking.RoleSelection({7: 3, 9: 2})
    prev_total = prev.total(formation, marks)
    new_total = sel.total(formation, marks)
    assert prev_total - new_total >= 1.0
    assert marking.select_roles(formation, replaceable, marks, prev).pairs == sel.pairs
    close = marking.RoleSelection({7: 1, 9: 3})
    marks2 = {7: np.array([4.0, 0.0]), 9: np.array([3.0, 4.2])}
    best = marking.select_roles(formation, replaceable, marks2)
    near_prev = marking.RoleSelection({7: 3, 9: 1})
    keep = marking.select_roles(formation, replaceable, marks2, near_prev)
    diff = near_prev.total(formation, marks2) - best.total(formation, marks2)
    assert (keep.pairs == near_prev.pairs) == (diff < 1.0)
    assert close.pairs  # dataclass sanity
    # More marks than replaceable roles: extra marks stay unassigned.
    many = {i: np.array([float(i), 0.0]) for i in range(5)}
    assert len(marking.select_roles(formation, replaceable, many).pairs) == 3


def test_full_plan_priorities_and_assignment():
    f = Formation.default()
    ball = np.array([-2.0, 1.0])
    pos = f.positions_at(ball)
    opp = np.array([[-2.5, 1.0], [-9.0, 4.0], [-10.0, -3.0], [5.0, 0.0]])
    plan = marking.plan(pos, f.roles, opp, ball)
    assert plan.marked.tolist() == [False, True, True, False]
    replaced = sorted(plan.selection.pairs.values())
    assert len(replaced) == 2
    for r in replaced:
        assert f.roles[r] not in ("goalie", "onBall", "supporter", "goalieReplacement")
        assert plan.priority[r] == 100.0 and plan.priority_distance[r] == 3.0
    s = f.index("supporter")
    assert plan.priority[s] == 10_000.0 and plan.priority_distance[s] == 1.5
    agents = np.random.default_rng(5).uniform([-15, -10], [15, 10], (len(f.roles), 2))
    a = plan.assign(agents)
    assert sorted(a.tolist()) == list(range(len(f.roles)))


def _numpy_opponents_to_mark(opponents, ball, marked=None):
    """opponents_to_mark on numpy arrays (the compiled kernel's spec)."""
    p = marking.MarkingParams()
    k = len(opponents)
    if k == 0:
        return np.zeros(0, dtype=bool)
    slack = 0.0 if marked is None else np.where(np.asarray(marked, bool), p.hysteresis, 0)
    to_goal = np.sqrt(np.sum((opponents - field.OWN_GOAL) ** 2, axis=1))
    to_ball = np.sqrt(np.sum((opponents - ball) ** 2, axis=1))
    not_closest = np.ones(k, dtype=bool)
    not_closest[int(np.argmin(to_ball))] = False
    return ((to_goal <= p.shot_range + slack) & not_closest & (to_ball >= p.min_ball_distance - slack)
            & (opponents[:, 0] - ball[0] <= p.max_behind_ball + slack))


def test_whom_to_mark_equals_the_numpy_rules_exactly():
    rng = np.random.default_rng(3)
    for _ in range(3000):
        k = int(rng.integers(0, 12))
        opp = rng.uniform([-16, -11], [16, 11], size=(k, 2))
        ball = rng.uniform([-16, -11], [16, 11], size=2)
        if rng.random() < 0.3:  # ties and exact thresholds
            opp, ball = np.round(opp * 4) / 4, np.round(ball * 4) / 4
        if k and rng.random() < 0.2:
            ball = opp[int(rng.integers(k))] + rng.normal(size=2) * rng.choice([0.0, 1e-12, 1.0])
        if k and rng.random() < 0.05:
            opp[int(rng.integers(k))] = np.nan
        marked = None if rng.random() < 0.5 else rng.random(k) < 0.5
        got = marking.opponents_to_mark(opp, ball, marked)
        assert got.dtype == bool
        np.testing.assert_array_equal(got, _numpy_opponents_to_mark(opp, ball, marked))

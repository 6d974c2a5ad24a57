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

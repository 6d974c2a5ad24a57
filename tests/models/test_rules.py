"""The league's rule on a full team's robot types (models.rules.robot_types_problem)."""

import numpy as np
import pytest

from models.rules import robot_type_join_problem, robot_types_problem
from models.scene import Lineup, default_types


@pytest.mark.parametrize("types", [
    default_types(11),
    (0, 4, 4, 4, 4, 4, 4, 4, 0, 1, 3),  # UT Austin Villa's 2014 team: 7 of type 4, 2 of type 0
    (0, 0, 0, 0, 0, 0, 0, 2, 2, 3, 3),  # 7 of one type, 9 of two
])
def test_legal_full_teams(types):
    assert robot_types_problem(types) is None


@pytest.mark.parametrize("types, words", [
    ((4,) * 11, "1 robot types"),
    ((0,) * 6 + (4,) * 5, "2 robot types"),
    ((4,) * 8 + (0, 1, 2), "8 robots of one type"),
    ((4,) * 7 + (0,) * 3 + (1,), "10 robots of two types"),
    ((0,) * 5 + (4,) * 5 + (1,), "10 robots of two types"),
])
def test_illegal_full_teams_say_which_rule(types, words):
    assert words in robot_types_problem(types)


def test_smaller_sides_may_play_any_types():
    assert robot_types_problem((4,) * 10) is None
    assert robot_types_problem((0,)) is None
    assert Lineup.default(4, 4).left == (0, 1, 2, 3, 4)[:4]


def test_joining_robots_are_held_to_what_a_full_team_may_be():
    assert robot_type_join_problem((4,) * 6, 4) is None
    assert "8 robots of type 4" in robot_type_join_problem((4,) * 7, 4)
    assert "10 robots of two types" in robot_type_join_problem((4,) * 5 + (0,) * 4, 0)
    assert "10 robots of two types" in robot_type_join_problem((4,) * 7 + (0,) * 2, 0)
    assert robot_type_join_problem((4,) * 7 + (0,) * 2, 1) is None
    for full in ((0, 4, 4, 4, 4, 4, 4, 4, 0, 1, 3), (0, 1, 2, 3, 4, 0, 1, 2, 3, 4, 0)):
        assert all(robot_type_join_problem(full[:k], full[k]) is None for k in range(11))


def test_joining_one_by_one_admits_exactly_the_legal_full_teams():
    rng = np.random.default_rng(7)
    for _ in range(2000):
        k = int(rng.integers(1, 6))  # teams of few types, so that many break the rule
        full = tuple(int(t) for t in rng.choice(rng.permutation(5)[:k], 11))
        joins = all(robot_type_join_problem(full[:i], full[i]) is None for i in range(11))
        assert joins == (robot_types_problem(full) is None), full

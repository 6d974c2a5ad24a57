"""walk_toward: the section's direction formula, braking, and side steps shrunk at speed."""

import math

import pytest

from skills.navigate import walk_toward
from skills.walk import default_param_files, direction_to_xy, load_walk_sets


@pytest.fixture(scope="module")
def params():
    return load_walk_sets(default_param_files(0))["go_to_target"]


def test_far_ahead_and_a_little_aside_it_walks_full_speed_with_half_the_side_step(params):
    d = math.radians(20.0)
    fx, fy = direction_to_xy(d, params.max_step_size_x, params.max_step_size_y)
    x, y, turn = walk_toward(3.0 * math.cos(d), 3.0 * math.sin(d), None, params)
    assert x == pytest.approx(fx) and fx == 1.0
    assert y == pytest.approx(0.5 * fy) and y > 0.1
    assert turn == pytest.approx(20.0 / 180.0)  # and turns toward the target
    assert walk_toward(3.0 * math.cos(d), 3.0 * math.sin(d), None, params,
                       side_at_speed=1.0)[1] == pytest.approx(fy)  # the formula unshrunk


def test_slow_near_the_target_the_side_step_is_whole(params):
    d = math.radians(20.0)
    fx, fy = direction_to_xy(d, params.max_step_size_x, params.max_step_size_y)
    x, y, _ = walk_toward(0.15 * math.cos(d), 0.15 * math.sin(d), None, params)  # braking: speed 0.3
    assert x == pytest.approx(0.3 * fx) and y == pytest.approx(0.3 * fy)


def test_the_side_step_shrinks_smoothly_with_the_forward_input(params):
    d = math.radians(25.0)
    ratios = []
    for dist in (0.15, 0.2, 0.25, 0.3, 0.35, 0.5):  # speed = dist / 0.5
        x, y, _ = walk_toward(dist * math.cos(d), dist * math.sin(d), None, params)
        ratios.append(y / x)
    assert all(a >= b for a, b in zip(ratios, ratios[1:]))
    assert ratios[-1] == pytest.approx(0.5 * ratios[0])
    assert max(a - b for a, b in zip(ratios, ratios[1:])) < 0.3 * ratios[0]  # no jump

"""The plane-geometry primitives: wrap, rotate and Pose2."""

import math

import numpy as np
import pytest

from models.geometry import Pose2, rotate, wrap

POSES = [Pose2(0.0, 0.0, 0.0), Pose2(1.5, -2.0, 0.7), Pose2(-4.2, 3.1, -2.9), Pose2(0.3, 0.1, math.pi)]


def _matrix(a: float) -> np.ndarray:
    return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])


@pytest.mark.parametrize("a", [0.0, 1.0, -1.0, math.pi, -math.pi, 3 * math.pi, -7.5, 100.0])
def test_wrap_range_and_equivalence(a):
    w = wrap(a)
    assert -math.pi <= w < math.pi
    assert math.isclose(math.cos(w), math.cos(a), abs_tol=1e-9)
    assert math.isclose(math.sin(w), math.sin(a), abs_tol=1e-9)


def test_wrap_arrays():
    a = np.linspace(-20.0, 20.0, 101)
    w = wrap(a)
    assert isinstance(w, np.ndarray)
    assert np.all((w >= -math.pi) & (w < math.pi))
    np.testing.assert_allclose(w, [wrap(float(v)) for v in a])
    assert wrap(math.pi) == -math.pi


def test_rotate_against_matrix():
    for a in (0.0, 0.4, -2.2, math.pi):
        np.testing.assert_allclose(rotate(0.7, -1.3, a), _matrix(a) @ [0.7, -1.3], atol=1e-12)


@pytest.mark.parametrize("pose", POSES)
def test_to_world_against_matrix_and_round_trip(pose):
    p = np.array([0.4, -1.1])
    world = pose.to_world(*p)
    np.testing.assert_allclose(world, _matrix(pose.heading) @ p + [pose.x, pose.y], atol=1e-12)
    np.testing.assert_allclose(pose.to_local(*world), p, atol=1e-12)


def test_vectorized_points():
    pose = POSES[1]
    xs, ys = np.array([0.0, 1.0, -2.0]), np.array([3.0, 0.5, 0.0])
    wx, wy = pose.to_world(xs, ys)
    for i in range(3):
        assert (wx[i], wy[i]) == pose.to_world(float(xs[i]), float(ys[i]))
    lx, ly = pose.to_local(wx, wy)
    np.testing.assert_allclose(lx, xs, atol=1e-12)
    np.testing.assert_allclose(ly, ys, atol=1e-12)


@pytest.mark.parametrize("pose", POSES)
def test_compose_with_inverse_is_identity(pose):
    for ident in (pose.compose(pose.inverse()), pose.inverse().compose(pose)):
        assert abs(ident.x) < 1e-12 and abs(ident.y) < 1e-12
        assert abs(wrap(ident.heading)) < 1e-12


def test_compose_chains_point_transforms():
    a, b = POSES[1], POSES[2]
    p = (0.25, -0.6)
    np.testing.assert_allclose(a.compose(b).to_world(*p), a.to_world(*b.to_world(*p)), atol=1e-12)

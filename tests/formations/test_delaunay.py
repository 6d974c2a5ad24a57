"""Delaunay formations: exact at samples, inside the field, file errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import formations
from formations import field
from formations.delaunay import Formation, FormationFileError, parse

DEFAULT = Formation.default()
DATA = Path(formations.__file__).parent / "data"

SMALL = """
# three samples
name tiny
roles a b
mirror a b
follow b
sample -10 -5
a -11 -5
b -10 -5
sample 10 -5
a 9 -4
b 10 -5
sample 0 5
a 0 4
b 0 5
"""


def test_default_formation_loads_with_eleven_player_roles():
    f = Formation.default()
    for role in (
        "goalie",
        "onBall",
        "supporter",
        "forwardLeft",
        "forwardRight",
        "wingLeft",
        "wingRight",
        "backLeft",
        "backRight",
        "goalieReplacement",
    ):
        assert role in f.roles
    assert len(f.roles) == 12  # 11 in play + goalieReplacement
    assert f.triangulation is not None


def test_interpolates_samples_exactly():
    f = DEFAULT
    for ball, pos in zip(f.balls, f.positions):
        got = f.positions_at(ball)
        expect = pos.copy()
        expect[f.index("onBall")] = ball
        np.testing.assert_array_equal(got, field.clip_to_field(expect, f.margin))


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(st.floats(-15, 15), st.floats(-10, 10))
def test_positions_inside_field_and_distinct(x, y):
    f = DEFAULT
    ball = np.array([x, y])
    pos = f.positions_at(ball)
    assert np.all(field.inside_field(pos, f.margin - 1e-9))
    np.testing.assert_array_equal(pos[f.index("onBall")], field.clip_to_field(ball, f.margin))
    others = np.delete(pos, f.index("onBall"), axis=0)
    gap = np.linalg.norm(others[:, None] - others[None], axis=-1) + 1e9 * np.eye(len(others))
    assert gap.min() > 0.05  # distinct targets, as SCRAM assumes


def test_barycentric_between_samples_and_nearest_outside_hull():
    f = parse(SMALL, "tiny.formation")
    # The centroid of the triangle averages the three samples.
    c = f.balls.mean(axis=0)
    np.testing.assert_allclose(f.positions_at(c)[0], f.positions[:, 0].mean(axis=0))
    np.testing.assert_allclose(f.positions_at(c)[1], c)  # b follows the ball
    # Outside the hull: nearest sample.
    np.testing.assert_allclose(f.positions_at([12.0, -9.0])[0], [9.0, -4.0])
    # Linear along an edge.
    mid = (f.balls[0] + f.balls[1]) / 2
    np.testing.assert_allclose(f.positions_at(mid)[0], (f.positions[0, 0] + f.positions[1, 0]) / 2)


def test_symmetry_mirrors_samples_and_swaps_partners():
    text = SMALL.replace("name tiny", "name tiny\nsymmetric yes")
    f = parse(text, "sym.formation")
    assert len(f.balls) == 6
    for ball in f.balls[:3]:
        p = f.positions_at(ball)
        q = f.positions_at(ball * [1, -1])
        np.testing.assert_allclose(q[0], p[1] * [1, -1])  # a <-> b mirrored
    # The default formation is left-right symmetric everywhere.
    d = DEFAULT
    rng = np.random.default_rng(4)
    swap = {r: r for r in d.roles}
    for left, right in (
        ("forwardLeft", "forwardRight"),
        ("wingLeft", "wingRight"),
        ("midLeft", "midRight"),
        ("backLeft", "backRight"),
    ):
        swap[left], swap[right] = right, left
    perm = [d.index(swap[r]) for r in d.roles]
    for ball in rng.uniform([-15, -10], [15, 10], (50, 2)):
        np.testing.assert_allclose(
            d.positions_at(ball * [1, -1]), d.positions_at(ball)[perm] * [1, -1], atol=1e-9
        )


def test_round_trip_dump():
    f = Formation.default()
    g = parse(f.dumps(), "dump.formation")
    np.testing.assert_allclose(g.balls, f.balls)
    np.testing.assert_allclose(g.positions, f.positions, atol=1e-5)


BAD = [
    ("roles a b\nsample 0 0\na 0 zero\nb 1 1\n", 3, "zero"),
    ("roles a b\nsample 0 0\na 0 0\n", 2, "missing"),
    ("roles a b\nsample 0 0\na 0 0\nb 1 1\nc 2 2\n", 5, "'c'"),
    ("roles a b\nsample 0 0\na 0 0\na 1 1\n", 4, "placed twice"),
    ("roles a b\nsample 0 0\na 0 0\nb 40 1\n", 4, "outside"),
    ("roles a b\nsample 0 0\na 0 0\nb 1 1\nsample 0 0\na 0 0\nb 1 1\n", 5, "repeats"),
    ("a 0 0\n", 1, "unknown"),
    ("roles a b\nmirror a c\n", 2, "'c'"),
    ("roles a b\nsymmetric maybe\n", 2, "maybe"),
    ("roles a b\nsample 0 nan\n", 2, "nan"),
    ("roles a a\n", 1, "duplicate"),
    ("# only a comment\n", 1, "roles"),
    ("roles a\na 0 0\n", 2, "before any"),
]


@pytest.mark.parametrize("text,line,needle", BAD)
def test_malformed_files_name_line_and_value(text, line, needle):
    with pytest.raises(FormationFileError) as err:
        parse(text, "bad.formation")
    msg = str(err.value)
    assert msg.startswith(f"bad.formation:{line}:"), msg
    assert needle in msg, msg
    assert err.value.line == line
    assert isinstance(err.value, ValueError)


def test_load_from_path(tmp_path):
    p = tmp_path / "x.formation"
    p.write_text(SMALL)
    assert Formation.load(p).name == "tiny"
    p.write_text("roles a\nsample 0 0\na 1 q\n")
    with pytest.raises(FormationFileError, match=r"x\.formation:3: .*'q'"):
        Formation.load(p)


# ------------------------------------------- the compiled lookup against scipy and numpy

_FLIP = np.array([1.0, -1.0])


def _numpy_positions_at(f: Formation, ball: np.ndarray) -> np.ndarray:
    """positions_at as scipy's find_simplex and numpy compute it (the compiled kernel's spec)."""
    ball = np.asarray(ball, dtype=float).reshape(2)
    if f.mirror is not None and ball[1] < 0:
        return _numpy_positions_at(f, ball * _FLIP)[np.array(f.mirror)] * _FLIP
    idx, w = f.weights(ball)
    if idx.size == 1:
        pos = f.positions[idx[0]].copy()
    else:
        pos = np.einsum("k,krd->rd", w / w.sum(), f.positions[idx])
        for j in idx.tolist():
            if tuple(f.balls[j].tolist()) == tuple(ball.tolist()):
                pos = f.positions[j].copy()
                break
    follow = np.array([r in f.follow for r in f.roles], dtype=bool)
    pos[follow] = ball
    lo, hi = field.field_box(f.margin)
    return np.minimum(np.maximum(pos, lo), hi)


def _probe_balls(f: Formation, rng: np.random.Generator, n: int) -> np.ndarray:
    """Random balls, the samples, points on and within 1e-15 and 1e-12 m of the triangles'
    edges and vertices (where find_simplex's tolerance and walk decide), outside the hull."""
    b = f.balls
    pts = [rng.uniform([-16, -11], [16, 11], size=(n, 2)), b, b * _FLIP, b + 1e-14]
    if f.triangulation is not None:
        s = f.triangulation.simplices
        for i, j in ((0, 1), (1, 2), (2, 0)):
            for u in (rng.uniform(0, 1), 0.5):
                e = b[s[:, i]] + u * (b[s[:, j]] - b[s[:, i]])
                pts += [e] + [e + rng.normal(size=e.shape) * scale for scale in (1e-15, 1e-12)]
    lo, hi = b.min(axis=0), b.max(axis=0)
    pts.append(np.array([[lo[0], 0.0], [hi[0] + 1e-14, 0.0], [0.0, lo[1] - 1e-14], [np.nan, 0.0],
                         [0.0, -0.0], [-0.0, -0.0]]))
    return np.concatenate(pts)


def _random_formation(rng: np.random.Generator, k: int) -> Formation:
    balls = rng.uniform([-14, -9], [14, 9], size=(int(rng.integers(1, 25)), 2))
    balls = np.unique(np.round(balls, k % 3), axis=0)  # grids: collinear and cocircular samples
    pos = rng.uniform([-14, -9], [14, 9], size=(len(balls), 3, 2))
    return Formation(("a", "b", "c"), balls, pos, follow=("b",) if k % 2 else (), margin=0.4 * (k % 3),
                     mirror=(1, 0, 2) if k % 3 == 0 else None)


def test_compiled_lookup_equals_scipy_and_numpy_bit_for_bit():
    rng = np.random.default_rng(7)
    formations = [Formation.load(p) for p in sorted(DATA.glob("*.formation"))]
    formations += [_random_formation(rng, k) for k in range(6)]
    formations.append(Formation(("a",), [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]], rng.normal(size=(3, 1, 2))))
    for f in formations:
        for ball in _probe_balls(f, rng, 300):
            want = _numpy_positions_at(f, ball)
            got = f.positions_at(ball)
            assert got.tobytes() == want.tobytes(), (f.name, ball.tolist())
            rows = np.array([len(f.roles) - 1, 0], dtype=np.int64)
            assert f.rows_at(rows, ball).tobytes() == want[rows].tobytes()

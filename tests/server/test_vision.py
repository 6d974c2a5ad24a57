"""The league's vision model: 120 deg cone, noise statistics, calibration error, lines."""

import math

import numpy as np
import pytest

from agent.posture import stand_pose
from models import field
from models.rules import VISION_SIGMA_HORIZONTAL, VISION_SIGMA_VERTICAL
from models.scene import Lineup
from server._kernels import camera_views
from server.vision import VisionSensor, in_cone, to_polar
from server.world import World
from tests.server.helpers import far_away, place_standing, standing_match


def true_polar(m, i, point):
    w = m.world
    cam = w.data.site_xpos[w.players[i].camera]
    rot = w.data.site_xmat[w.players[i].camera].reshape(3, 3)
    return to_polar((np.asarray(point) - cam) @ rot)


@pytest.fixture(scope="module")
def scene():
    m = standing_match()
    far_away(m)
    place_standing(m, 0, 0.0, 0.0, 0.0)  # L1 at the center spot looking at the right goal
    m.world.place_ball((3.0, 1.0))
    return m


def test_cone_decides_what_is_seen(scene):
    m = scene
    v = VisionSensor(m.world, np.random.default_rng(1)).see_all([0])[0]
    for name, pos in field.LANDMARKS.items():
        expected = bool(in_cone(true_polar(m, 0, pos)))
        assert (name in v.landmark_names) == expected, name
    assert set(v.landmark_names) == {"F1R", "F2R", "G1R", "G2R"}  # the goal ahead, not behind
    assert v.ball is not None
    assert not (v.player_unum == 1).any() or not v.player_ours.all()  # never sees itself


def test_noise_statistics_and_calibration(scene):
    m = scene
    sensor = VisionSensor(m.world, np.random.default_rng(7))
    sensor.calibration[:] = 0.0
    samples = np.array([sensor.see_all([0])[0].landmark("G1R") for _ in range(3000)])
    truth = true_polar(m, 0, field.LANDMARKS["G1R"])
    err = samples - truth
    assert np.allclose(err.mean(axis=0), 0.0, atol=4 * np.array([1e-3, 1e-4, 1e-4]))
    assert err[:, 1].std() == pytest.approx(VISION_SIGMA_HORIZONTAL, rel=0.08)
    assert err[:, 2].std() == pytest.approx(VISION_SIGMA_VERTICAL, rel=0.08)
    assert err[:, 0].std() == pytest.approx(truth[0] * 0.0965 / 100, rel=0.08)
    # A fixed calibration offset shifts every reading the same way (camera frame).
    sensor.calibration[0] = (0.005, -0.005, 0.005)
    shifted = np.array([sensor.see_all([0])[0].landmark("G1R") for _ in range(2000)]).mean(axis=0)
    cam = m.world.data.site_xpos[m.world.players[0].camera]
    rot = m.world.data.site_xmat[m.world.players[0].camera].reshape(3, 3)
    expected = to_polar((np.array(field.LANDMARKS["G1R"]) - cam) @ rot + sensor.calibration[0])
    assert np.allclose(shifted, expected, atol=[2e-3, 2e-4, 2e-4])


def test_other_players_parts_are_seen(scene):
    m = scene
    place_standing(m, 1, 4.0, 0.0, math.pi)  # R1 facing L1
    v = VisionSensor(m.world, np.random.default_rng(2)).see_all([0])[0]
    theirs = v.player_unum[~v.player_ours]
    assert (theirs == 1).sum() == 5  # head, both lower arms, both feet
    head = v.players[(~v.player_ours) & (v.player_part == 0)][0]
    truth = true_polar(m, 0, m.world.data.xpos[m.world.model.body("R1/head").id])
    assert head == pytest.approx(truth, abs=0.02)


def test_lines_are_clipped_to_the_cone(scene):
    v = VisionSensor(scene.world, np.random.default_rng(3)).see_all([0])[0]
    assert len(v.lines) > 3
    margin = math.radians(0.6)  # noise
    assert (np.abs(v.lines[..., 1]) <= math.radians(60) + margin).all()
    assert (np.abs(v.lines[..., 2]) <= math.radians(60) + margin).all()


def test_lines_are_clipped_at_the_cone_planes():
    """A camera at the origin looking along +x: a line across the view is cut where it
    leaves the pyramid, one behind the camera is dropped, one inside is kept whole."""
    a = np.array([[1.0, -5.0, 0.0], [-1.0, 0.0, 0.0], [2.0, 0.1, 0.0]])
    b = np.array([[1.0, 5.0, 0.0], [-2.0, 0.0, 0.0], [3.0, -0.1, 0.0]])
    points = np.stack([a, b], axis=1).reshape(-1, 3)
    _, _, _, _, lines, line_end, used = camera_views(
        points, 0, np.ones((1, 0), dtype=bool), np.zeros((1, 3)), np.eye(3)[None], np.zeros((1, 3)),
        math.tan(math.radians(60)), np.ones(18), 0, np.zeros(3),  # zero sigma: no noise
        np.ones(1, dtype=bool), np.ones(0, dtype=bool))
    assert line_end.tolist() == [2]  # the line behind the camera is not seen
    assert used == 12  # three draws per end point seen
    t = math.tan(math.radians(60))
    assert lines[0] == pytest.approx(to_polar(np.array([[1.0, -t, 0.0], [1.0, t, 0.0]])))
    assert lines[1] == pytest.approx(to_polar(np.stack([a[2], b[2]])))


def test_each_view_is_the_same_seen_alone_or_together():
    """Without noise, a player's view does not depend on who else is computed with it."""
    m = standing_match(left=(0, 1, 4), right=(2, 3))
    for i, (x, y, th) in enumerate([(0, 0, 0), (2, 0.5, 3.0), (-1, -1, 0.3), (3, 0, math.pi),
                                    (1, 1, -2.5)]):
        place_standing(m, i, x, y, th)
    m.world.place_ball((1.0, 0.2))
    sensor = VisionSensor(m.world, np.random.default_rng(4))
    sensor.sigma[:] = 0.0
    together = sensor.see_all()
    assert sorted(together) == [0, 1, 2, 3, 4]
    assert sensor.see_all([]) == {}
    for i in range(5):
        alone = sensor.see_all([i])[i]
        v = together[i]
        assert alone.landmark_names == v.landmark_names
        assert (alone.ball is None) == (v.ball is None)
        for f in ("landmarks", "lines", "players", "player_ours", "player_unum", "player_part"):
            assert np.allclose(getattr(alone, f), getattr(v, f), atol=1e-12), f
        mine = (v.player_unum == m.world.unum_of[i]) & (v.player_ours)
        assert not mine.any()  # never itself
        others = [j for j in range(5) if j != i]
        assert set(v.player_unum[v.player_part == 0]) <= {int(m.world.unum_of[j]) for j in others}
    assert sum(len(v.players) for v in together.values()) > 0


def test_single_robot_sees_the_field():
    w = World(Lineup((0,), ()))  # a training world: one robot, nobody else to see
    w.place_robot(0, 0.0, 0.0, 0.0, joints=stand_pose(0))
    v = VisionSensor(w, np.random.default_rng(0)).see_all()[0]
    assert set(v.landmark_names) == {"F1R", "F2R", "G1R", "G2R"} and len(v.players) == 0

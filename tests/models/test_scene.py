"""Scenes compose any legal line-up, with meaningful and cheap collisions."""

import mujoco
import numpy as np
import pytest

from models import field, scene
from models.scene import Lineup


def test_lineup_bounds():
    with pytest.raises(ValueError, match="at least one player"):
        Lineup((), ())
    with pytest.raises(ValueError, match="1 to 11"):
        Lineup((0,) * 12, (0,))
    with pytest.raises(ValueError, match="unknown robot type"):
        Lineup((5,), (0,))


@pytest.mark.parametrize("left,right", [((0,), (4,)), ((0, 1, 2), (3, 4)),
                                        (Lineup.default().left, Lineup.default().right)])
def test_scene_builds_with_every_player(left, right):
    lu = Lineup(tuple(left), tuple(right))
    m = mujoco.MjModel.from_xml_string(scene.scene_mjcf(lu))
    for side, unum, _ in lu.players():
        m.body(f"{side}{unum}/torso")
    assert m.geom("ball").size[0] == pytest.approx(field.BALL_RADIUS)
    assert m.body_mass[m.body("ball").id] == pytest.approx(field.BALL_MASS)


def test_collision_filter():
    """Robots touch the floor, the ball, goals and each other, never themselves."""
    m = mujoco.MjModel.from_xml_string(scene.scene_mjcf(Lineup((0, 0), (0,))))

    def collide(a, b):
        ga, gb = m.geom(a).id, m.geom(b).id
        return bool((m.geom_contype[ga] & m.geom_conaffinity[gb]) or
                    (m.geom_contype[gb] & m.geom_conaffinity[ga]))

    assert collide("L1/lfoot", "floor")
    assert collide("L1/lfoot", "ball")
    assert collide("L1/lfoot", "L2/rfoot")
    assert collide("L1/torso", "R1/head")
    assert collide("ball", "floor")
    assert collide("ball", "G1R")
    assert not collide("L1/lfoot", "L1/rfoot")
    assert not collide("L1/lowerarm".replace("lowerarm", "llowerarm"), "L1/torso")
    # Lines and flags are pictures, not obstacles.
    assert not collide("line0", "ball")


def test_field_dimensions():
    lines = field.FIELD_LINES
    assert np.isclose(np.abs(lines[..., 0]).max(), 15.0)
    assert np.isclose(np.abs(lines[..., 1]).max(), 10.0)
    assert field.LANDMARKS["G1R"] == (15.0, 1.05, 0.8)


def test_colliding_field_geoms_have_bodies_of_their_own():
    """The floor and goal frames sit in static bodies of their own (cheaper
    collisions than one many-geom world body), and still collide as before."""
    m = mujoco.MjModel.from_xml_string(scene.scene_mjcf(Lineup((0,), (0,))))
    world_geoms = range(m.body_geomadr[0], m.body_geomadr[0] + m.body_geomnum[0])
    assert m.body_geomnum[0] > 0 and not any(m.geom_contype[g] for g in world_geoms)
    for name in ("floor", "G1L", "goalR_back"):
        b = m.geom(name).bodyid[0]
        assert b != 0 and m.body_geomnum[b] == 1 and m.body_weldid[b] == 0
        assert m.geom_contype[m.geom(name).id]

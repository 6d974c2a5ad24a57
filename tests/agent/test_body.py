"""The villa player on the ball, in physics: from a few steps away it lines up, hands
over to the kicker and sends the ball toward its goal, seeing only its percepts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from agent.player import Player
from agent.posture import PostureAgent
from agent.requests import Dribble, Kick
from models.rules import PlayMode
from models.scene import Lineup
from server.match import Match


def place(m: Match, i: int, x: float, y: float, heading: float) -> None:
    """Trainer: stand player i at (x, y) (field frame) in its current joint pose."""
    w = m.world
    w.place_robot(i, x, y, heading, joints=w.joint_angles(i))
    w.settle_height(i)
    agent = m.agents[i]
    agent.world.beamed(x, y, heading)  # as after a beam: it knows where it stands
    agent.body.beamed()


@pytest.mark.parametrize("seed", [0, 1])
def test_on_ball_player_moves_the_ball_toward_the_goal(seed):
    m = Match(Player, PostureAgent, Lineup((0, seed), (0,)), half_time=300, seed=seed)
    for _ in range(60):  # beams and the first settling
        m.step()
    w = m.world
    i = w.player("L", 2)
    ball = np.array([4.0, 1.0])
    place(m, i, 2.6, 0.2, 0.3)
    w.place_robot(w.player("R", 1), 14.5, 9.0, math.pi)  # their goalie out of the way
    w.place_ball(tuple(ball))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    agent = m.agents[i]
    asked = set()
    for _ in range(round(35.0 / 0.02)):
        m.step()
        asked.add(type(agent.request))
        if np.hypot(*(w.ball_position()[:2] - ball)) > 2.0:
            break
    moved = w.ball_position()[:2] - ball
    assert asked & {Kick, Dribble}
    assert np.hypot(*moved) > 2.0, f"the ball moved only {np.hypot(*moved):.2f} m"
    assert moved[0] > 1.0  # toward the opponents' goal (+x for the left team)
    assert m.referee.falls["L"] == 0

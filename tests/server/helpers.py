"""Small worlds for server tests."""

from __future__ import annotations

import numpy as np

from agent.posture import PostureAgent, stand_pose
from models.rules import PlayMode
from models.scene import Lineup
from server.match import Match


def standing_match(left=(0,), right=(0,), seed=0, half_time=300.0) -> Match:
    """A posture-agent match past its kickoff, in PlayOn, every robot standing where beamed."""
    m = Match(PostureAgent, PostureAgent, Lineup(tuple(left), tuple(right)), half_time=half_time,
              seed=seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    return m


def place_standing(m: Match, i: int, x: float, y: float, heading: float) -> None:
    """Trainer: put player i in the stand pose at (x, y, heading), world frame."""
    t = m.world.players[i].robot_type
    m.world.place_robot(i, x, y, heading, joints=stand_pose(t))
    m.world.settle_height(i)


def run(m: Match, seconds: float) -> None:
    for _ in range(int(round(seconds / 0.02))):
        m.step()


def far_away(m: Match) -> None:
    """Park every robot off the field so that the ball moves freely."""
    for i, p in enumerate(m.world.players):
        place_standing(m, i, -12.0 + 2.0 * i, -10.8 if p.side == "L" else 10.8, 0.0)


__all__ = ["standing_match", "place_standing", "run", "far_away", "np"]

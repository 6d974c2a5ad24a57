"""Small physics worlds for the agent's perception tests (ground truth from server.World)."""

from __future__ import annotations

import math

import numpy as np

from agent.perceiving import PerceivingAgent
from models.rules import PlayMode
from models.scene import Lineup
from server.match import Match
from tests.server.helpers import place_standing, run  # noqa: F401  (shared with the server tests)


def perceiving_match(left=(0,), right=(0,), seed=0, **agent_kwargs) -> Match:
    """A match of perceiving agents, run past its kickoff and set to PlayOn."""
    def factory(side: str, unum: int, robot_type: int, s: int) -> PerceivingAgent:
        return PerceivingAgent(side, unum, robot_type, s, **agent_kwargs)
    m = Match(factory, factory, Lineup(tuple(left), tuple(right)), half_time=300.0, seed=seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    return m


def true_pose_team(m: Match, i: int) -> np.ndarray:
    """Player i's torso (x, y, heading) in its own team frame."""
    x, y, h = m.world.player_pose(i)
    if m.world.players[i].side == "R":
        x, y, h = -x, -y, h + math.pi
    return np.array([x, y, math.remainder(h, 2 * math.pi)])


def pose_error(m: Match, i: int) -> tuple[float, float]:
    """(position error m, heading error rad) of player i's world model."""
    est = m.agents[i].world.pose
    true = true_pose_team(m, i)
    return float(np.hypot(*(est[:2] - true[:2]))), abs(math.remainder(est[2] - true[2], 2 * math.pi))

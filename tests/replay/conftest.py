"""A short recorded 3 v 3 match with known poses, shared by the replay tests.

Posture agents stand still, so the trainer moves things between cycles: the ball
rolls, L2 is put at a known place and heading, R3 is laid face down (fallen),
and the left team annotates role targets. `truth` holds the exact torso poses
computed from the float64 state at every cycle.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
import pytest

from agent.posture import PostureAgent
from models.messages import Action, Percept
from models.scene import Lineup
from server.log import MatchLog, write_log
from server.match import Match

CYCLES = 250
MOVE_AT = 120  # cycle at which the trainer moves L2 and lays R3 down
L2_POSE = (-3.0, 4.0, 1.0)  # x, y (m), heading (rad)
R3_PLACE = (4.0, -5.0)


def target_of(unum: int) -> tuple[float, float]:
    """The role target (field frame, m) the test agents of the left team annotate."""
    return (-8.0 + 2.0 * unum, -2.0)


class TargetAgent(PostureAgent):
    """A posture agent that also annotates a fixed role target for the match log."""

    def act(self, percept: Percept) -> Action:
        a = super().act(percept)
        a.annotations = {"target": target_of(self.unum)}
        return a


@dataclass
class Recorded:
    log: MatchLog
    path: object  # pathlib.Path of the written log
    torso_xpos: np.ndarray  # (T, n, 3) exact torso centers per frame (m)
    torso_xmat: np.ndarray  # (T, n, 9)


@pytest.fixture(scope="session")
def recorded(tmp_path_factory) -> Recorded:
    m = Match(TargetAgent, PostureAgent, Lineup.default(3, 3), half_time=10.0, seed=7, record=True)
    w = m.world
    probe = mujoco.MjData(w.model)
    xpos, xmat = [], []
    for c in range(CYCLES):
        if c == 60:
            w.place_ball((1.0, -2.0), velocity=(0.0, 0.0, 0.0))
            w.set_ball_velocity((1.5, 0.8, 0.0))
        if c == MOVE_AT:
            w.place_robot(w.player("L", 2), *L2_POSE)
            w.place_robot(w.player("R", 3), *R3_PLACE, heading=0.5, lying="front")
        m.step()
        probe.qpos[:] = w.data.qpos
        mujoco.mj_kinematics(w.model, probe)
        xpos.append(probe.xpos[w.torso_ids].copy())
        xmat.append(probe.xmat[w.torso_ids].copy())
    log = m.match_log()
    path = tmp_path_factory.mktemp("replay") / "match.npz"
    write_log(log, path)
    return Recorded(log, path, np.array(xpos), np.array(xmat))

"""A villa player is blind to which side it plays on: given the percepts an L player
received in a match, turned into what an R player in the mirrored match would receive,
an R player with the same seed answers with exactly the same actions.

The mirrored match is the field turned 180 deg about its center (a rotation, so the
physics is the same): flags and posts swap names (F1L <-> F2R, G1L <-> G2R, ...),
modes swap sides and so do the scores; every relative measurement stays as it is.
"""

from __future__ import annotations

import copy

import numpy as np
import pytest

from agent.player import Player
from agent.strategy import FIELD_ROLES, GOALIE
from models.messages import Percept
from models.scene import Lineup
from server.match import Match

TURNED = {"F1L": "F2R", "F2L": "F1R", "F1R": "F2L", "F2R": "F1L",
          "G1L": "G2R", "G2L": "G1R", "G1R": "G2L", "G2R": "G1L"}
CYCLES = 900  # 18 s: beams, kickoff, the first touches and kicks, messages every cycle


def turned_mode(mode: str) -> str:
    for a, b in (("_Left", "_Right"), ("_left", "_right")):
        if mode.endswith(a):
            return mode[: -len(a)] + b
        if mode.endswith(b):
            return mode[: -len(b)] + a
    return mode


def turned(p: Percept) -> Percept:
    q = copy.deepcopy(p)
    q.side = "R" if p.side == "L" else "L"
    q.play_mode = turned_mode(p.play_mode)
    q.score_left, q.score_right = p.score_right, p.score_left
    if q.vision is not None:
        q.vision.landmark_names = tuple(TURNED[n] for n in p.vision.landmark_names)
    return q


@pytest.fixture(scope="module")
def recorded():
    """Percepts and actions of every left player in a seeded 5 v 5 villa match."""
    log: dict[tuple, tuple[list, list]] = {}

    class Recorder:
        def __init__(self, side, unum, robot_type, seed):
            self.player = Player(side, unum, robot_type, seed)
            self.key = (unum, robot_type, seed)
            if side == "L":
                log[self.key] = ([], [])

        def act(self, percept):
            action = self.player.act(percept)
            if self.key in log and self.player.side == "L":
                log[self.key][0].append(copy.deepcopy(percept))
                log[self.key][1].append(copy.deepcopy(action))
            return action

    m = Match(Recorder, Recorder, Lineup.default(5, 5), half_time=300.0, seed=3)
    m.run(max_cycles=CYCLES)
    assert m.referee.touches["L"] + m.referee.touches["R"] > 0  # the ball was played
    return log


def test_a_right_player_answers_a_turned_match_as_the_left_player_did(recorded):
    # The left team kicks off first; players who stand elsewhere at the other team's kickoff
    # (the taker, and the supporter who steps back from the taker's spot) are not mirrored.
    moved = {u for u in range(2, 6)
             if Player("L", u, 0).kickoff_position(True) != Player("L", u, 0).kickoff_position(False)}
    roles = {u: FIELD_ROLES[(u - 2) % len(FIELD_ROLES)] for u in range(2, 6)}
    assert moved == {u for u, r in roles.items() if r in ("onBall", "supporter")}
    checked = 0
    for (unum, robot_type, seed), (percepts, actions) in recorded.items():
        if unum in moved:
            continue
        right = Player("R", unum, robot_type, seed)
        for k, (p, a) in enumerate(zip(percepts, actions)):
            b = right.act(turned(p))
            assert np.array_equal(a.joint_velocities, b.joint_velocities), (unum, k, p.play_mode)
            assert (a.say, a.beam) == (b.say, b.beam), (unum, k, p.play_mode)
        checked += 1
    assert checked == 5 - len(moved) and GOALIE == 1

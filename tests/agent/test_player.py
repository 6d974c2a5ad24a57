"""A villa player's decisions on hand-made snapshots (no physics): kickoff positions,
what the on-ball player asks for, the goalie, and keeping away at their restarts."""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import pytest

from agent import strategy as st
from agent.player import Player
from agent.requests import Dive, Dribble, Kick, WalkTo
from agent.teamconfig import TeamConfig, variant
from models import field as fld
from models.rules import PlayMode


@functools.cache
def player(unum: int) -> Player:
    return Player("L", unum, 0, seed=unum)


@pytest.fixture(scope="module")
def players():
    return {u: player(u) for u in (1, 6)}


def view(unum, me, ball, mates=(), opponents=(), mode=PlayMode.PLAY_ON, ours=None, velocity=(0.0, 0.0)):
    opp = np.array(opponents, dtype=float).reshape(-1, 2)
    return st.TeamView(unum=unum, time=10.0, mode=mode, ours=ours, pose=me, fallen=False,
                       ball=np.array(ball, dtype=float), ball_velocity=np.array(velocity, dtype=float),
                       mates=tuple(mates), opponents=opp, opponents_fallen=np.zeros(len(opp), dtype=bool))


@pytest.mark.parametrize("unum", range(1, 12))
@pytest.mark.parametrize("ours", [True, False])
def test_kickoff_positions_are_legal(unum, ours):
    x, y, h = player(unum).kickoff_position(ours)
    assert x < 0 and abs(y) < fld.HALF_WIDTH
    taker = ours and st.FIELD_ROLES[(unum - 2) % 10] == "onBall" and unum != 1
    if not taker:
        assert math.hypot(x, y) > fld.CENTER_CIRCLE_RADIUS
    if unum != 1:  # field players face the center spot
        assert math.cos(h - math.atan2(-y, -x)) > 0.99


@pytest.mark.parametrize("ours", [True, False])
def test_kickoff_positions_are_apart(ours):
    xy = np.array([player(u).kickoff_position(ours)[:2] for u in range(1, 12)])
    gaps = np.hypot(*(xy[:, None] - xy[None]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    assert gaps.min() >= st.KICKOFF_SPACING - 1e-9  # no two players beamed onto one spot


def test_villa_dribbles_in_play_and_kicks_its_kickoff():
    assert isinstance(Player("L", 2, 0).decide(view(2, (-1.0, 0.0, 0.0), (0.0, 0.0))), Dribble)
    assert isinstance(Player("L", 2, 0).decide(view(2, (9.0, 0.0, 0.0), (10.0, 0.0))), Dribble)
    kickoff = view(2, (-0.3, 0.0, 0.0), (0.0, 0.0), mode=PlayMode.KICK_OFF_LEFT, ours=True)
    assert isinstance(Player("L", 2, 0).decide(kickoff), Kick)


@pytest.mark.parametrize("kickoff", ["pass", "walkup", "deep"])
def test_kickoff_taker_stands_where_its_kick_needs(kickoff):
    """The pass kicked from where the taker is beamed; walkup and deep walk up from farther."""
    config = TeamConfig(kickoff=kickoff)
    taker = next(u for u in range(2, 12) if st.FIELD_ROLES[(u - 2) % 10] == "onBall")
    p = Player("L", taker, 0, config=config)
    spot = st.KICKOFF_TAKER if kickoff == "pass" else st.KICKOFF_TAKER_BACK
    assert np.allclose(p.kickoff_position(True)[:2], spot)
    req = p.decide(view(taker, (*spot, 0.0), (0.0, 0.0), opponents=[(1.0, 2.0)],
                        mode=PlayMode.KICK_OFF_LEFT, ours=True))
    assert isinstance(req, Kick)
    if kickoff == "deep":
        assert req.target[0] > 10.0
    else:  # the 44 deg pass to the side away from the opponent
        assert req.target[1] < 0 and math.isclose(math.hypot(*req.target), 3.0)
        assert math.isclose(math.atan2(-req.target[1], req.target[0]), math.radians(44.0))


def test_on_ball_player_kicks_when_free_and_dribbles_when_pressed():
    p = Player("L", 2, 0, config=variant("Kicks"))
    free = p.decide(view(2, (-1.0, 0.0, 0.0), (0.0, 0.0)))
    assert isinstance(free, Kick) and free.kicks
    dists = {round(p.body.kicks[n].spec.distance, 1) for n in free.kicks}
    reach = math.hypot(free.target[0], free.target[1])
    assert all(abs(d - reach) < 0.2 for d in dists)  # kicks of the distance to the target
    pressed = Player("L", 2, 0, config=variant("Kicks")).decide(
        view(2, (-1.0, 0.0, 0.0), (0.0, 0.0), opponents=[(1.0, 0.5)]))
    assert isinstance(pressed, Dribble)


def test_shots_only_dribbles_where_the_team_would_pass_and_shoots_where_it_would_shoot():
    shots_only = variant("ShotsOnly")
    far = view(2, (-1.0, 0.0, 0.0), (0.0, 0.0))  # free, the goal out of reach: villa passes
    assert isinstance(Player("L", 2, 0, config=variant("Kicks")).decide(far), Kick)
    assert isinstance(Player("L", 2, 0, config=shots_only).decide(far), Dribble)
    near = view(2, (9.0, 0.0, 0.0), (10.0, 0.0))
    req = Player("L", 2, 0, config=shots_only).decide(near)
    assert isinstance(req, Kick) and req.target[0] > fld.HALF_LENGTH


def test_dribble_cone_held_turns_only_for_a_possession_that_starts_as_a_race():
    beside = dict(unum=2, me=(-3.0, -1.5, 0.0), ball=(-3.0, 0.0))  # 1.5 m from the ball, from the side
    goal_line = st.dribble_target(view(**beside), 0.0)
    held = variant("DribbleConeHeld")
    free_first = Player("L", 2, 0, config=held)
    free = free_first.decide(view(**beside, opponents=[(-3.0, 1.6)]))  # 1.6 m from the ball: no race
    raced = Player("L", 2, 0, config=held).decide(view(**beside, opponents=[(-3.0, 1.4)]))
    always = Player("L", 2, 0, config=variant("DribbleCone")).decide(view(**beside, opponents=[(-3.0, 1.6)]))
    assert isinstance(free, Dribble) and isinstance(raced, Dribble)
    assert np.allclose(free.target, goal_line)  # free: straight at the goal
    for turned in (raced.target, always.target):  # toward +y, the side the player comes along
        assert turned[1] > 0.5 and math.hypot(turned[0] + 3.0, turned[1]) < 2.5
    later = dataclasses.replace(view(**beside, opponents=[(-3.0, 1.4)]), time=12.0)
    assert np.allclose(free_first.decide(later).target, goal_line)  # held for the possession


def test_a_shot_in_reach_uses_kicks_that_reach_the_goal():
    p = Player("L", 2, 0, config=variant("Kicks"))
    req = p.decide(view(2, (9.0, 0.0, 0.0), (10.0, 0.0)))
    assert isinstance(req, Kick) and req.target[0] > fld.HALF_LENGTH
    assert all(p.body.kicks[n].spec.distance >= 5.4 for n in req.kicks)


def test_others_walk_to_formation_spots_and_keep_away_at_their_restarts(players):
    p = players[6]
    onball = st.Mate(2, 3.0, -0.5, 0.0)
    req = p.decide(view(6, (-4.0, 3.0, 0.0), (1.5, 0.0), mates=[onball]))
    assert isinstance(req, WalkTo)
    req = p.decide(view(6, (1.5, 4.0, 0.0), (1.5, 0.0), mates=[onball], mode=PlayMode.KICK_IN_RIGHT,
                        ours=False))
    assert isinstance(req, WalkTo) and math.hypot(req.x - 1.5, req.y) >= st.KEEP_AWAY - 1e-6


def test_goalie_dives_at_a_shot_and_otherwise_guards_the_line(players):
    g = players[1]
    me = (st.GOALIE_LINE, 0.0, 0.0)
    req = g.decide(view(1, me, (-11.0, 0.0), velocity=(-4.0, 0.5)))
    assert isinstance(req, Dive) and req.name in ("DIVE_LEFT", "DIVE_CENTER")
    req = g.decide(view(1, me, (-5.0, 3.0)))
    assert isinstance(req, WalkTo) and req.x == pytest.approx(st.GOALIE_LINE) and 0 < req.y < 1.0

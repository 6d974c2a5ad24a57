"""Referee decisions on goals, balls out of play and restarts (trainer-moved balls)."""

import math

import numpy as np
import pytest

from agent.player import Player
from agent.posture import PostureAgent
from models import field
from models.rules import FREE_KICK_DISTANCE, PlayMode
from models.scene import Lineup
from server._kernels import fallen_rules
from server.match import Match
from server.referee import DOWN_UP_Z, STANDING_UP_Z
from tests.server.helpers import far_away, place_standing, run, standing_match


def kinds(m):
    return [e.kind for e in m.referee.events]


@pytest.mark.parametrize("direction,scorer,kickoff", [(1, "L", PlayMode.KICK_OFF_RIGHT),
                                                      (-1, "R", PlayMode.KICK_OFF_LEFT)])
def test_goal_and_kickoff_to_the_team_that_conceded(direction, scorer, kickoff):
    m = standing_match()
    far_away(m)
    m.world.place_ball((direction * 13.0, 0.2))
    m.world.set_ball_velocity((direction * 6.0, 0.0, 0.0))
    run(m, 3.0)
    ref = m.referee
    assert ref.score[scorer] == 1 and ref.score["RL".replace(scorer, "")] == 0
    goal = [e for e in ref.events if e.kind == "goal"]
    assert len(goal) == 1 and goal[0].team == scorer
    assert ref.mode == (PlayMode.GOAL_LEFT if scorer == "L" else PlayMode.GOAL_RIGHT)
    run(m, 3.1)
    assert ref.mode == kickoff
    assert abs(m.world.ball_position()[:2]).max() < 1e-6


def test_shot_over_the_bar_is_no_goal():
    m = standing_match()
    far_away(m)
    m.world.place_ball((14.0, 0.0), z=1.2)
    m.world.set_ball_velocity((5.0, 0.0, 1.0))
    run(m, 1.5)
    assert m.referee.score == {"L": 0, "R": 0}
    assert m.referee.mode == PlayMode.GOAL_KICK_RIGHT


def test_kickoff_goal_needs_a_second_touch():
    m = standing_match()
    far_away(m)
    m.referee.kickoff_pending = True  # as right after a kickoff, nobody touched yet
    m.world.place_ball((13.0, 0.0))
    m.world.set_ball_velocity((6.0, 0.0, 0.0))
    run(m, 2.0)
    assert m.referee.score == {"L": 0, "R": 0}
    assert "no_goal" in kinds(m)
    assert m.referee.mode == PlayMode.GOAL_KICK_RIGHT


def touch_ball(m, i, x, y):
    """Trainer: stand player i at (x, y) facing +x and lay the ball against its left foot."""
    place_standing(m, i, x, y, 0.0)
    foot = m.world.data.xpos[m.world.model.body(f"{m.world.players[i].name}/lfoot").id]
    m.world.place_ball((foot[0] + 0.08 + 0.02, foot[1]))  # the sole is thin: overlap a little
    run(m, 0.1)
    assert m.referee.last_touch == i


@pytest.mark.parametrize("y", [9.0, -9.0])
def test_side_line_gives_kick_in_to_the_other_team(y):
    m = standing_match()
    far_away(m)
    touch_ball(m, 0, 0.0, 0.0)  # L1 touches last
    place_standing(m, 0, -5.0, -10.8, 0.0)
    m.world.place_ball((3.0, y))
    m.world.set_ball_velocity((0.0, math.copysign(4.0, y), 0.0))
    run(m, 1.0)
    assert m.referee.mode == PlayMode.KICK_IN_RIGHT
    bx, by, _ = m.world.ball_position()
    assert by == pytest.approx(math.copysign(10.0, y), abs=0.02)
    assert bx == pytest.approx(3.0, abs=0.05)  # where it crossed the line


def test_end_line_after_attacker_gives_goal_kick():
    m = standing_match()
    far_away(m)
    touch_ball(m, 0, 0.0, 0.0)  # L1, attacking +x, touches last
    place_standing(m, 0, -5.0, -10.8, 0.0)
    m.world.place_ball((13.5, 5.0))
    m.world.set_ball_velocity((5.0, 0.0, 0.0))
    run(m, 1.0)
    assert m.referee.mode == PlayMode.GOAL_KICK_RIGHT
    bx, by, _ = m.world.ball_position()
    assert (bx, by) == pytest.approx((14.0, 0.0), abs=0.02)


def test_end_line_after_defender_gives_corner_kick():
    m = standing_match()
    far_away(m)
    touch_ball(m, 1, 0.0, 0.0)  # R1, defending +x, touches last
    place_standing(m, 1, 5.0, 10.8, 0.0)
    m.world.place_ball((13.5, -5.0))
    m.world.set_ball_velocity((5.0, 0.0, 0.0))
    run(m, 1.0)
    assert m.referee.mode == PlayMode.CORNER_KICK_LEFT
    bx, by, _ = m.world.ball_position()
    assert (bx, by) == pytest.approx((15.0, -10.0), abs=0.05)


def test_opponents_kept_away_at_a_kick_in():
    m = standing_match()
    far_away(m)
    touch_ball(m, 0, 0.0, 0.0)
    place_standing(m, 1, 3.2, 9.0, math.pi)  # R1 waits near where the ball goes out
    place_standing(m, 0, -5.0, -10.8, 0.0)
    m.world.place_ball((3.0, 9.5))
    m.world.set_ball_velocity((0.0, 3.0, 0.0))
    run(m, 1.0)
    # L1 touched last, so the kick-in is R's: R1 may stay. Now the other way round.
    assert m.referee.mode == PlayMode.KICK_IN_RIGHT
    m.referee.set_play_mode(PlayMode.KICK_IN_LEFT)
    run(m, 0.1)
    d = math.dist(m.world.torso_positions()[1, :2], m.world.ball_position()[:2])
    assert d >= FREE_KICK_DISTANCE
    assert "reposition" in kinds(m)


def test_ball_dropped_after_15_s_without_a_touch():
    m = standing_match()
    far_away(m)
    m.referee.set_play_mode(PlayMode.KICK_IN_LEFT)
    run(m, 15.1)
    assert m.referee.mode == PlayMode.PLAY_ON
    assert "drop_ball" in kinds(m)


def test_fourth_defender_in_the_penalty_area_is_moved_out():
    m = standing_match(left=(0, 0, 0, 0, 0), right=(0,))
    far_away(m)
    for i, y in enumerate([0.0, 1.0, -1.0, 0.5]):
        place_standing(m, i, -14.0 + 0.3 * i, y, 0.0)
    run(m, 0.1)
    place_standing(m, 4, -14.2, -0.6, 0.0)  # the fifth: one too many
    run(m, 0.1)
    events = [e for e in m.referee.events if e.kind == "illegal_defense"]
    assert events and events[0].player == 5
    assert m.world.torso_positions()[4, 0] > -15.0 + field.PENALTY_DEPTH


def test_half_time_and_game_over():
    m = standing_match(half_time=2.0)
    far_away(m)
    run(m, 2.1)
    assert "half_time" in kinds(m)
    while m.referee.mode != PlayMode.GAME_OVER:
        m.step()
    assert m.referee.game_time == pytest.approx(4.0, abs=0.03)
    kickoffs = [e.detail for e in m.referee.events if e.detail.startswith("KickOff")]
    assert kickoffs[-1].startswith("KickOff_Right")


def test_beam_only_before_kickoff():
    m = standing_match()
    assert not m.referee.beam_allowed()
    m.referee.set_play_mode(PlayMode.BEFORE_KICK_OFF)
    assert m.referee.beam_allowed()


def test_player_down_too_long_is_repositioned():
    m = standing_match(left=(0, 0), right=(0,))
    far_away(m)
    m.world.place_robot(1, -3.0, 2.0, 0.0, lying="back")  # L2 lies on its back
    run(m, 14.0)
    assert not [e for e in m.referee.events if e.kind == "reposition" and e.player == 2]
    assert m.referee.falls["L"] == 1
    run(m, 1.5)
    moved = [e for e in m.referee.events if e.kind == "reposition" and e.player == 2]
    assert moved and "too long" in moved[0].detail
    assert m.world.torso_up()[1] > 0.9  # put back on its feet, off the side line
    assert abs(m.world.torso_positions()[1, 1]) > 10.0


def _count_falls(tilts_heights):
    """New falls the referee's bookkeeping counts for one torso going through
    (up-axis z, height in m) states, standing height 0.4 m."""
    xpos, xmat = np.zeros((1, 3)), np.zeros((1, 9))
    fallen, nan = np.zeros(1, dtype=bool), np.full(1, np.nan)
    down_since, unsteady_since = nan.copy(), nan.copy()
    new, late = np.empty(1, dtype=np.int64), np.empty(1, dtype=np.int64)
    count = 0
    for k, (up, z) in enumerate(tilts_heights):
        xmat[0, 8], xpos[0, 2] = up, z
        nf, _ = fallen_rules(xpos, xmat, np.zeros(1, dtype=np.int64), np.full(1, 0.24), fallen, down_since,
                             unsteady_since, np.full(1, 1e9), np.full(1, 1e9), 0.02 * k,
                             (DOWN_UP_Z, STANDING_UP_Z), new, late)
        count += nf
    return count


def test_a_getup_that_leans_into_its_stand_is_one_fall():
    lying, sitting_up, leaning_in, standing = (0.0, 0.1), (0.9, 0.15), (0.46, 0.2), (1.0, 0.4)
    assert _count_falls([standing, lying, sitting_up, leaning_in, standing]) == 1
    assert _count_falls([standing, lying, sitting_up, leaning_in, standing, lying, standing]) == 2
    assert _count_falls([standing, (0.6, 0.4), standing]) == 0  # a stumble that never lies


def test_a_real_getup_from_the_back_counts_one_fall():
    """Type 2's getup from the back sits up, then leans its torso to 0.46 of vertical as
    it rises: one fall, not two."""
    m = Match(Player, PostureAgent, Lineup((2,), (0,)), half_time=300, seed=1)
    run(m, 1.2)
    m.world.place_robot(1, 14.5, 9.0, math.pi)
    m.world.place_robot(0, -3.0, 0.0, 0.0, lying="back")
    m.agents[0].world.beamed(-3.0, 0.0, 0.0)
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    run(m, 8.0)
    assert m.world.torso_up()[0] > 0.9  # up again
    assert m.referee.falls["L"] == 1


def test_a_dropped_kickoff_ball_may_be_scored_by_anyone():
    m = standing_match()
    far_away(m)
    m.referee.set_play_mode(PlayMode.KICK_OFF_RIGHT)  # the right team's kickoff, never taken
    m.referee.kickoff_pending = True
    run(m, 15.1)
    assert m.referee.mode == PlayMode.PLAY_ON and "drop_ball" in kinds(m)
    m.world.place_ball((13.0, 0.0))
    m.world.set_ball_velocity((6.0, 0.0, 0.0))
    run(m, 2.0)
    assert m.referee.score["L"] == 1 and "no_goal" not in kinds(m)


def test_territory_is_the_balls_mean_x_in_play_toward_each_teams_attacking_goal():
    m = standing_match()
    far_away(m)
    m.world.place_ball((4.0, 2.0))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    run(m, 1.0)
    m.world.place_ball((-2.0, 2.0))
    run(m, 3.0)  # 1 s at x = 4, then 3 s at x = -2: mean -0.5
    assert m.referee.play_on_time == pytest.approx(4.0, abs=0.03)
    assert m.referee.territory("L") == pytest.approx(-0.5, abs=0.05)
    assert m.referee.territory("R") == -m.referee.territory("L")
    stats = m.result(1.0).stats
    assert stats["L"]["territory"] == pytest.approx(-0.5, abs=0.05)

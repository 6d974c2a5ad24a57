"""A team chooses its robot types (as a league agent names its type when it joins): the
match and the batch play them, and refuse a full team that breaks the league's rule."""

import numpy as np
import pytest

from agent.posture import PostureAgent
from agent.teamconfig import TeamConfig
from agent.variants import VillaFactory
from cli.teams import factory as resolve
from models.scene import Lineup
from optimization.executor import InlineExecutor
from server.batch import BatchSettings, run_batch
from server.match import Match, lineup_for, team_types
from tests.batch_teams import all_toes, toes_first

CHOSEN = (0, 3, 0, 0, 3, 0, 0, 2, 2, 3, 0)


def test_a_match_plays_the_types_each_team_chooses():
    villa = VillaFactory(TeamConfig(robot_types=CHOSEN))
    m = Match(villa, PostureAgent, team_names=("chosen", "posture"))
    assert m.lineup == Lineup(CHOSEN, Lineup.default().right)
    assert [p.robot_type for p in m.world.players[:11]] == list(CHOSEN)
    assert [a.robot_type for a in m.agents[:11]] == list(CHOSEN)


def test_a_smaller_side_takes_its_first_uniform_numbers():
    assert lineup_for(toes_first, PostureAgent, 3, 2) == Lineup((4, 4, 3), (0, 1))
    numpy_types = VillaFactory(TeamConfig(robot_types=tuple(np.array(CHOSEN))))
    assert team_types(numpy_types, 11) == CHOSEN and all(type(t) is int for t in team_types(numpy_types, 11))


@pytest.mark.parametrize("types, words", [
    ((4,) * 11, "1 robot types; a full team needs at least 3"),
    ((0, 1, 2), "chooses 3 robot types for 11 players"),
    ((0, 1, 2, 3, 5, 0, 1, 2, 3, 4, 0), "robot type 5"),
    ((0, 1, 2, 3, True, 0, 1, 2, 3, 4, 0), "robot type True"),
])
def test_a_bad_choice_is_refused_naming_the_team(types, words):
    with pytest.raises(ValueError, match="team 'mine'") as err:
        team_types(VillaFactory(TeamConfig(robot_types=types)), 11, "mine")
    assert words in str(err.value)


def test_a_given_line_up_is_held_to_the_rule_too():
    with pytest.raises(ValueError, match=r"team 'right' plays robot types \[4, 4, 4, .*at most 7"):
        Match(PostureAgent, PostureAgent, Lineup(Lineup.default().left, (4,) * 8 + (0, 1, 2)))
    with pytest.raises(ValueError, match="at least 3"):
        Match(all_toes, PostureAgent)


def test_batch_rows_record_each_teams_types(tmp_path):
    settings = BatchSettings("tests.batch_teams:toes_first", "posture", half_time=0.2, seed=1,
                             home_size=2, away_size=3)
    rows = []
    run_batch(settings, 2, tmp_path, resolve, InlineExecutor, inflight=1, progress=None, on_row=rows.append)
    assert [r["a_side"] for r in sorted(rows, key=lambda r: r["game"])] == ["L", "R"]
    for r in rows:
        assert "error" not in r, r
        assert r["types"] == {"A": [4, 4], "B": [0, 1, 2]}


def test_villa_plays_mostly_type_0_and_in_turn_is_the_team_before():
    from agent.teamconfig import MOSTLY_TYPE_0
    in_turn = Lineup.default().right
    assert lineup_for(resolve("villa"), resolve("villa:InTurn"), 11, 11) == Lineup(MOSTLY_TYPE_0, in_turn)
    assert team_types(resolve("villa:NoSprint"), 11) == Lineup.default().left  # earlier teams as they were

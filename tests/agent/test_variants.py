"""The villa variants ("Positioning to Win" section 6): the NearestStopper and PathCost
options of the role assignment against brute force, the formations, the names, and
every variant playing a moment of a tiny match."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from agent import strategy as st
from agent.teamconfig import PAPER_TABLE2, VARIANTS, VILLA, TeamConfig, UnknownVariant, variant, variant_name
from cli import teams
from formations.delaunay import Formation
from formations.variants import MAKERS
from models.rules import PlayMode, robot_types_problem
from tests.agent.test_strategy import view

STOPPER = st.FIELD_ROLES.index("supporter")


def _brute(cost: np.ndarray) -> tuple[float, float]:
    """The least (max, sum of squares) of cost (n, n) over every permutation."""
    n = len(cost)
    best = min(itertools.permutations(range(n)),
               key=lambda p: (round(max(cost[i, p[i]] for i in range(n)), 9),
                              sum(cost[i, p[i]] ** 2 for i in range(n))))
    return max(cost[i, best[i]] for i in range(n)), sum(cost[i, best[i]] ** 2 for i in range(n))


@pytest.mark.parametrize("path_cost", [False, True])
def test_nearest_stopper_gives_the_supporter_to_the_nearest_then_scram_for_the_rest(path_cost):
    rng = np.random.default_rng(7)
    formation = Formation.default()
    for _ in range(6):
        ball = rng.uniform([-10, -6], [10, 6])
        targets = st.role_positions(formation, ball)
        mates = tuple(st.Mate(u, *rng.uniform([-14, -9], [14, 9]), rng.uniform(-3, 3)) for u in range(3, 9))
        v = view(me=(0.0, 0.0, 0.0), ball=ball, mates=mates, unum=2)
        on_ball = st.on_ball_player(v)
        obstacles = st.role_obstacles(v, on_ball) if path_cost else None
        roles = st.assign_roles(v, targets, "mmd-msd2", on_ball, nearest_stopper=True, obstacles=obstacles)
        assert sorted(roles) == list(range(10))
        assert roles[on_ball - 2] == 0
        players = [m for m in v.team() if m.unum != on_ball]
        to_stopper = [st.walking_cost(m, targets[STOPPER], obstacles) for m in players]
        stopper = players[int(np.argmin(to_stopper))]
        assert roles[stopper.unum - 2] == STOPPER  # the nearest, whatever SCRAM would say
        rest = [m for m in players if m is not stopper]
        used = sorted(roles[m.unum - 2] for m in rest)
        assert used == list(range(2, 2 + len(rest)))
        cost = np.array([[st.walking_cost(m, targets[r], obstacles) for r in used] for m in rest])
        got = [cost[i, used.index(roles[m.unum - 2])] for i, m in enumerate(rest)]
        want_max, want_sq = _brute(cost)
        assert max(got) == pytest.approx(want_max)
        assert sum(c * c for c in got) == pytest.approx(want_sq)


def test_nearest_stopper_can_differ_from_scram():
    # Supporter at (-1.5, 0) and forwardLeft at (-1.5, 6): SCRAM minimizes the longest
    # walk, so it sends the far player 3 to the supporter; NearestStopper sends player 2.
    targets = np.zeros((10, 2))
    targets[STOPPER] = (-1.5, 0.0)
    targets[2] = (-1.5, 6.0)
    me = (-1.5, 1.0, math.pi / 2)
    mates = (st.Mate(3, -1.5, -4.0, math.pi / 2), st.Mate(4, 19.0, 0.0, 0.0))
    v = view(me=me, ball=(20.0, 0.0), mates=mates, unum=2)
    scram = st.assign_roles(v, targets, "mmd-msd2", on_ball=4)
    nearest = st.assign_roles(v, targets, "mmd-msd2", on_ball=4, nearest_stopper=True)
    assert scram[:3] == (2, 1, 0) and nearest[:3] == (1, 2, 0)


def test_detour_is_the_walk_round_one_disk():
    disk = np.array([[0.0, 0.0, 1.0]])
    # Straight through the center from (-2, 0) to (2, 0): two tangents of sqrt(3) and an
    # arc of pi - 2 acos(1/2) = pi/3, less the straight 4 m.
    want = 2 * math.sqrt(3) + math.pi / 3 - 4.0
    assert st.detour((-2.0, 0.0), (2.0, 0.0), disk) == pytest.approx(want)
    assert st.detour((-2.0, 1.5), (2.0, 1.5), disk) == 0.0  # passes clear
    assert st.detour((-2.0, 0.0), (-0.5, 0.0), disk) == 0.0  # ends inside: ignored
    m = st.Mate(2, -2.0, 0.0, 0.0)
    assert st.walking_cost(m, np.array([2.0, 0.0]), disk) == pytest.approx(4.0 + want)


def test_path_obstacles_merge_the_ball_and_the_on_ball_player_when_they_overlap():
    one = st.path_obstacles(np.array([0.0, 0.0]), (0.4, 0.0))
    assert one.shape == (1, 3)
    x, y, r = one[0]
    assert math.hypot(x, y) + st.BALL_RADIUS_PATH <= r + 1e-9
    assert math.hypot(x - 0.4, y) + st.ON_BALL_RADIUS_PATH <= r + 1e-9
    assert st.path_obstacles(np.array([0.0, 0.0]), (3.0, 0.0)).shape == (2, 3)
    assert st.path_obstacles(None, None).shape == (0, 3)


def test_path_cost_sends_the_player_behind_the_ball_to_the_position_behind_it():
    # Ball at 0, on-ball player at (-0.4, 0). Targets: one 2 m in front of the ball, one
    # 2 m behind. Player 3 stands 2.5 m in front, player 4 2.5 m behind... but offset so
    # that straight lines tie; the detour breaks the tie.
    ball = np.array([0.0, 0.0])
    targets = np.zeros((10, 2))
    targets[1] = (2.0, 0.0)
    targets[2] = (-2.0, 0.0)
    mates = (st.Mate(3, -2.0, 0.0, 0.0), st.Mate(4, 2.0, 0.0, math.pi))
    v = view(me=(-0.4, 0.0, 0.0), ball=ball, mates=mates, unum=2, mode=PlayMode.PLAY_ON)
    obstacles = st.role_obstacles(v, 2)
    assert len(obstacles)
    plain = st.assign_roles(v, targets, "mmd-msd2", on_ball=2)
    path = st.assign_roles(v, targets, "mmd-msd2", on_ball=2, obstacles=obstacles)
    assert (path[1], path[2]) == (2, 1)  # each keeps its side of the ball
    assert sorted(plain) == list(range(10))


@pytest.mark.parametrize("name", sorted(MAKERS))
def test_variant_formations_load(name):
    f = Formation.load(Path(__file__).resolve().parents[2] / "formations" / "data" / f"{name}.formation")
    assert f.roles == Formation.default().roles
    for ball in ((0.0, 0.0), (9.0, -5.0), (-13.0, 8.0)):
        pos = f.positions_at(np.array(ball))
        assert np.all(np.isfinite(pos))
        assert np.allclose(pos[f.index("onBall")], ball)


def test_boxes_do_not_move_with_the_ball_and_offensive_stays_near_it():
    from agent.player import _formation
    boxes, off = _formation("boxes.formation"), _formation("offensive.formation")
    default = Formation.default()
    a, b = boxes.positions_at(np.array([-8.0, 3.0])), boxes.positions_at(np.array([9.0, -6.0]))
    field_roles = [boxes.index(r) for r in st.FIELD_ROLES[1:]]
    assert np.allclose(a[field_roles], b[field_roles])
    ball = np.array([3.0, 1.0])

    def spread(f):
        p = f.positions_at(ball)[field_roles]
        return float(np.mean(np.hypot(*(p - ball).T)))
    assert spread(off) < spread(default)


def test_variant_names_are_case_insensitive_and_cover_the_papers_table():
    assert set(PAPER_TABLE2) <= set(VARIANTS)
    assert variant_name("aLLbaLL") == "AllBall"
    assert variant("static").assignment == "static"
    assert variant("PositiveCombo").path_cost and variant("PositiveCombo").nearest_stopper
    assert not variant("NoTeamwork").collision_avoidance and variant("NoTeamwork").all_ball
    with pytest.raises(UnknownVariant, match="variants: NoCollAvoid"):
        variant("nope")
    with pytest.raises(teams.UnknownTeam) as err:
        teams.factory("villa:nope")
    assert "\n" not in str(err.value) and "AllBall" in str(err.value)


@pytest.mark.parametrize("name", list(VARIANTS))
def test_every_variant_builds_and_plays_a_moment(name):
    from models.scene import Lineup
    from server.match import Match

    fa = teams.factory(f"villa:{name.lower()}")
    match = Match(fa, teams.factory("villa"), Lineup.default(2, 1), half_time=0.75, seed=1)
    result = match.run().to_dict()
    assert not [e for e in result["events"] if e["kind"] == "agent_crashed"]
    assert result["game_time"] >= 1.0


def test_walk_files_load_after_the_shipped_walk_for_the_types_that_have_one(tmp_path):
    from agent.player import Player
    from agent.teamconfig import TeamConfig

    (tmp_path / "fast_type1.txt").write_text("max_step_size_x\t71.5\nsprint_walk_height\t190\n")
    config = TeamConfig(walk_files=(str(tmp_path / "fast_type{type}.txt"),))
    shipped = Player("L", 2, 1, config=TeamConfig(walk_files=())).body.motion.walk.sets
    sets = Player("L", 2, 1, config=config).body.motion.walk.sets
    assert sets["go_to_target"].max_step_size_x == pytest.approx(0.0715)  # mm in the file
    assert sets["sprint"].walk_height == pytest.approx(0.190)
    assert sets["go_to_target"].walk_height == shipped["go_to_target"].walk_height
    assert shipped["go_to_target"].max_step_size_x != pytest.approx(0.0715)
    # type 2 has no such file: the shipped walk
    other = Player("L", 3, 2, config=config).body.motion.walk.sets
    assert other == Player("L", 3, 2, config=TeamConfig(walk_files=())).body.motion.walk.sets
    with pytest.raises(FileNotFoundError, match="nowhere.txt"):
        Player("L", 2, 1, config=TeamConfig(walk_files=("nowhere.txt",)))
    (tmp_path / "slew_type1.params").write_text("kick_base_slew\t90\n")
    slewing = TeamConfig(kick_files=(str(tmp_path / "slew_type{type}.params"),))
    kicks = Player("L", 2, 1, config=slewing).body.kicks
    assert kicks["kick_left"].base_slew == pytest.approx(math.radians(90.0))
    assert Player("L", 2, 1).body.kicks["kick_left"].base_slew != pytest.approx(math.radians(90.0))


def test_villa_walks_on_the_fast_sets_and_slowwalk_on_the_shipped_ones():
    from agent.player import Player
    from agent.teamconfig import variant
    from skills.params import read_entries
    from skills.walk import DATA as SKILL_DATA

    for robot_type in range(5):
        fast = Player("L", 2, robot_type).body.motion.walk.sets["go_to_target"]
        slow = Player("L", 2, robot_type, config=variant("SlowWalk")).body.motion.walk.sets["go_to_target"]
        learned = read_entries(SKILL_DATA / f"walk_fast_type{robot_type}.txt")
        assert fast.walk_height == pytest.approx(learned["walk_height"].value / 1000.0)  # mm in the file
        assert fast.phase_length == pytest.approx(learned["phase_length"].value)
        assert slow.phase_length != pytest.approx(learned["phase_length"].value)
    kicks = Player("L", 2, 0).body.kicks["kick_left"]
    assert kicks.base_slew == pytest.approx(math.radians(125.4))  # kick_fast_type0.params
    assert Player("L", 2, 0, config=variant("SlowWalk")).body.kicks["kick_left"].base_slew != kicks.base_slew


def test_fast_sprint_walks_straight_ahead_on_sprint_sets_from_the_fast_stands(monkeypatch):
    """villa:FastSprint (villa) keeps the go-to-target sets of the team before (NoSprint) and
    sprints (types 1-4) on sets learned from their stands; type 3's walks farther in 6 s
    straight ahead than its go-to-target set, without falling."""
    import benchmarks.walk as bw
    from agent.player import Player
    from agent.teamconfig import variant
    from skills.walk import DATA as SKILL_DATA

    for t in range(5):
        body = Player("L", 2, t, config=variant("FastSprint")).body
        sets = body.motion.walk.sets
        before = Player("L", 2, t, config=variant("NoSprint")).body
        assert sets["go_to_target"] == before.motion.walk.sets["go_to_target"]
        assert (body.sprint_within is None) == (t == 0) and before.sprint_within is None
        if t > 0:  # learned from the go-to-target stand: within 4 mm of its height
            assert abs(sets["sprint"].walk_height - sets["go_to_target"].walk_height) < 0.004
    files = ["walk_fast_type3.txt", "walk_fast_sprint_type3.txt"]
    monkeypatch.setattr(bw, "PARAMS", [str(SKILL_DATA / f) for f in files])
    go = bw.constant_walk(3, (1.0, 0.0, 0.0), 6.0)
    sprint = bw.constant_walk(3, (1.0, 0.0, 0.0), 6.0, "sprint")
    assert not go["fell"] and not sprint["fell"]
    assert sprint["vx"] > go["vx"] + 0.05  # m/s


def test_file_types_limit_the_walk_and_kick_files_to_those_types():
    from agent.player import Player
    from agent.teamconfig import TeamConfig, variant

    only0 = TeamConfig(file_types=(0,))
    slow = variant("SlowWalk")
    assert Player("L", 2, 0, config=only0).body.motion.walk.sets == Player("L", 2, 0).body.motion.walk.sets
    assert (Player("L", 2, 1, config=only0).body.motion.walk.sets
            == Player("L", 2, 1, config=slow).body.motion.walk.sets
            != Player("L", 2, 1).body.motion.walk.sets)


def test_an_unknown_kickoff_is_refused():
    with pytest.raises(ValueError, match="kickoff 'long'"):
        TeamConfig(kickoff="long")


def test_goalie4_keeps_the_league_rule_on_types():
    types = variant("Goalie4").robot_types
    assert types[0] == 4 and types[1:] == variant("MostlyType0").robot_types[1:]
    assert robot_types_problem(types) is None


def test_groundcombo_is_its_three_parts_together():
    parts = {name: variant(name) for name in ("TurnRamp", "DeepKickoff", "Goalie4")}
    combo = variant("GroundCombo")
    assert combo.turn_ramp == parts["TurnRamp"].turn_ramp > 0
    assert combo.kickoff == parts["DeepKickoff"].kickoff == "deep"
    assert combo.robot_types == parts["Goalie4"].robot_types
    undone = replace(combo, turn_ramp=VILLA.turn_ramp, kickoff=VILLA.kickoff, robot_types=VILLA.robot_types)
    assert undone == VILLA

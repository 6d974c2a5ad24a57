"""The team decision on hand-made snapshots (no physics): who takes the ball, roles,
where to walk and where to kick."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from agent import strategy as st
from formations.delaunay import Formation
from models import field as fld
from models.geometry import wrap
from models.rules import PlayMode


def view(me=(0.0, 0.0, 0.0), ball=(1.0, 0.0), mates=(), opponents=(), unum=2, fallen=False,
         mode=PlayMode.PLAY_ON, velocity=(0.0, 0.0)) -> st.TeamView:
    opp = np.array(opponents, dtype=float).reshape(-1, 2)
    return st.TeamView(unum=unum, time=0.0, mode=mode, ours=None, pose=tuple(me), fallen=fallen,
                       ball=None if ball is None else np.array(ball, dtype=float),
                       ball_velocity=np.array(velocity, dtype=float), mates=tuple(mates),
                       opponents=opp, opponents_fallen=np.zeros(len(opp), dtype=bool))


def test_closeness_adds_a_meter_in_front_of_the_ball_and_a_fall_unless_on_top_of_it():
    ball = (0.0, 0.0)
    assert st.closeness(-2.0, 0.0, False, ball) == pytest.approx(2.0)
    assert st.closeness(2.0, 0.0, False, ball) == pytest.approx(3.0)  # in front
    assert st.closeness(-2.0, 0.0, True, ball) == pytest.approx(3.5)  # fallen
    assert st.closeness(-0.5, 0.0, True, ball) == pytest.approx(0.5)  # fallen on top of it


def test_closeness_near_the_goals_judges_front_by_the_nearest_post():
    # Ball beside our goal: a defender nearer our post than the ball is behind it (no penalty),
    # one farther out is in front.
    ball = (-14.0, 4.0)
    inside = st.closeness(-14.5, 2.0, False, ball)
    outside = st.closeness(-13.5, 6.0, False, ball)
    assert inside == pytest.approx(math.hypot(0.5, 2.0))
    assert outside == pytest.approx(math.hypot(0.5, 2.0) + 1.0)
    # Beside their goal: an attacker nearer their post than the ball is in front.
    ball = (14.0, -4.0)
    assert st.closeness(14.5, -2.0, False, ball) == pytest.approx(math.hypot(0.5, 2.0) + 1.0)
    assert st.closeness(13.0, -5.0, False, ball) == pytest.approx(math.hypot(1.0, 1.0))


def test_the_goalie_takes_the_ball_only_inside_its_box():
    goalie = st.Mate(1, -14.0, 0.0, 0.0)
    far = st.Mate(5, -5.0, 0.0, 0.0)
    v = view(me=(-6.0, 3.0, 0.0), ball=(-13.5, 0.5), mates=(goalie, far), unum=3)
    assert st.on_ball_player(v) == 1
    v = view(me=(0.0, 5.0, 0.0), ball=(-12.0, 0.5), mates=(goalie, far), unum=3)
    assert st.on_ball_player(v) == 5  # outside the box the goalie stays home


def test_role_assignment_is_the_brute_force_minimum_of_max_then_squares():
    rng = np.random.default_rng(3)
    formation = Formation.default()
    for _ in range(5):
        ball = rng.uniform([-10, -6], [10, 6])
        targets = st.role_positions(formation, ball)
        mates = tuple(st.Mate(u, *rng.uniform([-14, -9], [14, 9]), rng.uniform(-3, 3)) for u in range(3, 9))
        v = view(me=(0.0, 0.0, 0.0), ball=ball, mates=mates, unum=2)
        on_ball = st.on_ball_player(v)
        roles = st.assign_roles(v, targets, "mmd-msd2", on_ball)
        assert sorted(roles) == list(range(10))
        assert roles[on_ball - 2] == 0
        players = [m for m in v.team() if m.unum != on_ball]
        used = sorted(roles[m.unum - 2] for m in players)
        assert used == list(range(1, 1 + len(players)))  # the first roles by priority are filled
        cost = np.array([[st.walking_cost(m, targets[r]) for r in used] for m in players])
        got = [cost[i, used.index(roles[m.unum - 2])] for i, m in enumerate(players)]
        best = min(itertools.permutations(range(len(players))),
                   key=lambda p: (round(max(cost[i, p[i]] for i in range(len(p))), 9),
                                  sum(cost[i, p[i]] ** 2 for i in range(len(p)))))
        want = [cost[i, best[i]] for i in range(len(best))]
        assert max(got) == pytest.approx(max(want))
        assert sum(c * c for c in got) == pytest.approx(sum(c * c for c in want))


def test_static_assignment_gives_shirt_order():
    v = view()
    assert st.assign_roles(v, np.zeros((10, 2)), "static") == tuple(range(10))


def test_avoid_walks_round_an_obstacle_on_the_way_and_away_when_too_close():
    me, target = (0.0, 0.0, 0.0), (4.0, 0.0)
    assert np.allclose(st.avoid(me, target, np.zeros((0, 2))), target)
    assert np.allclose(st.avoid(me, target, np.array([[0.0, 3.0]])), target)  # not in the way
    step = st.avoid(me, target, np.array([[1.0, 0.1]]))
    # Tangent: perpendicular to the obstacle's direction, passing on the side away from it.
    assert step[1] < 0 and abs(step @ np.array([1.0, 0.1])) < 1e-6 * 10
    close = st.avoid(me, target, np.array([[0.3, 0.05]]))
    assert close[0] < 0.0  # within the collision threshold it also backs away


def test_facing_turns_to_the_ball_only_near_the_position():
    assert st.facing((0.0, 0.0), (2.0, 0.0), np.array([0.0, 5.0])) is None
    assert st.facing((0.0, 0.0), (0.3, 0.0), np.array([0.0, 5.0])) == pytest.approx(math.pi / 2)


def test_keep_away_and_own_half():
    ball = np.array([0.0, 0.0])
    p = st.keep_away(np.array([0.5, 0.0]), ball)
    assert np.hypot(*p) == pytest.approx(st.KEEP_AWAY)
    far = np.array([-5.0, 1.0])
    assert np.allclose(st.keep_away(far, ball), far)
    q = st.own_half(np.array([1.0, 3.0]))
    assert q[0] < 0 and np.hypot(*q) >= fld.CENTER_CIRCLE_RADIUS
    r = st.own_half(np.array([0.5, 0.2]))
    assert r[0] < 0 and np.hypot(*r) >= fld.CENTER_CIRCLE_RADIUS


def test_pass_target_is_the_best_of_every_candidate_and_shuns_opponents():
    ball = np.array([0.0, 0.0])
    dists = [3.0, 6.0]
    opp = np.array([[6.0, 0.0]])
    mates = np.array([[4.0, 4.0]])
    target, d = st.pass_target(ball, dists, opp, mates)
    best = max(((ball + r * np.array([math.cos(a), math.sin(a)]), r)
                for a in np.arange(-math.pi, math.pi, math.radians(10)) if abs(a) <= math.radians(100)
                for r in dists), key=lambda c: st.kick_score(c[0], opp, mates))
    assert np.allclose(target, best[0]) and d == best[1]
    assert np.hypot(*(target - opp[0])) > 2.0


def test_shot_target_needs_reach_and_aims_away_from_the_goalie():
    ball = np.array([10.0, 0.0])
    assert st.shot_target(ball, np.zeros((0, 2)), reach=3.0) is None
    goalie = np.array([[14.5, 0.5]])
    t = st.shot_target(ball, goalie, reach=8.0)
    assert t is not None and t[0] > fld.HALF_LENGTH and t[1] < 0
    assert abs(t[1]) < fld.GOAL_WIDTH / 2
    assert st.shot_target(np.array([13.0, 9.0]), np.zeros((0, 2)), reach=20.0) is None  # too narrow


def _deep_landing_clearance(ball, aim, opponents, reach):
    d = aim - ball
    landing = ball + min(reach, np.hypot(*d)) * d / np.hypot(*d)
    ab = landing - ball
    t = np.clip((opponents - ball) @ ab / (ab @ ab), 0.0, 1.0)
    return float(np.min(np.hypot(*(opponents - (ball + t[:, None] * ab)).T)))


def test_deep_kick_target_aims_nearest_the_goal_on_a_clear_path():
    ball, reach = np.zeros(2), 12.0
    assert np.allclose(st.deep_kick_target(ball, np.zeros((0, 2)), reach), [fld.HALF_LENGTH, 0.0])
    rng = np.random.default_rng(3)
    for _ in range(50):  # against brute force over the aims
        opp = rng.uniform([2.0, -4.0], [12.0, 4.0], (int(rng.integers(1, 6)), 2))
        aim = st.deep_kick_target(ball, opp, reach)
        aims = [np.array([fld.HALF_LENGTH, y]) for y in st.DEEP_KICK_AIMS]
        gaps = [min(_deep_landing_clearance(ball, a, opp, reach), st.DEEP_KICK_CLEAR) for a in aims]
        best = max(range(len(aims)), key=lambda k: (gaps[k], -abs(aims[k][1])))
        assert np.allclose(aim, aims[best])
    # an opponent straight ahead: the kick goes past it, on the first aim clear of it by 1 m
    aim = st.deep_kick_target(ball, np.array([[3.0, 0.0]]), reach)
    assert _deep_landing_clearance(ball, aim, np.array([[3.0, 0.0]]), reach) >= st.DEEP_KICK_CLEAR
    assert 0.0 < abs(aim[1]) <= 6.0


def test_goalie_stands_between_ball_and_goal_and_dives_at_shots():
    x, y, h = st.goalie_position(np.array([-10.0, 4.0]))
    assert x == pytest.approx(st.GOALIE_LINE)
    assert 0.0 < y < fld.GOAL_WIDTH / 2
    assert math.cos(h) > 0 and math.sin(h) > 0  # facing the ball
    me = (st.GOALIE_LINE, 0.0, 0.0)
    assert st.dive_for(np.array([-11.0, 0.0]), np.array([-4.0, 0.0]), me) == "DIVE_CENTER"
    assert st.dive_for(np.array([-11.0, 0.0]), np.array([-4.0, 0.4]), me) == "DIVE_LEFT"
    assert st.dive_for(np.array([-11.0, 0.0]), np.array([-4.0, -0.4]), me) == "DIVE_RIGHT"
    assert st.dive_for(np.array([-11.0, 0.0]), np.array([2.0, 0.0]), me) is None  # going away
    assert st.dive_for(np.array([-11.0, 0.0]), np.array([-4.0, 3.0]), me) is None  # wide
    assert st.dive_for(np.array([-3.0, 0.0]), np.array([-1.0, 0.0]), me) is None  # not in time


def test_dribble_when_an_upright_opponent_is_near_the_ball():
    v = view(ball=(0.0, 0.0), opponents=[(1.5, 0.0)])
    assert st.opponent_near_ball(v, 2.0)
    assert not st.opponent_near_ball(v, 1.0)


def _heading(ball, target) -> float:
    return math.atan2(target[1] - ball[1], target[0] - ball[0])


def test_a_dribble_cone_turns_toward_the_approach_by_its_share_and_at_most_the_cone():
    cone = math.radians(60.0)
    ball = (0.0, 1.0)
    goal = st.dribble_target(view(me=(-1.0, 1.0, 0.0), ball=ball))
    assert np.array_equal(st.dribble_target(view(me=(0.0, 3.0, 0.0), ball=ball), 0.0), goal)
    to_goal = _heading(ball, goal)
    beside = st.dribble_target(view(me=(0.0, 3.0, 0.0), ball=ball), cone)  # coming down the field's -y
    turn = wrap(_heading(ball, beside) - to_goal)
    assert turn == pytest.approx(st.CONE_SHARE * wrap(-math.pi / 2 - to_goal), abs=1e-9)
    ahead = st.dribble_target(view(me=(2.0, 1.0, 0.0), ball=ball), cone)  # between the ball and the goal
    assert abs(wrap(_heading(ball, ahead) - to_goal)) == pytest.approx(cone, abs=1e-9)
    assert math.hypot(ahead[0] - ball[0], ahead[1] - ball[1]) == pytest.approx(st.CONE_AHEAD)


def test_a_dribble_cone_lies_between_the_goal_and_the_approach():
    rng = np.random.default_rng(7)
    cone = math.radians(60.0)
    for _ in range(300):
        ball = rng.uniform((-fld.HALF_LENGTH, -fld.HALF_WIDTH), (fld.HALF_LENGTH, fld.HALF_WIDTH))
        me = ball + rng.uniform(-2.0, 2.0, 2)
        goal = st.dribble_target(view(me=(*me, 0.0), ball=ball))
        t = st.approach_target(ball, goal, me, cone)
        turn = wrap(_heading(ball, t) - _heading(ball, goal))
        approach = wrap(_heading(me, ball) - _heading(ball, goal))
        assert abs(turn) <= cone + 1e-9 and abs(turn) <= abs(approach) + 1e-9
        assert turn * approach >= 0.0  # toward the side the player comes from
        inside = abs(t[0]) <= fld.HALF_LENGTH - 0.3 and abs(t[1]) <= fld.HALF_WIDTH - 0.3
        assert inside or np.array_equal(t, goal)


def test_a_dribble_cone_is_the_goal_near_the_goal_and_near_the_touch_line():
    cone = math.radians(60.0)
    near_goal = np.array([fld.HALF_LENGTH - 1.5, 0.5])
    goal = st.dribble_target(view(ball=near_goal))
    assert np.array_equal(st.approach_target(near_goal, goal, (near_goal[0], 2.5), cone), goal)
    by_line = np.array([0.0, fld.HALF_WIDTH - 0.5])
    goal = st.dribble_target(view(ball=by_line))
    # coming from the field's middle, the turned line would cross the touch line
    assert np.array_equal(st.approach_target(by_line, goal, (0.0, 0.0), cone), goal)


def test_a_dribble_cone_fades_out_over_the_distances_it_is_given():
    cone = math.radians(60.0)
    for d, share in ((4.0, 0.0), (7.0, 0.25), (9.0, 0.75), (11.0, 1.0)):
        ball = np.array([fld.HALF_LENGTH - d, 0.0])
        me = (ball[0], -2.0)  # beside the ball, 90 deg off the goal's line: a turn of 54 deg unfaded
        goal = st.dribble_target(view(me=(*me, 0.0), ball=ball))
        t = st.approach_target(ball, goal, me, cone, fade=(6.0, 10.0))
        turn = abs(wrap(_heading(ball, t) - _heading(ball, goal)))
        assert turn == pytest.approx(min(share * cone, st.CONE_SHARE * math.pi / 2), abs=1e-9)
    # the default fade (2 m to 5 m) leaves the whole turn 7 m from the goal
    ball = np.array([fld.HALF_LENGTH - 7.0, 0.0])
    goal = st.dribble_target(view(ball=ball))
    t = st.approach_target(ball, goal, (ball[0], -2.0), cone)
    assert abs(wrap(_heading(ball, t) - _heading(ball, goal))) == pytest.approx(st.CONE_SHARE * math.pi / 2)


def test_an_inward_cone_turns_only_toward_the_fields_long_axis():
    cone = math.radians(60.0)
    rng = np.random.default_rng(11)
    turned = 0
    for _ in range(300):
        ball = rng.uniform((-fld.HALF_LENGTH, -fld.HALF_WIDTH), (fld.HALF_LENGTH, fld.HALF_WIDTH))
        me = ball + rng.uniform(-2.0, 2.0, 2)
        goal = st.dribble_target(view(me=(*me, 0.0), ball=ball))
        both = st.approach_target(ball, goal, me, cone)
        t = st.approach_target(ball, goal, me, cone, inward=True)
        outward = (math.sin(_heading(ball, both)) - math.sin(_heading(ball, goal))) * ball[1] > 0.0
        assert np.array_equal(t, goal if outward else both)
        turned += not np.array_equal(t, goal)
    assert turned > 50  # it still turns, toward the middle
    # coming from the middle to a ball on the +y side: the plain cone pushes it toward the touch line
    ball, me = np.array([0.0, 5.0]), (0.0, 3.0)
    goal = st.dribble_target(view(me=(*me, 0.0), ball=ball))
    assert st.approach_target(ball, goal, me, cone)[1] > ball[1]
    assert np.array_equal(st.approach_target(ball, goal, me, cone, inward=True), goal)


def test_the_kickoff_taker_can_be_left_out():
    near = st.Mate(3, -2.0, 2.0, 0.0)
    v = view(me=(-0.2, 0.0, 0.0), ball=(1.5, 1.5), mates=(near,), unum=2)
    assert st.on_ball_player(v) == 2
    assert st.on_ball_player(v, exclude=2) == 3


def test_walking_costs_match_the_single_cost():
    rng = np.random.default_rng(5)
    players = [st.Mate(u, *rng.uniform(-10, 10, 2), rng.uniform(-3, 3), bool(u % 2)) for u in range(2, 8)]
    targets = rng.uniform(-10, 10, (5, 2))
    want = np.array([[st.walking_cost(m, t) for t in targets] for m in players])
    assert np.allclose(st.walking_costs(players, targets), want, rtol=0, atol=1e-12)


def _numpy_walking_costs(players, targets):
    """walking_costs as numpy computes it elementwise (the compiled kernel's spec)."""
    xs = np.array([[m.x, m.y, m.heading, m.fallen] for m in players], dtype=float).reshape(-1, 4)
    t = np.asarray(targets, dtype=float).reshape(-1, 2)
    dx = t[None, :, 0] - xs[:, None, 0]
    dy = t[None, :, 1] - xs[:, None, 1]
    dist = np.hypot(dx, dy)
    turn = np.abs(wrap(np.arctan2(dy, dx) - xs[:, None, 2])) / math.pi
    turn = np.where(dist > st.FACE_BALL_WITHIN, turn, 0.0)
    return dist + st.TURN_COST * turn + st.FALLEN_PENALTY * xs[:, None, 3]


def test_walking_costs_equal_numpy():
    """The compiled costs are numpy's formula to rounding (numpy's own floats move by an ulp
    from one release's SIMD and BLAS to the next, so exact equality is not the spec)."""
    rng = np.random.default_rng(1)
    for _ in range(3000):
        k, n = rng.integers(0, 11, 2)
        players = [st.Mate(u, *rng.uniform([-15, -10], [15, 10]), rng.uniform(-7, 7),
                           bool(rng.random() < 0.3)) for u in range(k)]
        targets = rng.uniform([-15, -10], [15, 10], size=(n, 2))
        if k and n and rng.random() < 0.3:  # on the grid, one target exactly FACE_BALL_WITHIN away
            players = [st.Mate(m.unum, round(m.x), round(m.y), m.heading, m.fallen) for m in players]
            targets = np.round(targets)
            targets[0] = (players[0].x + st.FACE_BALL_WITHIN, players[0].y)
        got, want = st.walking_costs(players, targets), _numpy_walking_costs(players, targets)
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12)


def _numpy_avoid(me, target, obstacles, proximity=st.PROXIMITY, collision=st.COLLISION):
    """avoid on numpy arrays (the compiled kernel's spec)."""
    p = np.asarray(me[:2], dtype=float)
    t = np.asarray(target[:2], dtype=float)
    to_t = t - p
    dist = float(np.hypot(*to_t))
    if dist < 1e-6 or len(obstacles) == 0:
        return t
    want = to_t / dist
    rel = np.asarray(obstacles, dtype=float)[:, :2] - p
    d = np.hypot(rel[:, 0], rel[:, 1])
    near = (d < proximity) & (d < dist) & (d > 1e-6) & (rel @ want > 0.0)
    if not near.any():
        return t
    i = int(np.argmin(np.where(near, d, np.inf)))
    u = rel[i] / d[i]
    left = np.array([-u[1], u[0]])
    tangent = left if float(left @ want) >= 0 else -left
    step = tangent - u if d[i] < collision else tangent
    step = step / max(float(np.hypot(*step)), 1e-9)
    return p + step * min(dist, proximity)


def test_avoid_equals_numpy():
    """Random walks and obstacles, equal to numpy's formula to rounding. Some obstacles lie
    across the walk to 1e-16 m, where rounding decides whether they count: there the
    kernel's answer must be numpy's with the obstacle moved 1e-9 m to one side or the other."""
    rng = np.random.default_rng(2)
    edges = 0
    for _ in range(20000):
        k = int(rng.integers(0, 22))
        me = tuple(rng.uniform([-15, -10, -4], [15, 10, 4]).tolist())
        target = np.array(me[:2]) + rng.normal(size=2) * rng.choice([1e-7, 0.3, 1.0, 3.0])
        obstacles = np.array(me[:2]) + rng.normal(size=(k, 2)) * rng.choice([0.3, 1.0, 3.0])
        edge, w = None, None
        if k and rng.random() < 0.5:
            w = (target - me[:2]) / np.hypot(*(target - me[:2]))
            edge = int(rng.integers(k))
            obstacles[edge] = (me[:2] + rng.uniform(0.1, 1.2) * np.array([-w[1], w[0]])
                               + w * rng.normal() * 1e-16)
        if rng.random() < 0.2:
            obstacles, target = np.round(obstacles * 4) / 4, np.round(target * 4) / 4
        got, want = st.avoid(me, target, obstacles), _numpy_avoid(me, target, obstacles)
        if np.allclose(got, want, rtol=1e-12, atol=1e-12):
            continue
        assert edge is not None, (me, target, obstacles)
        edges += 1
        sides = []
        for sign in (1.0, -1.0):
            moved = obstacles.copy()
            moved[edge] += sign * 1e-9 * w
            sides.append(_numpy_avoid(me, target, moved))
        assert any(np.allclose(got, s, rtol=1e-12, atol=1e-7) for s in sides), (me, target, obstacles)
    assert edges < 100  # the knife edge is rare


def test_a_finishing_dribble_aims_past_a_goalie_standing_in_front_of_the_ball():
    ball = np.array([fld.HALF_LENGTH - 1.0, 0.0])  # where a goal kick's ball lies
    keeper = [(fld.HALF_LENGTH - 0.48, 0.02)]
    plain = st.dribble_target(view(me=(ball[0] - 1.0, 0.0, 0.0), ball=ball, opponents=keeper))
    aim = st.dribble_target(view(me=(ball[0] - 1.0, 0.0, 0.0), ball=ball, opponents=keeper), finish=True)
    gap = st._clearance(ball, aim, np.array(keeper))
    assert st._clearance(ball, plain, np.array(keeper)) < st.FINISH_CLEAR  # the plain aim grazes it
    assert gap > st._clearance(ball, plain, np.array(keeper)) + 0.05
    assert abs(aim[1]) == pytest.approx(max(st.FINISH_AIMS))


def test_a_finishing_dribble_centers_a_ball_beside_the_goal_first():
    beside = np.array([fld.HALF_LENGTH - 0.3, fld.GOAL_WIDTH / 2 + 0.4])
    plain = st.dribble_target(view(me=(beside[0] - 1.0, beside[1], 0.0), ball=beside))
    assert plain[0] > fld.HALF_LENGTH  # straight at the mouth, whose line misses it
    aim = st.dribble_target(view(me=(beside[0] - 1.0, beside[1], 0.0), ball=beside), finish=True)
    assert np.array_equal(aim, st.CUTBACK)
    in_front = np.array([fld.HALF_LENGTH - 1.5, 0.3])
    aim = st.dribble_target(view(ball=in_front), finish=True)
    assert aim[0] > fld.HALF_LENGTH and abs(aim[1]) <= fld.GOAL_WIDTH / 2


def test_a_finishing_dribble_changes_nothing_away_from_their_goal():
    rng = np.random.default_rng(5)
    cone = math.radians(60.0)
    far_x = fld.HALF_LENGTH - st.FINISH_ZONE
    for _ in range(300):
        ball = rng.uniform((-fld.HALF_LENGTH, -fld.HALF_WIDTH), (far_x, fld.HALF_WIDTH))
        me = ball + rng.uniform(-2.0, 2.0, 2)
        v = view(me=(*me, 0.0), ball=ball)  # no opponents: every line is clear
        assert np.array_equal(st.dribble_target(v, cone, finish=True), st.dribble_target(v, cone))

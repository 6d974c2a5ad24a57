"""The team decision: pure functions of one player's picture of the world.

Everything here takes a `TeamView` (a snapshot of the world model: own pose,
ball, teammates and opponents as this player knows them) and returns plain
values, so it is tested without physics. All positions are in the team frame
(own goal at -x; m), headings in rad. Sections refer to MacAlpine's
dissertation (appendix D) and "Positioning to Win" (PtW).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from formations import _kernels as _fkernels
from formations.delaunay import Formation
from formations.scram import assign_costs
from models import field as fld
from models.geometry import wrap
from models.rules import FREE_KICK_DISTANCE, PlayMode

GOALIE = 1  # the only shirt number with a role of its own
# The field roles in priority order: with k field players the first k are filled.
# The team's vote is a permutation of these ten over the shirt numbers 2..11.
FIELD_ROLES = ("onBall", "supporter", "forwardLeft", "forwardRight", "midLeft", "midRight",
               "backLeft", "backRight", "wingLeft", "wingRight")
FIELD_UNUMS = tuple(range(2, 12))
OPP_GOAL = np.array([fld.HALF_LENGTH, 0.0])
OWN_GOAL = np.array([-fld.HALF_LENGTH, 0.0])
FRONT_PENALTY = 1.0  # m added to the closeness of a player in front of the ball (D.1.1)
FALLEN_PENALTY = 1.5  # m added for a fallen player ... (D.1.1)
FALLEN_NEAR = 0.65  # m ... unless it lies this close to the ball
TURN_COST = 0.5  # m of walking a half turn costs in the role assignment
PROXIMITY, COLLISION = 1.25, 0.5  # m, D.1.2 thresholds round other players
FACE_BALL_WITHIN = 0.5  # m from a position: face the ball instead of the position (D.1.3)
KEEP_AWAY = FREE_KICK_DISTANCE + 0.8  # m from the ball at the opponents' restarts
GOALIE_LINE = -fld.HALF_LENGTH + 0.5  # m: the goalie's line in front of its goal (D.3.1)
KICKOFF_TAKER = np.array([-0.17, 0.0])  # m: where the on-ball role stands at our kickoff
# m: where it stands for a kick it must walk up to (at KICKOFF_TAKER its first step nudges the ball)
KICKOFF_TAKER_BACK = np.array([-0.35, 0.0])
DEEP_KICK_AIMS = np.arange(-6.0, 6.5, 0.5)  # m: goal-line y a deep kick may aim at, ...
DEEP_KICK_CLEAR = 1.0  # m: ... its path this far from every opponent
KICKOFF_SPACING = 1.0  # m: least distance between two field players' kickoff positions
OPPONENT_RADIUS_SQ = 25.0  # m^2: eq. D.1's opponent penalty reach
MIN_SHOT_ANGLE = math.radians(8.0)  # rad: the goal mouth must look at least this wide to shoot
# A dribble cone (`approach_target`): the share of the angle between the goal's line and the
# player's approach that the dribble turns, the distance to a turned target (m) and the
# distances from the opponents' goal (m) over which the turn fades out.
CONE_SHARE = 0.6
CONE_AHEAD = 2.0
CONE_FADE = (2.0, 5.0)
DRIBBLE_AIMS = (0.0, 0.6, -0.6)  # m from the mouth's middle, behind the goal line: a dribble's aims
# A finishing dribble (`dribble_target`'s `finish`): the aims across the mouth (m from its
# middle, behind the goal line), the clearance (m) under which an aim's line counts as
# blocked, the least margin (m) inside a post where the line must cross the goal line, how
# near the goal line (m) a ball that misses so is centered first, and where to (team frame, m).
FINISH_AIMS = (0.0, 0.6, -0.6, 0.85, -0.85)
FINISH_CLEAR = 0.35
FINISH_POST_MARGIN = 0.2
FINISH_ZONE = 3.0
CUTBACK = np.array([fld.HALF_LENGTH - 1.2, 0.0])


@dataclass(frozen=True)
class Mate:
    """A teammate as this player knows it (team frame)."""

    unum: int
    x: float
    y: float
    heading: float
    fallen: bool = False


@dataclass(frozen=True)
class TeamView:
    """One player's snapshot of the world (team frame, m, rad, s)."""

    unum: int
    time: float
    mode: PlayMode
    ours: bool | None  # the play mode is ours (True), theirs (False) or nobody's (None)
    pose: tuple[float, float, float]
    fallen: bool
    ball: np.ndarray | None  # (2,)
    ball_velocity: np.ndarray = field(default_factory=lambda: np.zeros(2))
    mates: tuple[Mate, ...] = ()  # known teammates other than this player
    opponents: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    opponents_fallen: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    kick_targets: tuple[tuple[int, tuple[float, float]], ...] = ()  # (sender, target) heard lately

    @property
    def me(self) -> Mate:
        x, y, h = self.pose
        return Mate(self.unum, x, y, h, self.fallen)

    def team(self) -> list[Mate]:
        """Every known player of the team, this one included, by shirt number."""
        return sorted((*self.mates, self.me), key=lambda m: m.unum)


# --------------------------------------------------------------- who goes to the ball

def closeness(x: float, y: float, fallen: bool, ball: Sequence[float]) -> float:
    """D.1.1's adjusted distance (m) of a player at (x, y) to the ball."""
    bx, by = float(ball[0]), float(ball[1])
    dist = math.hypot(x - bx, y - by)
    adjust = FALLEN_PENALTY if fallen and dist > FALLEN_NEAR else 0.0
    half_goal = fld.GOAL_WIDTH / 2
    corner_reach = fld.HALF_WIDTH - half_goal
    if abs(by) > half_goal and bx < -fld.HALF_LENGTH + corner_reach:
        post = (-fld.HALF_LENGTH, math.copysign(half_goal, by))
        if math.hypot(x - post[0], y - post[1]) > math.hypot(bx - post[0], by - post[1]):
            adjust += FRONT_PENALTY  # defending: in front means farther from our post
    elif abs(by) > half_goal and bx > fld.HALF_LENGTH - corner_reach:
        post = (fld.HALF_LENGTH, math.copysign(half_goal, by))
        if math.hypot(x - post[0], y - post[1]) < math.hypot(bx - post[0], by - post[1]):
            adjust += FRONT_PENALTY
    elif x >= bx:
        adjust += FRONT_PENALTY
    return dist + adjust


def in_own_penalty_area(p: Sequence[float], margin: float = 0.0) -> bool:
    return (p[0] < -fld.HALF_LENGTH + fld.PENALTY_DEPTH + margin
            and abs(p[1]) < fld.PENALTY_WIDTH / 2 + margin)


def on_ball_player(view: TeamView, exclude: int | None = None) -> int | None:
    """Shirt number of the player of least closeness; the goalie only inside its box;
    `exclude` never (the kickoff's taker until another player has played the ball)."""
    if view.ball is None:
        return None
    best, best_c = None, math.inf
    goalie_may = in_own_penalty_area(view.ball)
    for m in view.team():
        if (m.unum == GOALIE and not goalie_may) or m.unum == exclude:
            continue
        c = closeness(m.x, m.y, m.fallen, view.ball)
        if c < best_c - 1e-9:
            best, best_c = m.unum, c
    return best


# ------------------------------------------------------------------ role assignment

def role_positions(formation: Formation, ball: np.ndarray, shift: float = 0.0) -> np.ndarray:
    """(10, 2) positions of FIELD_ROLES for a ball position (the formation's lookup)."""
    out = formation.rows_at(formation.indices(FIELD_ROLES), ball)
    if shift:
        out[1:, 0] = np.clip(out[1:, 0] + shift, -fld.HALF_LENGTH + 0.5, fld.HALF_LENGTH - 0.5)
    return out


def walking_cost(m: Mate, target: np.ndarray, obstacles: np.ndarray | None = None) -> float:
    """Cost (m) of walking to a target: distance, a turn toward it, and a fall (SCRAM's
    path cost with the robot's state); with `obstacles` (k, 3) disks (x, y, radius),
    the walk goes round them (PtW section 6's PathCost: `detour`)."""
    disks = None if obstacles is None or not len(obstacles) else _disks(obstacles)
    return _walking_cost(m, float(target[0]), float(target[1]), disks)


def _walking_cost(m: Mate, tx: float, ty: float, disks: list[list[float]] | None) -> float:
    dx, dy = tx - m.x, ty - m.y
    dist = math.hypot(dx, dy)
    turn = abs(wrap(math.atan2(dy, dx) - m.heading)) / math.pi if dist > FACE_BALL_WITHIN else 0.0
    cost = dist + TURN_COST * turn + (FALLEN_PENALTY if m.fallen else 0.0)
    if disks:
        cost += _detour(m.x, m.y, tx, ty, disks)
    return cost


def _disks(obstacles: np.ndarray) -> list[list[float]]:
    """(k, 3) disks as lists of Python floats (the per-pair loops run faster on them)."""
    return np.asarray(obstacles, dtype=float).reshape(-1, 3).tolist()


def walking_costs(players: Sequence[Mate], targets: np.ndarray) -> np.ndarray:
    """`walking_cost` (no obstacles) of every player (rows) to every target (columns)."""
    xs = np.array([[m.x, m.y, m.heading, m.fallen] for m in players], dtype=float).reshape(-1, 4)
    t = np.ascontiguousarray(targets, dtype=float).reshape(-1, 2)
    return _fkernels.walking_costs(xs, t, FACE_BALL_WITHIN, TURN_COST, FALLEN_PENALTY)


BALL_RADIUS_PATH = 0.3  # m kept from the ball by a walk that must not push it (PathCost)
ON_BALL_RADIUS_PATH = COLLISION  # m kept from the on-ball player (PathCost)


def path_obstacles(ball: np.ndarray | None, on_ball: Sequence[float] | None) -> np.ndarray:
    """(k, 3) disks a role walk goes round (PathCost): the ball and the on-ball player,
    one enclosing disk when the two overlap."""
    disks = []
    if ball is not None:
        disks.append((float(ball[0]), float(ball[1]), BALL_RADIUS_PATH))
    if on_ball is not None:
        disks.append((float(on_ball[0]), float(on_ball[1]), ON_BALL_RADIUS_PATH))
    if len(disks) == 2:
        (ax, ay, ar), (bx, by, br) = disks
        d = math.hypot(bx - ax, by - ay)
        if d < ar + br:  # overlapping: the smallest disk holding both
            if d + ar <= br or d + br <= ar:
                disks = [disks[0] if ar >= br else disks[1]]
            else:
                r = (d + ar + br) / 2
                u = (r - ar) / d
                disks = [(ax + (bx - ax) * u, ay + (by - ay) * u, r)]
    return np.array(disks, dtype=float).reshape(-1, 3)


def role_obstacles(view: TeamView, on_ball: int | None) -> np.ndarray:
    """`path_obstacles` of a view: its ball and the on-ball player where known."""
    at = next(((m.x, m.y) for m in view.team() if m.unum == on_ball), None)
    return path_obstacles(view.ball, at)


def detour(start: Sequence[float], goal: Sequence[float], disks: np.ndarray) -> float:
    """Extra length (m) of walking from `start` to `goal` round disks (k, 3) over the
    straight line: for each disk the segment cuts, the shortest path round that one
    disk (two tangents and an arc) less the chord; the disks add up (exact for one
    disk, an estimate for several). A start or goal inside a disk ignores it."""
    return _detour(float(start[0]), float(start[1]), float(goal[0]), float(goal[1]), _disks(disks))


def _detour(px: float, py: float, tx: float, ty: float, disks: list[list[float]]) -> float:
    sx, sy = tx - px, ty - py
    seg2 = sx * sx + sy * sy
    if seg2 < 1e-12:
        return 0.0
    straight = math.sqrt(seg2)
    extra = 0.0
    for cx, cy, r in disks:
        s = min(max(((cx - px) * sx + (cy - py) * sy) / seg2, 0.0), 1.0)
        ex, ey = px + s * sx - cx, py + s * sy - cy
        if ex * ex + ey * ey > 1.000001 * r * r:
            continue  # the straight walk clears it by far (the exact tests below agree)
        dp = math.hypot(px - cx, py - cy)
        dt = math.hypot(tx - cx, ty - cy)
        if dp <= r or dt <= r:
            continue
        if math.hypot(ex, ey) >= r:
            continue  # the straight walk clears it
        angle = abs(wrap(math.atan2(py - cy, px - cx) - math.atan2(ty - cy, tx - cx)))
        arc = max(angle - math.acos(r / dp) - math.acos(r / dt), 0.0)
        extra += math.sqrt(dp * dp - r * r) + math.sqrt(dt * dt - r * r) + r * arc - straight
    return max(extra, 0.0)


def assign_roles(view: TeamView, targets: np.ndarray, method: str = "mmd-msd2",
                 on_ball: int | None = None,
                 nearest_stopper: bool = False, obstacles: np.ndarray | None = None) -> tuple[int, ...]:
    """This player's vote: the role index (into FIELD_ROLES) of each of shirt numbers 2..11.

    targets: (10, 2) role positions. The on-ball player takes role 0; the other
    known field players share the next roles by `method` (SCRAM on walking
    cost); unknown shirt numbers get the roles left over, in order. `method`
    "static" gives shirt number 2 + k role k. With `nearest_stopper` (PtW 6's
    NearestStopper) the supporter role (1, directly behind the ball: the paper's
    stopper) first goes to the known field player of least walking cost to it, and
    `method` shares the rest. `obstacles` (k, 3) disks make the walking cost go
    round them (PathCost; `path_obstacles`)."""
    if method == "static":
        return tuple(range(len(FIELD_UNUMS)))
    known = [m for m in view.team() if m.unum in FIELD_UNUMS]
    roles = [-1] * len(FIELD_UNUMS)
    free_roles = list(range(len(FIELD_ROLES)))
    if on_ball is not None and on_ball in FIELD_UNUMS:
        roles[on_ball - 2] = 0
        free_roles.remove(0)
        known = [m for m in known if m.unum != on_ball]
    stopper = FIELD_ROLES.index("supporter")
    disks = None if obstacles is None or not len(obstacles) else _disks(obstacles)
    if nearest_stopper and known and stopper in free_roles:
        tx, ty = targets[stopper].tolist()
        costs = [_walking_cost(m, tx, ty, disks) for m in known]
        nearest = known[int(np.argmin(costs))]  # ties: the lower shirt number
        roles[nearest.unum - 2] = stopper
        free_roles.remove(stopper)
        known = [m for m in known if m is not nearest]
    k = min(len(known), len(free_roles))
    if k:
        use = free_roles[:k]
        if obstacles is None or not len(obstacles):
            cost = walking_costs(known[:k], targets[use])
        else:
            spots = targets[use].tolist()
            cost = np.array([[_walking_cost(m, tx, ty, disks) for tx, ty in spots] for m in known[:k]])
        pick = assign_costs(cost, method)
        for m, j in zip(known[:k], pick):
            roles[m.unum - 2] = use[int(j)]
    left = [r for r in free_roles if r not in roles]
    for i in range(len(roles)):
        if roles[i] < 0:
            roles[i] = left.pop(0)
    return tuple(roles)


# --------------------------------------------------------------------- walking

def avoid(me: Sequence[float], target: Sequence[float], obstacles: np.ndarray,
          proximity: float = PROXIMITY, collision: float = COLLISION) -> np.ndarray:
    """D.1.2: the point to walk toward instead of `target` (team frame) so as to pass
    round `obstacles` (k, 2): tangent to one within `proximity`, and away from it
    too within `collision`. Only obstacles nearer than the target count."""
    p = np.asarray(me[:2], dtype=float)
    t = np.asarray(target[:2], dtype=float)
    to_t = t - p
    dist = float(np.hypot(*to_t))
    if dist < 1e-6 or len(obstacles) == 0:
        return t
    px, py = p.tolist()
    tx, ty = t.tolist()
    obstacles = np.ascontiguousarray(obstacles, dtype=float)
    turn, x, y = _fkernels.avoid_step(px, py, tx, ty, dist, obstacles, proximity, collision)
    return np.array([x, y]) if turn else t


def facing(me: Sequence[float], target: Sequence[float], ball: np.ndarray | None) -> float | None:
    """D.1.3: the heading to end with at a position: toward the ball once within
    FACE_BALL_WITHIN of the target (None: keep facing the target)."""
    if ball is None or math.hypot(target[0] - me[0], target[1] - me[1]) > FACE_BALL_WITHIN:
        return None
    return math.atan2(ball[1] - me[1], ball[0] - me[0])


def keep_away(target: np.ndarray, ball: np.ndarray, radius: float = KEEP_AWAY) -> np.ndarray:
    """A position pushed out of a circle round the ball, toward our own goal's side."""
    d = target - ball
    n = float(np.hypot(*d))
    if n >= radius:
        return target
    u = d / n if n > 1e-6 else np.array([-1.0, 0.0])
    return ball + u * radius


def own_half(target: np.ndarray) -> np.ndarray:
    """A position kept in our half and out of the center circle (kickoff rules)."""
    p = np.array([min(float(target[0]), -0.3), float(target[1])])
    r = fld.CENTER_CIRCLE_RADIUS + 0.6
    if math.hypot(*p) < r:
        n = float(np.hypot(*p))
        p = p / n * r if n > 1e-6 else np.array([-r, 0.0])
    return p


def kickoff_positions(formation: Formation, our_kickoff: bool,
                      taker: np.ndarray = KICKOFF_TAKER) -> np.ndarray:
    """(10, 2) kickoff positions of FIELD_ROLES (team frame, m): the formation for the ball
    on the center spot, kept in our half and out of the center circle, the on-ball role
    at `taker` behind the ball at our kickoff. A role that lands within KICKOFF_SPACING of an
    earlier one stands that much farther back (at their kickoff the on-ball role and the
    supporter were both pushed out of the circle to one spot, and fell over each other)."""
    out: list[np.ndarray] = []
    for i, p in enumerate(role_positions(formation, np.zeros(2))):
        q = np.array(taker, dtype=float) if i == 0 and our_kickoff else own_half(p)
        while any(math.hypot(*(q - o)) < KICKOFF_SPACING for o in out):
            q[0] -= KICKOFF_SPACING
        out.append(q)
    return np.array(out)


# ------------------------------------------------------------------- the ball

def shot_target(ball: np.ndarray, opponents: np.ndarray, reach: float) -> np.ndarray | None:
    """A point in the opponents' goal to shoot at, if a kick reaching `reach` (m) can
    get there and the mouth looks at least MIN_SHOT_ANGLE wide: the one of five
    across the mouth farthest from every opponent's line to it."""
    goal_x = fld.HALF_LENGTH + 0.5
    posts = [math.atan2(s * fld.GOAL_WIDTH / 2 - ball[1], fld.HALF_LENGTH - ball[0]) for s in (1.0, -1.0)]
    if fld.HALF_LENGTH - ball[0] < 0.3 or abs(wrap(posts[0] - posts[1])) < MIN_SHOT_ANGLE:
        return None  # the mouth looks too narrow for the kicks' aim
    ys = np.linspace(-0.35, 0.35, 5) * fld.GOAL_WIDTH
    best, best_gap = None, -math.inf
    for y in ys:
        t = np.array([goal_x, y])
        if float(np.hypot(*(t - ball))) > reach:
            continue
        gap = _clearance(ball, t, opponents)
        if gap > best_gap:
            best, best_gap = t, gap
    return best


def deep_kick_target(ball: np.ndarray, opponents: np.ndarray, reach: float,
                     clear: float = DEEP_KICK_CLEAR) -> np.ndarray:
    """Where a kick reaching `reach` (m) from `ball` should aim to go deep: a point on
    their goal line 0-6 m from its center, the nearest to the center whose path to the
    landing passes `clear` m from every opponent (else the clearest); team frame, m."""
    best, best_key = None, (-math.inf, 0.0)
    for y in DEEP_KICK_AIMS:
        aim = np.array([fld.HALF_LENGTH, y])
        d = aim - ball
        n = float(np.hypot(*d))
        landing = ball + min(reach, n) * d / max(n, 1e-9)
        key = (min(_clearance(ball, landing, opponents), clear), -abs(y))
        if key > best_key:
            best, best_key = aim, key
    return best


def _clearance(a: np.ndarray, b: np.ndarray, points: np.ndarray) -> float:
    """Least distance (m) from `points` (k, 2) to the segment a-b (inf for none)."""
    if len(points) == 0:
        return math.inf
    ab = b - a
    t = np.clip(((points - a) @ ab) / max(float(ab @ ab), 1e-9), 0.0, 1.0)
    closest = a + t[:, None] * ab
    return float(np.min(np.hypot(*(points - closest).T)))


def kick_scores(targets: np.ndarray, opponents: np.ndarray, mates: np.ndarray) -> np.ndarray:
    """Equation D.1 for (k, 2) targets: toward the goal, away from opponents, near a
    teammate."""
    t = np.asarray(targets, dtype=float).reshape(-1, 2)
    score = -np.hypot(OPP_GOAL[0] - t[:, 0], OPP_GOAL[1] - t[:, 1])
    if len(opponents):
        d2 = np.sum((t[:, None, :] - opponents[None, :, :]) ** 2, axis=2)
        score -= np.sum(np.maximum(OPPONENT_RADIUS_SQ - d2, 0.0), axis=1)
    if len(mates):
        near = np.min(np.hypot(*(t[:, None, :] - mates[None, :, :]).transpose(2, 0, 1)), axis=1)
        score += np.maximum(10.0 - near, 0.0)
    return score


def kick_score(target: np.ndarray, opponents: np.ndarray, mates: np.ndarray) -> float:
    """Equation D.1 for one target."""
    return float(kick_scores(target, opponents, mates)[0])


_DIRECTIONS = np.arange(-math.pi, math.pi, math.radians(10.0))
_FORWARD = _DIRECTIONS[np.abs(_DIRECTIONS) <= math.radians(100)]  # farther back is too far backwards
_UNITS = np.stack([np.cos(_FORWARD), np.sin(_FORWARD)], axis=1)


def pass_target(ball: np.ndarray, distances: Sequence[float], opponents: np.ndarray,
                mates: np.ndarray) -> tuple[np.ndarray, float]:
    """D.2.2: the best of the targets every 10 degrees round the ball at each kick
    distance (m), skipping those out of the field or well backwards; (target, distance)."""
    d = np.asarray(distances, dtype=float)
    b = np.asarray(ball, dtype=float)
    targets = (b[None, None, :] + d[None, :, None] * _UNITS[:, None, :]).reshape(-1, 2)
    dist = np.broadcast_to(d[None, :], (len(_UNITS), len(d))).reshape(-1)
    margin = 0.5
    inside = ((np.abs(targets[:, 0]) <= fld.HALF_LENGTH - margin)
              & (np.abs(targets[:, 1]) <= fld.HALF_WIDTH - margin))
    if not inside.any():  # nothing inside: straight at the goal, shortest kick
        dmin = float(d.min())
        u = (OPP_GOAL - ball) / max(float(np.hypot(*(OPP_GOAL - ball))), 1e-9)
        return ball + dmin * u, dmin
    scores = np.where(inside, kick_scores(targets, opponents, mates), -np.inf)
    k = int(np.argmax(scores))
    return targets[k].copy(), float(dist[k])


def opponent_near_ball(view: TeamView, radius: float) -> bool:
    """An upright opponent within `radius` (m) of the ball (D.2.1's reason to dribble)."""
    if view.ball is None or len(view.opponents) == 0:
        return False
    d = np.hypot(*(view.opponents - view.ball).T)
    return bool(np.any((d < radius) & ~view.opponents_fallen))


def opponent_may_reach_first(view: TeamView, lead: float) -> bool:
    """An upright opponent no farther from the ball than I am plus `lead` (m): a race."""
    if view.ball is None or len(view.opponents) == 0:
        return False
    mine = float(np.hypot(view.pose[0] - view.ball[0], view.pose[1] - view.ball[1]))
    d = np.hypot(*(view.opponents - view.ball).T)
    return bool(np.any((d < mine + lead) & ~view.opponents_fallen))


def dribble_target(view: TeamView, cone: float = 0.0, inward: bool = False,
                   fade: tuple[float, float] = CONE_FADE, finish: bool = False) -> np.ndarray:
    """Where to dribble: the goal's center, or across the box toward the far post when
    an opponent stands on the line to it (a reflex, D.1.5). With `cone` (rad), the line
    turns from there toward the one the player comes along (`approach_target`; with
    `inward`, never toward the nearer touchline; `fade` as there).

    With `finish`, the aims are FINISH_AIMS and a blocked line (clearance under
    FINISH_CLEAR) gives way to any clearer one; a ball whose line to its aim would cross
    the goal line outside the posts (beside the goal, within FINISH_ZONE of the end line)
    is pushed toward CUTBACK, in front of the goal, instead."""
    ball = view.ball
    best, best_gap = OPP_GOAL, -math.inf
    clear = FINISH_CLEAR if finish else 0.0
    for y in FINISH_AIMS if finish else DRIBBLE_AIMS:
        t = np.array([fld.HALF_LENGTH + 0.5, y])
        gap = _clearance(ball, t, view.opponents)
        if gap > best_gap + 0.3 or (best_gap < clear and gap > best_gap):
            best, best_gap = t, gap
    if finish and ball[0] > fld.HALF_LENGTH - FINISH_ZONE and not _crosses_mouth(ball, best):
        return CUTBACK.copy()
    return approach_target(ball, best, view.pose, cone, inward, fade) if cone > 0.0 else best


def _crosses_mouth(ball: np.ndarray, aim: np.ndarray) -> bool:
    """The line from `ball` to `aim` (behind the opponents' goal line) crosses that line
    at least FINISH_POST_MARGIN inside the posts."""
    bx, by = float(ball[0]), float(ball[1])
    y = by  # a ball on or past the line: where it lies
    if bx < fld.HALF_LENGTH:
        y += (float(aim[1]) - by) * (fld.HALF_LENGTH - bx) / (float(aim[0]) - bx)
    return abs(y) <= fld.GOAL_WIDTH / 2 - FINISH_POST_MARGIN


def approach_target(ball: np.ndarray, goal: np.ndarray, me: Sequence[float], cone: float,
                    inward: bool = False, fade: tuple[float, float] = CONE_FADE) -> np.ndarray:
    """A dribble target (team frame, m) on the line from the ball toward `goal`, turned
    toward the line from the player at `me` through the ball by CONE_SHARE of the angle
    between them, at most `cone` rad: a player beside or ahead of the ball pushes it on
    sooner instead of going round it, and a player dribbling on (its approach is its last
    push) steers back toward the goal plan by plan. The turn fades out over `fade` (m from
    the opponents' goal: none within the first, all of it beyond the second); `goal` itself
    when the turned line would leave the field within CONE_AHEAD m. With `inward`, a turn
    that would point the line further toward the touchline on the ball's side is not taken
    (`goal` itself)."""
    b = np.asarray(ball, dtype=float)
    gx, gy = float(goal[0] - b[0]), float(goal[1] - b[1])
    ax, ay = float(b[0] - me[0]), float(b[1] - me[1])
    if math.hypot(ax, ay) < 1e-3:
        return np.asarray(goal, dtype=float)
    near, far = fade
    limit = cone * min(max((float(np.hypot(*(OPP_GOAL - b))) - near) / (far - near), 0.0), 1.0)
    heading = math.atan2(gy, gx)
    turn = min(max(CONE_SHARE * wrap(math.atan2(ay, ax) - heading), -limit), limit)
    if inward and (math.sin(heading + turn) - math.sin(heading)) * float(b[1]) > 0.0:
        return np.asarray(goal, dtype=float)
    t = b + CONE_AHEAD * np.array([math.cos(heading + turn), math.sin(heading + turn)])
    if abs(t[0]) > fld.HALF_LENGTH - 0.3 or abs(t[1]) > fld.HALF_WIDTH - 0.3:
        return np.asarray(goal, dtype=float)
    return t


# ------------------------------------------------------------------------ goalie

def goalie_position(ball: np.ndarray | None) -> tuple[float, float, float]:
    """D.3.1: on the line 0.5 m in front of the goal, between the ball and the goal's
    center, facing the ball."""
    if ball is None:
        return GOALIE_LINE, 0.0, 0.0
    gx = -fld.HALF_LENGTH
    bx, by = float(ball[0]), float(ball[1])
    if bx - gx < 0.6:
        y = by
    else:
        y = by * (GOALIE_LINE - gx) / (bx - gx)
    y = float(np.clip(y, -fld.GOAL_WIDTH / 2 + 0.2, fld.GOAL_WIDTH / 2 - 0.2))
    return GOALIE_LINE, y, math.atan2(by - y, bx - GOALIE_LINE)


def dive_for(ball: np.ndarray | None, velocity: np.ndarray, me: Sequence[float],
             horizon: float = 1.2, reach: float = 0.25) -> str | None:
    """The dive (skills.dive name) that stops a shot: the ball moving toward our goal
    crosses the goalie's line within `horizon` s between the posts; a center dive
    when it passes within `reach` (m) of the goalie, else a side dive."""
    if ball is None:
        return None
    vx, vy = float(velocity[0]), float(velocity[1])
    if vx > -0.8:
        return None
    t = (me[0] - float(ball[0])) / vx
    if not 0.0 <= t <= horizon:
        return None
    y = float(ball[1]) + vy * t
    if abs(y) > fld.GOAL_WIDTH / 2 + 0.3:
        return None
    off = y - me[1]  # + passes on the left of a goalie facing +x
    if abs(off) < reach:
        return "DIVE_CENTER"
    return "DIVE_LEFT" if off * math.cos(me[2]) > 0 else "DIVE_RIGHT"


__all__ = [
    "FIELD_ROLES", "FIELD_UNUMS", "GOALIE", "Mate", "TeamView", "approach_target", "assign_roles", "avoid",
    "closeness", "deep_kick_target", "detour", "dive_for", "dribble_target", "facing", "goalie_position",
    "keep_away", "kick_score", "kick_scores", "kickoff_positions", "on_ball_player",
    "opponent_may_reach_first", "opponent_near_ball", "own_half", "pass_target", "path_obstacles",
    "role_obstacles", "role_positions", "shot_target", "walking_cost", "walking_costs",
]

"""Physics trials with ground truth: of single skills on the trainer (a goalie dive, a
stance move (align), an IK kick, and the IK kick's backswing clearance (kinematics)),
and of villa players in a match: a first touch on a free ball, a finish against a standing
goalie, a duel, and clearing a ball at the own goal line.

The benchmarks (`benchmarks.dive`, `benchmarks.align`, `benchmarks.ikkick`,
`benchmarks.firsttouch`, `benchmarks.finishing`, `benchmarks.duel`,
`benchmarks.clearing`) and the physics tests run these same
trials. Frames: the field frame of the trainer's world; a kick's offsets in the robot frame
at its start (m, rad).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import mujoco
import numpy as np

from agent.kicker import SKILL_GAINS
from agent.posture import PostureAgent
from agent.teamconfig import TeamConfig
from agent.variants import VillaFactory
from models import field as fld
from models import nao
from models.geometry import Pose2, wrap
from models.messages import Action
from models.robot import robot_mjcf
from models.rules import CYCLE, PlayMode
from models.scene import Lineup
from optimization.robot import new_robot
from server.match import Match
from server.referee import Referee
from server.trainer import Trainer
from skills.align import Align
from skills.dive import Dive
from skills.kicks.ik import IkKick
from skills.motion import Motion
from skills.walk import WalkParams

LIMIT = 10.0  # s from the dive's start to standing again
LOW = 0.5  # the torso is down below this fraction of the standing height


@dataclass
class DiveRun:
    """Ground truth of one dive (lateral: m along the robot's starting left, from its start)."""

    ground: float | None  # s until the torso was below LOW x standing height
    reach_left: float  # farthest any collision geom got to the left while diving and down
    reach_right: float  # ... to the right (negative)
    torso_lateral: float  # torso displacement to the left when the robot was down
    up_after: float | None  # s until the dive reported done
    upright_at_end: bool  # torso up and high when done, and still so 0.5 s later
    times: dict  # s from the dive's start at which each phase (last) began


def run_dive(robot_type: int, name: str, seed: int) -> DiveRun:
    """A robot stands still (walk stand, seeded heading and joint noise), then plays `name`."""
    rng = np.random.default_rng(seed)
    trainer = Trainer(Lineup((robot_type,), ()), seed=seed, vision=False)
    w = trainer.world
    dive = Dive(robot_type, name)
    q = dive.motion.walk.update(0.0, 0.0, 0.0).targets
    q = np.where(np.isnan(q), 0.0, q) + rng.normal(0.0, 0.01, q.shape)
    dive.motion.reset()
    heading = float(rng.uniform(-math.pi, math.pi))
    w.place_ball((10.0, 8.0))
    w.place_robot(0, 0.0, 0.0, heading, joints=q)
    w.settle_height(0)
    for _ in range(25):
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.motion.walk_step(pc, 0.0, 0.0, 0.0))})
    p = w.players[0]
    geoms = [g for g in range(p.geoms[0], p.geoms[1] + 1) if w.model.geom_contype[g]]
    start = w.torso_positions()[0].copy()
    left = np.array([-math.sin(heading), math.cos(heading)])
    stand = nao.standing_height(robot_type)
    t0 = w.time
    ground, up_after = None, None
    reach_l = reach_r = lateral = 0.0
    while w.time - t0 < LIMIT and up_after is None:
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
        torso = w.torso_positions()[0]
        if ground is None and torso[2] < LOW * stand:
            ground = w.time - t0
        if dive.phase in ("dive", "down"):
            y = (w.data.geom_xpos[geoms, :2] - start[:2]) @ left
            reach_l, reach_r = max(reach_l, float(y.max())), min(reach_r, float(y.min()))
            lateral = float((torso[:2] - start[:2]) @ left)
        if dive.done:
            up_after = w.time - t0

    def upright() -> bool:
        return bool(w.torso_up()[0] > 0.9 and w.torso_positions()[0, 2] > 0.8 * stand)

    ok = up_after is not None and upright()
    for _ in range(25):  # it keeps standing
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
    times = {k: v - t0 for k, v in dive.times.items()}
    return DiveRun(ground, reach_l, reach_r, lateral, up_after, ok and upright(), times)


START_SET = "approach_to_kick"  # the walk set of the "walk" start


def come_to_stand(tr: Trainer, mo: Motion, start: str, rng: np.random.Generator) -> bool:
    """Bring a new robot to a stand as `start` says ("walk" or "stand"); False if it fell."""
    w = tr.world
    if start == "walk":
        walk = mo.walk
        until = w.time + rng.uniform(1.0, 2.0)
        while w.time < until or not walk.step_begins():
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.4, 0.0, 0.0, START_SET))})
        walk.reset()  # stop at the change of support, as the approach does
        until = w.time + rng.uniform(0.5, 0.8)
        while w.time < until or not (mo.last is not None and mo.last.standing):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0, START_SET))})
    else:
        for _ in range(25):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
    return w.torso_up()[0] > 0.5


def align_errors(robot_type: int, tries: int, move: float, turn: float, seed: int,
                 start: str = "walk") -> dict:
    rng = np.random.default_rng([seed, robot_type])
    align = Align(robot_type)
    errors, falls, start_falls = [], 0, 0
    for _ in range(tries):
        request = (rng.uniform(-move, move), rng.uniform(-move, move), math.radians(rng.uniform(-turn, turn)))
        tr, mo = new_robot(robot_type)
        w = tr.world
        if not come_to_stand(tr, mo, start, rng):  # fell walking: not the align's fall
            start_falls += 1
            continue
        x0, y0, h0 = w.player_pose(0)
        mo.walk.reset()
        align.reset(request)
        fell = False
        while not align.done:
            pc = tr.percepts()[0]
            tr.step({0: Action(mo.command(align.step(pc), pc))})
            fell = fell or bool(w.torso_up()[0] < 0.5)
        for _ in range(25):  # stand 0.5 s: a fall there counts too
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
            fell = fell or bool(w.torso_up()[0] < 0.5)
        falls += fell
        if fell:
            continue
        x1, y1, h1 = w.player_pose(0)
        c, s = math.cos(h0), math.sin(h0)
        dx, dy = c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0)
        dh = math.remainder(h1 - h0, 2.0 * math.pi)
        errors.append((1e3 * abs(dx - request[0]), 1e3 * abs(dy - request[1]),
                       math.degrees(abs(dh - request[2]))))
    e = np.array(errors) if errors else np.full((1, 3), np.nan)
    return {"benchmark": "align", "robot_type": robot_type, "start": start, "tries": tries, "falls": falls,
            "fell_before": start_falls,
            "error_mean_mm_mm_deg": [round(float(v), 1) for v in e.mean(axis=0)],
            "error_max_mm_mm_deg": [round(float(v), 1) for v in e.max(axis=0)],
            "seconds_per_move": round(align.params.duration, 2)}


TOUCH = 0.05  # m the ball moves for a first touch
CLEARANCE_SAMPLES = 80  # samples of the backswing checked by `backswing_clearance`


def kick_trial(t: int, kick: IkKick, offset: tuple[float, float] = (0.0, 0.0), roll: float = 3.0,
               stand: float = 0.5) -> dict:
    """One kick in physics; returns distance (m), direction (rad, robot frame at the start),
    along (m, displacement along spec.direction), fell, and the direction's deviation
    from spec.direction (rad, + to the left) and its size (error)."""
    tr, mo = new_robot(t)
    w = tr.world
    for _ in range(round(stand / 0.02)):  # stand and kick at the kicks' gains, as the Kicker does
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0, kp=SKILL_GAINS[0]))})
    mo.skill_gains(SKILL_GAINS)
    x0, y0, h0 = w.player_pose(0)
    start = Pose2(x0, y0, h0)
    bx, by = kick.spec.ball[0] + offset[0], kick.spec.ball[1] + offset[1]
    w.place_ball(start.to_world(bx, by))
    b0 = w.ball_position()[:2].copy()
    kick.reset((bx, by))
    fell = False
    while not kick.done:
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.command(kick.step(pc), pc))})
        if w.torso_up()[0] < 0.5:
            fell = True
            break
    mo.reset()
    n = round(roll / 0.02)
    for _ in range(n):
        if fell or np.linalg.norm(w.ball_velocity()[:2]) < 0.02:
            break
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        if w.torso_up()[0] < 0.5:
            fell = True
    rest = w.ball_rest_position()  # a ball still rolling is carried on to its stop
    dx, dy = Pose2(b0[0], b0[1], h0).to_local(rest[0], rest[1])
    dist = math.hypot(dx, dy)
    direction = math.atan2(dy, dx)
    a = kick.spec.direction
    along = dx * math.cos(a) + dy * math.sin(a)
    return {"distance": dist, "direction": direction, "along": along, "fell": fell,
            "deviation": wrap(direction - a), "error": abs(wrap(direction - a))}


class _Scene:
    """One robot of a type and a free-floating ball geom, posed kinematically (no physics)."""

    def __init__(self, robot_type: int) -> None:
        xml = robot_mjcf(robot_type).replace(
            "</worldbody>", f'<body name="ball" mocap="true"><geom name="ball" type="sphere" '
            f'size="{fld.BALL_RADIUS}" contype="0" conaffinity="0"/></body></worldbody>')
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.qadr = np.array([m.jnt_qposadr[m.joint(n).id] for n in nao.joint_names(robot_type)])
        self.ball = m.geom("ball").id
        self.leg = {side: [g for g in range(m.ngeom) if m.body(m.geom_bodyid[g]).name in
                           (f"{side}shank", f"{side}ankle", f"{side}foot", f"{side}toe")]
                    for side in "lr"}


_SCENES: dict[int, _Scene] = {}


def backswing_clearance(kick: IkKick, ball: tuple[float, float] | None = None) -> tuple[float, float]:
    """Least distance (m) between the ball and the kicking shank, ankle, foot or toe while
    the foot swings back, before the strike; and the normalized swing time of it.

    Kinematics only: the torso upright where the kick puts it, the legs at the
    kick's IK targets, the ball at `ball` (robot frame, m; default the spec's). The
    backswing runs to the pull-back: the waypoint farthest back against the kick's
    direction. A backswing that grazes the ball rolls it off the strike's path (type
    4's toe clipped it in most walking IK 45-in kicks). Leaves `kick` reset to the
    spec's ball."""
    sc = _SCENES.setdefault(kick.robot_type, _Scene(kick.robot_type))
    m, d = sc.model, sc.data
    kick.reset(ball)
    u = np.array([math.cos(kick.spec.direction), math.sin(kick.spec.direction)])
    back = min(kick.params.waypoints, key=lambda w: float(u @ w.pos[:2])).t
    d.mocap_pos[0] = [kick.ball[0], kick.ball[1], fld.BALL_RADIUS]
    best, at = math.inf, 0.0
    for s in np.linspace(0.0, back, CLEARANCE_SAMPLES + 1):
        t = kick.params.shift_time + float(s) * kick.params.swing_time
        _, torso, _ = kick.pose_at(t)
        q = kick.targets_at(t)
        d.qpos[:3] = torso
        d.qpos[3:7] = [1.0, 0.0, 0.0, 0.0]
        d.qpos[sc.qadr] = np.where(np.isnan(q), 0.0, q)
        mujoco.mj_kinematics(m, d)
        for g in sc.leg[kick.kick_side]:
            dist = mujoco.mj_geomDistance(m, d, sc.ball, g, 0.5, None)
            if dist < best:
                best, at = dist, float(s)
    kick.reset()
    return best, at


def solo_match(player: type, robot_type: int, seed: int, half_time: float, config: TeamConfig,
               sets: Mapping[str, WalkParams] | None = None) -> Match:
    """A match of one `player` (a villa `Player` subclass whose decision a task replaces,
    playing `config`; its body's walk sets of `sets`' names replaced: an optimization's
    candidates) against one posture robot, after the beams and the first settling."""

    def make(side: str, unum: int, t: int, s: int):
        p = player(side, unum, t, s, config)
        if sets:
            p.body.motion.walk.sets.update(sets)
        return p

    m = Match(make, PostureAgent, Lineup((robot_type,), (0,)), half_time=half_time, seed=seed)
    for _ in range(60):
        m.step()
    return m


def place_player(m: Match, i: int, x: float, y: float, heading: float) -> None:
    """Trainer: stand match player i at (x, y) facing `heading` (field frame; m, rad) in
    its current joint pose, its agent told as after a beam (it knows where it stands)."""
    w = m.world
    w.place_robot(i, x, y, heading, joints=w.joint_angles(i))
    w.settle_height(i)
    agent = m.agents[i]
    agent.world.beamed(x, y, heading)
    agent.body.beamed()


def play_on_with(m: Match, ball: tuple[float, float], players: list[tuple[str, tuple[float, float]]],
                 velocity: tuple[float, float] = (0.0, 0.0)) -> Referee:
    """Trainer commands: each (side, place) player 2 at its place (field frame, m) facing the
    ball, the ball at `ball` rolling at `velocity` (m/s), then play on; the referee."""
    w = m.world
    bx, by = float(ball[0]), float(ball[1])
    for side, (x, y) in players:
        place_player(m, w.player(side, 2), x, y, math.atan2(by - y, bx - x))
    w.place_ball((bx, by), velocity=(float(velocity[0]), float(velocity[1]), 0.0))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    return m.referee


@dataclass(frozen=True)
class FirstTouch:
    """A villa player's first touch on a free ball: s after play on (None: none), the
    ball's progress toward the opponents' goal (m, +x of the field) and the falls."""

    touch: float | None
    progress: float
    falls: int


def first_touch(robot_type: int, config: TeamConfig, seed: int, ball: tuple[float, float], bearing: float,
                distance: float, seconds: float = 12.0,
                roll: tuple[float, float] = (0.0, 0.0)) -> FirstTouch:
    """Play on with a free ball at `ball` (field frame, m) and the left team's player 2
    (`robot_type`, playing `config`) standing `distance` m from it at `bearing` (rad, from
    the ball), facing it: it does what the team does with a free ball, from its percepts.
    Their goalie stands out of the way. A ball given a `roll` velocity (m/s, field frame)
    is touched when the player first touches it (the referee's count), a still one when
    it has moved TOUCH m."""
    m = Match(VillaFactory(config), PostureAgent, Lineup((0, robot_type), (0,)), half_time=300, seed=seed)
    for _ in range(60):  # the beams and the first settling
        m.step()
    w = m.world
    b = np.array(ball, dtype=float)
    x, y = b[0] + distance * math.cos(bearing), b[1] + distance * math.sin(bearing)
    place_player(m, w.player("L", 2), x, y, wrap(bearing + math.pi))
    w.place_robot(w.player("R", 1), 14.5, 9.0, math.pi)
    w.place_ball((float(b[0]), float(b[1])))
    rolls, touches = roll != (0.0, 0.0), m.referee.touches["L"]
    if rolls:
        w.set_ball_velocity((float(roll[0]), float(roll[1]), 0.0))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    touch = None
    for k in range(round(seconds / CYCLE)):
        m.step()
        if touch is None and (m.referee.touches["L"] > touches if rolls
                              else float(np.hypot(*(w.ball_position()[:2] - b))) > TOUCH):
            touch = round((k + 1) * CYCLE, 6)
    return FirstTouch(touch, float(w.ball_position()[0] - b[0]), int(m.referee.falls["L"]))


@dataclass(frozen=True)
class Finish:
    """A villa player's finish against a standing goalie: how it ended ("goal", "out" over
    the end line or side line, or None: the ball still in play), s after play on, and falls."""

    outcome: str | None
    time: float
    falls: int


def finish(robot_type: int, config: TeamConfig, seed: int, ball: tuple[float, float],
           start: tuple[float, float], seconds: float = 30.0) -> Finish:
    """Play on with a free ball at `ball` (field frame, m) near the right goal, whose posture
    goalie stands where it was beamed, and the left team's player 2 (`robot_type`, playing
    `config`) standing at `start` facing the ball: it does what the team does with the ball,
    from its percepts, until a goal, an out or `seconds`."""
    m = Match(VillaFactory(config), PostureAgent, Lineup((0, robot_type), (0,)), half_time=300, seed=seed)
    for _ in range(60):  # the beams and the first settling
        m.step()
    ref = play_on_with(m, ball, [("L", start)])
    seen, falls = len(ref.events), ref.falls["L"]
    for k in range(round(seconds / CYCLE)):
        m.step()
        ended = next((e.kind for e in ref.events[seen:] if e.kind in ("goal", "out")), None)
        if ended is not None:
            return Finish(ended, round((k + 1) * CYCLE, 6), int(ref.falls["L"] - falls))
    return Finish(None, seconds, int(ref.falls["L"] - falls))


@dataclass(frozen=True)
class Duel:
    """One duel for a free ball: how far it went toward the left team's attacking goal
    (m, +x of the field), the time each side was the last to have touched it (possession,
    s), which side touched it first (None: neither) and each side's falls."""

    progress: float
    possession: dict[str, float]
    first: str | None
    falls: dict[str, int]


def duel(left: TeamConfig, right: TeamConfig, robot_type: int, seed: int, ball: tuple[float, float],
         starts: tuple[tuple[float, float], tuple[float, float]], seconds: float = 20.0) -> Duel:
    """Play on for `seconds` with a free ball at `ball` (field frame, m) and one field
    player a side (`robot_type`), the left one playing `left` and the right one `right`,
    each standing at its `starts` (field frame, m) facing the ball: both do what their
    team does with a free ball, from their percepts. The goalies stay in their goals."""
    m = Match(VillaFactory(left), VillaFactory(right), Lineup((0, robot_type), (0, robot_type)),
              half_time=300, seed=seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # the beams and the first settling, ...
        m.step()  # ... ended before any player sees the kickoff (its taker would plan it)
    w = m.world
    b = np.array(ball, dtype=float)
    ref = play_on_with(m, ball, list(zip("LR", starts)))
    held, falls, touches = dict(ref.possession), dict(ref.falls), dict(ref.touches)
    first = None
    for _ in range(round(seconds / CYCLE)):
        m.step()
        if first is None:
            first = next((s for s in "LR" if ref.touches[s] > touches[s]), None)
    return Duel(float(w.ball_position()[0] - b[0]),
                {s: round(ref.possession[s] - held[s], 6) for s in "LR"}, first,
                {s: ref.falls[s] - falls[s] for s in "LR"})


CLEAR_DISTANCE = 2.5  # m from the own goal line: a ball this far out is cleared


@dataclass(frozen=True)
class Clear:
    """A ball lying at the own goal line: how the try ended ("cleared": CLEAR_DISTANCE m out;
    "goal": into the own goal; "out": over a line; None: none of them within the try), s after
    play on, and the left team's falls."""

    outcome: str | None
    time: float
    falls: int


def clear(robot_type: int, config: TeamConfig, seed: int, ball: tuple[float, float],
          start: tuple[float, float], attacker: tuple[float, float] | None = None,
          seconds: float = 30.0, velocity: tuple[float, float] = (0.0, 0.0), goalie_type: int = 0) -> Clear:
    """Play on with a free ball at `ball` (field frame, m) in front of the left goal, rolling
    at `velocity` (m/s), defended by the left team's goalie (playing `config`, beamed in its
    goal) and player 2 (`robot_type`) standing at `start` facing the ball; with `attacker`,
    a villa player of the right team (the same type) stands there facing the ball, else the
    right team is a posture goalie. Until the ball, once within CLEAR_DISTANCE m of the goal
    line, is that far out again (cleared), a goal, an out, or `seconds`. The left goalie is
    of `goalie_type`."""
    right = (0, robot_type) if attacker is not None else (0,)
    m = Match(VillaFactory(config), VillaFactory(TeamConfig()) if attacker is not None else PostureAgent,
              Lineup((goalie_type, robot_type), right), half_time=300, seed=seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # the beams and the first settling
        m.step()
    w = m.world
    players = [("L", start)] + ([("R", attacker)] if attacker is not None else [])
    ref = play_on_with(m, ball, players, velocity)
    seen, falls = len(ref.events), ref.falls["L"]
    entered = False
    for k in range(round(seconds / CYCLE)):
        m.step()
        t = round((k + 1) * CYCLE, 6)
        ended = next((e.kind for e in ref.events[seen:] if e.kind in ("goal", "out")), None)
        if ended is not None:
            return Clear(ended, t, int(ref.falls["L"] - falls))
        out = float(w.ball_position()[0]) + fld.HALF_LENGTH
        if entered and out >= CLEAR_DISTANCE:
            return Clear("cleared", t, int(ref.falls["L"] - falls))
        entered = entered or out < CLEAR_DISTANCE
    return Clear(None, seconds, int(ref.falls["L"] - falls))

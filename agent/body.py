"""The body: one skill request a cycle turned into joint velocities.

It owns the robot's `skills.motion.Motion` (walk engine, joint control,
getups) and plays what the decision layer asks (`agent.requests`): walking to
a pose, dribbling, standing, a goalie dive, and kicks through
`agent.kicker.Kicker` (approach, align and the kick of least cost). A skill
that has begun (a kick, an align, a dive, a getup) finishes before another
request takes the body. Poses come from the world model (team frame, m, rad).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from agent.head import HeadController
from agent.kicker import ALIGN, DONE, KICK, LEAN, Kicker
from agent.requests import Dive, Dribble, Kick, SkillRequest, Stand, WalkTo
from agent.worldmodel import WorldModel
from models.geometry import Pose2, wrap
from models.messages import Percept
from models.rules import CYCLE
from skills.dive import Dive as DiveSkill
from skills.imu import TiltEstimator
from skills.kicks import all_kicks
from skills.navigate import sprints, walk_toward
from skills.walk import WalkParams

BEAM_SETTLE = 0.5  # s standing still after a beam (blending into the stand: Motion.enter_stand)
STOP_DISTANCE = 0.08  # m from a WalkTo target where the robot stands
STOP_TURN = math.radians(12.0)  # rad of heading error left when it stands
DRIBBLE_BEHIND = 0.25  # m behind the ball where a dribble lines up
DRIBBLE_LANE = 0.1  # m either side of the ball's line: pushing on
DRIBBLE_FACING = math.radians(25.0)  # rad of heading error while pushing on
DRIBBLE_REACH = 0.6  # m from the ball: farther, line up again
DRIBBLE_LEAD = 0.8  # m past the ball: pushing on, walk toward this point ...
DRIBBLE_BRAKE = 0.5  # m ... slowing within this of it (walk_toward's braking radius)
HOLD_SET = "dribble_hold"  # the walk set a held dribble pushes with (Body's dribble_hold)
BALL_ROUND = 0.5  # m: go round the ball this far when it is in the way of lining up
# The funnel (TeamConfig.dribble_funnel): lining a dribble up without stopping.
FUNNEL_CONE = math.radians(35.0)  # rad off the line behind the ball (seen from it): round it first
FUNNEL_LEAD = 0.7  # m: behind the ball, walk toward its line this far ahead ...
FUNNEL_NEAR = 0.15  # ... but no nearer the ball than this (m behind it)
FUNNEL_BRAKE = 0.25  # m: walk_toward's braking radius walking into the line ...
ORBIT_LEAD = math.radians(50.0)  # rad: rounding the ball, walk toward the circle this far on ...
ORBIT_BRAKE = 0.05  # m ... without slowing
KICK_BEHIND = 0.5  # m behind the ball where the walk hands a kick over to the kicker
HANDOVER = 0.9  # m from the ball: the kicker (approach, align, kick) takes over
RELEASE = 1.6  # m: the ball got this far away during the approach: walk again
SYNC_NEAR = 0.6  # m: farther from the ball the kicker's pose follows the world model's ...
SYNC_POSITION = 0.25  # m ... when it is this far off
SYNC_HEADING = math.radians(15.0)  # rad ... or turned this much


class Body:
    """Skills of one robot behind the requests of `agent.requests`.

    kick_box: the kicks' tolerance boxes (where the approach must stop) scaled by this;
    sprint_within: the bearing (deg) within which a far target is walked to with the
    "sprint" set, not "go_to_target" (None: never; `skills.navigate.sprints`), once the walk
    steps forward at `sprint_from` of the go-to-target set's longest step (0: from a stand);
    walk_sets: the walk sets (default: the type's shipped ones); kick_params: keyframe kick
    parameter files loaded after the shipped ones; dribble_set: the walk set a dribble walks
    through the ball with; funnel: line a dribble up with `_funnel`, not `_line_up`;
    dribble_hold: (lead m, brake m, step gain a cycle) for a push that keeps the ball near:
    walk toward `lead` m past the ball slowing within `brake` m of that point, with the
    dribble set's step sizes following the request at `gain` a cycle (None: DRIBBLE_LEAD,
    DRIBBLE_BRAKE and the set's own gain); ball_focus: the head stays on the ball within this
    (m) while a dribble or kick is asked for (elsewhere within the head's own 1 m); goalie_head:
    the head always on the ball, as the dissertation's goalie (8.2.1)."""

    def __init__(self, robot_type: int, kick_box: float = 1.0, sprint_within: float | None = None,
                 walk_sets: Mapping[str, WalkParams] | None = None, kick_params: Sequence[Path] = (),
                 dribble_set: str = "go_to_target", funnel: bool = False,
                 dribble_hold: tuple[float, float, float] | None = None, turn_ramp: float = 0.0,
                 sprint_from: float = 0.0, ball_focus: float | None = None,
                 goalie_head: bool = False) -> None:
        self.robot_type = robot_type
        if ball_focus is not None and ball_focus < 0.0:
            raise ValueError(f"ball_focus {ball_focus}: must be >= 0 (m from the ball) or None")
        self.ball_focus = ball_focus
        if turn_ramp < 0.0:
            raise ValueError(f"turn_ramp {turn_ramp}: must be >= 0 (turn input a second; 0: off)")
        self.turn_ramp = turn_ramp
        if sprint_from < 0.0:
            raise ValueError(f"sprint_from {sprint_from}: must be >= 0 (a fraction of the longest step)")
        self.dribble_set = dribble_set
        self.funnel = funnel
        self.sprint_within = None if sprint_within is None else math.radians(sprint_within)
        self.sprint_from = sprint_from
        self.kicks = all_kicks(robot_type, keyframe_params=list(kick_params))
        if kick_box != 1.0:  # a wider box to stop in: fewer aligns, a less exact kick
            for k in self.kicks.values():
                k.spec = replace(k.spec, tolerance=tuple(kick_box * t for t in k.spec.tolerance))
        self.kicker = Kicker(robot_type, self.kicks, walk_sets)
        self.motion = self.kicker.motion
        if dribble_set not in self.motion.walk.sets:
            sets = ", ".join(self.motion.walk.sets)
            raise ValueError(f"unknown dribble walk set {dribble_set!r}; sets are {sets}")
        self._push = (dribble_set, DRIBBLE_LEAD, DRIBBLE_BRAKE)  # (walk set, lead m, brake m)
        if dribble_hold is not None:
            lead, brake, gain = dribble_hold
            if brake <= 0.0 or not 0.0 < gain <= 1.0:
                raise ValueError(f"dribble_hold {dribble_hold}: the brake must be > 0 m "
                                 "and the gain in (0, 1]")
            sets = self.motion.walk.sets
            sets[HOLD_SET] = replace(sets[dribble_set], pid_step_size_x=gain, pid_step_size_y=gain)
            self._push = (HOLD_SET, lead, brake)
        self.tilt = TiltEstimator()
        self.head = HeadController(goalie=goalie_head)
        self._ball_request = False  # the request this cycle is a dribble or a kick
        self.kicking = False  # the kicker has the body
        self.dive: DiveSkill | None = None
        self.odometry = (0.0, 0.0, 0.0)  # the walk's (dx, dy, dtheta) in the last cycle (torso frame)
        self.kicks_started = 0  # kicks begun (the kicker left its approach for a kick)
        self._recovering = False
        self._funneling = False  # behind the ball, walking into its line (`_funnel`)
        self._kick_state = None
        self._settle_until: float | None = -1.0  # s: standing still after a beam until then
        self._turn = (-1.0, 0.0)  # (s, turn input) of the last walk cycle, for turn_ramp

    @property
    def busy(self) -> bool:
        """A kick, an align, a dive or a getup holds the body."""
        return self.dive is not None or (self.kicking and (self.kicker.state in (KICK, ALIGN)
                                                           or self.motion.recovering))

    @property
    def down(self) -> bool:
        """Lying or getting up."""
        return self._recovering or self.motion.recovering

    def beamed(self) -> None:
        """The robot was moved by a beam: start the walk from standing, after standing
        still for BEAM_SETTLE s (stepping off at once tipped robots over)."""
        self._leave_kicker()
        self.motion.reset()
        self._settle_until = None

    def execute(self, request: SkillRequest, percept: Percept, world: WorldModel) -> np.ndarray:
        """Joint velocities (rad/s, league order) for this cycle."""
        self.tilt.update(percept.gyro, percept.accel, CYCLE)
        self._ball_request = isinstance(request, (Dribble, Kick))
        before = self.motion.last
        v = self._execute(request, percept, world)
        after = self.motion.last
        self.odometry = after.odometry if after is not None and after is not before else (0.0, 0.0, 0.0)
        if self.kicking:
            if self.kicker.state == KICK and self._kick_state != KICK:
                self.kicks_started += 1
            self._kick_state = self.kicker.state
        return v

    # ------------------------------------------------------------------ dispatch

    def _execute(self, req: SkillRequest, percept: Percept, world: WorldModel) -> np.ndarray:
        if self.dive is not None:
            v = self.dive.step(percept)
            if self.dive.done:
                self.dive.release()
                self.dive = None
                self.motion.reset()
            return v
        if isinstance(req, Dive) and not self.busy and not self.down:
            self._leave_kicker()
            self.dive = DiveSkill(self.robot_type, req.name, motion=self.motion)
            return self.dive.step(percept)
        if self.kicking:
            if self.busy or (isinstance(req, Kick) and self._near_ball(world, RELEASE)):
                return self._kick(req, percept, world)
            self._leave_kicker()
        elif (isinstance(req, Kick) and not self.down and self._near_ball(world, HANDOVER)
              and self._may_stop()):
            self._start_kick(req, world)
            return self._kick(req, percept, world)
        if self._settle_until is None:
            self._settle_until = percept.time + BEAM_SETTLE
        if percept.time < self._settle_until:
            self.motion.skill_gains(None)
            return self._look(self.motion.enter_stand(percept), percept, world)
        leaning = max(abs(self.tilt.pitch), abs(self.tilt.roll)) > LEAN
        if leaning or self._recovering or self.motion.recovering:
            v = self.motion.recover(percept)
            self._recovering = v is not None
            if v is not None:
                return v
        if isinstance(req, Kick):  # far from the ball: walk to line up behind it
            return self._line_up(percept, world, req.target, KICK_BEHIND)
        if isinstance(req, WalkTo):
            return self._walk_to(percept, world, req.x, req.y, req.heading, req.set_name)
        if isinstance(req, Dribble):
            return self._dribble(req, percept, world)
        heading = req.heading if isinstance(req, Stand) else None
        return self._stand(percept, world, heading)

    # --------------------------------------------------------------------- kicks

    def _may_stop(self) -> bool:
        walk = self.motion.walk
        return not walk.walking or walk.step_begins()

    def _start_kick(self, req: Kick, world: WorldModel) -> None:
        self.kicker.kicks = {n: self.kicks[n] for n in req.kicks}
        self.kicker.start(tuple(float(v) for v in world.pose), req.target)
        self.kicker.tilt = copy.deepcopy(self.tilt)  # its own is stale after a spell of walking
        if world.ball_filter.initialized:
            self.kicker.ball.position = world.ball_filter.position
            self.kicker.ball.seen_at = world.ball.last_seen
        self.kicking = True
        self._kick_state = self.kicker.state

    def _kick(self, req: SkillRequest, percept: Percept, world: WorldModel) -> np.ndarray:
        k = self.kicker
        if isinstance(req, Kick) and k.state not in (KICK, ALIGN):
            if k.state == DONE:  # the last kick is over: a new one from where the robot stands
                self._start_kick(req, world)
            else:
                k.target = (float(req.target[0]), float(req.target[1]))
                if set(req.kicks) != set(k.kicks):
                    k.kicks = {n: self.kicks[n] for n in req.kicks}
                if not self._near_ball(world, SYNC_NEAR):
                    self._sync_kicker(world)
        return k.act(percept)

    def _near_ball(self, world: WorldModel, radius: float) -> bool:
        if not world.ball_filter.initialized:
            return False
        bx, by = world.ball_filter.position
        x, y, _ = world.pose
        return math.hypot(bx - x, by - y) < radius

    def _sync_kicker(self, world: WorldModel) -> None:
        """Away from the ball the kicker's dead reckoning follows the world model
        (near it, dead reckoning is the steadier picture of where the ball lies)."""
        k = self.kicker
        x, y, h = (float(v) for v in world.pose)
        off = math.hypot(k.odo.x - x, k.odo.y - y)
        if off > SYNC_POSITION or abs(wrap(k.odo.heading - h)) > SYNC_HEADING:
            k.odo.x, k.odo.y, k.odo.heading = x, y, h
            if world.ball_filter.initialized:
                k.ball.position = world.ball_filter.position

    def _leave_kicker(self) -> None:
        if not self.kicking:
            return
        self.kicking = False
        self.motion.skill_gains(None)
        if self.kicker.state == DONE:  # it holds the kick's last pose: walk from the stand
            self.motion.reset()

    # --------------------------------------------------------------------- walks

    def _walk(self, percept: Percept, world: WorldModel, x: float, y: float, turn: float,
              set_name: str = "go_to_target") -> np.ndarray:
        self.motion.skill_gains(None)
        if self.turn_ramp > 0.0:
            turn = self._ramp(percept.time, turn)
        return self._look(self.motion.walk_step(percept, x, y, turn, set_name), percept, world)

    def _ramp(self, now: float, turn: float) -> float:
        """The turn input grown by at most `turn_ramp` a second from the last walk cycle's
        (from 0 after a pause or a change of side); shrinking at once. A full turn right
        after walking forward at full speed tips the fast walk over."""
        t0, last = self._turn
        prev = last if 0.0 < now - t0 <= 1.5 * CYCLE and last * turn > 0.0 else 0.0
        if abs(turn) > abs(prev):
            turn = math.copysign(min(abs(turn), abs(prev) + self.turn_ramp * CYCLE), turn)
        self._turn = (now, turn)
        return turn

    def _look(self, v: np.ndarray, percept: Percept, world: WorldModel) -> np.ndarray:
        """`v` with the head's velocities: toward the ball, or scanning for it."""
        rel = world.ball_relative() if world.ball.valid else None
        bearing, dist = rel if rel is not None else (None, None)
        focus = self.ball_focus if self._ball_request else None
        v[0:2] = self.head.velocities(percept.time, percept.joints, bearing, dist, focus)
        return v

    def _walk_to(self, percept: Percept, world: WorldModel, tx: float, ty: float,
                 heading: float | None, set_name: str = "go_to_target", sprint: bool = True,
                 brake: float = 0.5) -> np.ndarray:
        """Walk toward (tx, ty) (team frame, m), ending facing `heading` if given, slowing
        within `brake` m; with `sprint` and the team's sprint_within, the sprint set toward a
        far target ahead."""
        x, y, h = world.pose.tolist()
        dx, dy = Pose2(x, y, h).to_local(tx, ty)
        dheading = None if heading is None else wrap(heading - h)
        if math.hypot(dx, dy) < STOP_DISTANCE and (dheading is None or abs(dheading) < STOP_TURN):
            return self._walk(percept, world, 0.0, 0.0, 0.0, set_name)
        if sprint and set_name == "go_to_target" and sprints(dx, dy, self.sprint_within) and self._at_speed():
            set_name = "sprint"
        params = self.motion.walk.sets[set_name]
        return self._walk(percept, world, *walk_toward(dx, dy, dheading, params, brake=brake), set_name)

    def _at_speed(self) -> bool:
        """The walk steps forward at sprint_from of the go-to-target set's longest step."""
        if self.sprint_from <= 0.0:
            return True
        walk = self.motion.walk
        return float(walk.step[0]) >= self.sprint_from * walk.sets["go_to_target"].max_step_size_x

    def _stand(self, percept: Percept, world: WorldModel, heading: float | None) -> np.ndarray:
        x, y, _ = world.pose
        return self._walk_to(percept, world, x, y, heading)

    def _dribble(self, req: Dribble, percept: Percept, world: WorldModel) -> np.ndarray:
        """Line up behind the ball facing the target, then walk through it (D.1.6)."""
        if not world.ball_filter.initialized:
            return self._stand(percept, world, None)
        ball = world.ball_filter.position
        me = np.asarray(world.pose[:2], dtype=float)
        u = _unit(np.asarray(req.target, dtype=float) - ball)
        along, across = _ball_frame(me, ball, u)
        facing = abs(wrap(math.atan2(u[1], u[0]) - float(world.pose[2])))
        if (along < -0.05 and abs(across) < DRIBBLE_LANE and facing < DRIBBLE_FACING
                and float(np.hypot(*(me - ball))) < DRIBBLE_REACH):
            set_name, lead, brake = self._push
            aim = ball + lead * u - 0.5 * across * np.array([-u[1], u[0]])
            # through the ball, never sprinting: sprinting through it fell 4 times in 10 tries
            return self._walk_to(percept, world, float(aim[0]), float(aim[1]), None,
                                 set_name, sprint=False, brake=brake)
        if self.funnel:
            return self._funnel(percept, world, req.target)
        return self._line_up(percept, world, req.target, DRIBBLE_BEHIND)

    def _line_up(self, percept: Percept, world: WorldModel, target: tuple[float, float],
                 behind: float) -> np.ndarray:
        """Walk to `behind` m behind the ball on its line to `target`, facing along it;
        from beside or in front of the ball, round it first (D.1.4)."""
        ball = world.ball_filter.position
        me = np.asarray(world.pose[:2], dtype=float)
        u = _unit(np.asarray(target, dtype=float) - ball)
        along, across = _ball_frame(me, ball, u)
        stage = ball - behind * u
        if along > -0.15 and abs(across) < BALL_ROUND:  # beside or in front: round the ball first
            side = 1.0 if across >= 0 else -1.0
            stage = ball + BALL_ROUND * side * np.array([-u[1], u[0]]) - 0.2 * u
        heading = math.atan2(u[1], u[0]) if float(np.hypot(*(me - stage))) < 0.5 else None
        return self._walk_to(percept, world, float(stage[0]), float(stage[1]), heading)

    def _funnel(self, percept: Percept, world: WorldModel, target: tuple[float, float]) -> np.ndarray:
        """Get behind the ball on its line to `target` (team frame, m) without stopping.

        Seen from the ball, more than FUNNEL_CONE off that line: walk round the ball facing
        the way, toward the BALL_ROUND circle ORBIT_LEAD further round. Within, and from then
        on while behind the ball (the line turns as the robot comes round: the cone's does):
        walk toward the line FUNNEL_LEAD m ahead, facing along it, until `_dribble` pushes on.
        `_line_up` instead stops at a spot behind the ball and steps sideways into it, slowly,
        when the line moved."""
        ball = world.ball_filter.position
        me = np.asarray(world.pose[:2], dtype=float)
        u = _unit(np.asarray(target, dtype=float) - ball)
        d = me - ball
        phi = math.atan2(d[1], d[0])
        delta = wrap(math.atan2(-u[1], -u[0]) - phi)  # round the ball by this to be behind it
        along, _ = _ball_frame(me, ball, u)
        self._funneling = along < -0.05 if self._funneling else abs(delta) < FUNNEL_CONE
        if not self._funneling:
            a = phi + math.copysign(min(abs(delta), ORBIT_LEAD), delta)
            via = ball + BALL_ROUND * np.array([math.cos(a), math.sin(a)])
            return self._walk_to(percept, world, float(via[0]), float(via[1]), None, brake=ORBIT_BRAKE)
        point = ball + min(along + FUNNEL_LEAD, -FUNNEL_NEAR) * u
        return self._walk_to(percept, world, float(point[0]), float(point[1]), math.atan2(u[1], u[0]),
                             brake=FUNNEL_BRAKE)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.hypot(*v)), 1e-6)


def _ball_frame(me: np.ndarray, ball: np.ndarray, u: np.ndarray) -> tuple[float, float]:
    """(along, across) of a point in the frame at the ball with x along `u` (m; along < 0
    is behind the ball)."""
    d = me - ball
    return float(d @ u), float(u[0] * d[1] - u[1] * d[0])


__all__ = ["Body"]

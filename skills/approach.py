"""Walking up to the ball to kick it, and which kick to use (dissertation 8.2.7).

Frames: positions and headings are in one ground frame of the caller's
choosing (the field frame, or a dead-reckoning frame: m, rad); the robot frame
is the torso projected on the ground (x forward, y left). A kick's
`skills.kicks.KickSpec` says where the ball must lie in the robot frame when
the kick starts and in which direction (robot frame) it sends the ball.

* `kick_pose`: where the robot must stand, and facing where, for a kick to send
  the ball toward a target.
* `kick_cost`: UT's cost of moving to that pose, distance (m) + turn / 360 deg
  + 0.5 when the ball lies in the path, and `choose_kick`, the kick of least cost.
* `Approach`: walk inputs toward the pose. Far from it, or on the wrong side of
  the ball, it walks to a waypoint: straight to a staging point `stage` behind
  the pose when the way is clear, otherwise to where the path touches a circle
  of radius `around` round the ball and then round it, stepping sideways
  while it faces the ball (UT's circling, dissertation D.1.6; the head keeps
  the ball in view). The fast go-to-target set only for walking on ahead;
  turning, stepping sideways and circling with the steadier approach-to-kick
  set. Within `near` of the pose, and facing within `enter_turn` of the kick's
  heading (else it first turns at the staging point: the creep turns slowly),
  it creeps in with the approach-to-kick set and UT's velocity rule, per axis
  of the robot frame::

      v = sqrt(2 * MAXDECEL * (d if d > 2 * BUFFER else d - BUFFER))

  (d: distance still to go along the axis, v: the speed that can still stop in
  time), steering onto the kick line like a car while far and with sideways
  steps in the last centimetres, on errors low-passed over about a step (the
  torso sways and twists with every step). At the pose it stops and, once it
  has stood still for `settle` s, judges the pose again on what it sees
  standing: `ready` when the ball lies in the kick's tolerance box and the
  heading is within tolerance; otherwise it fixes a small error with a short
  burst of steps, walks on when short, or backs off and comes again (this
  walk turns poorly on the spot, and each stop turns the robot by about 5 deg
  at random). With `align` given, an error small enough for `skills.align.Align`
  (a few cm and up to 20 deg) is instead handed to the caller (mode "align"),
  which steps it off one foot at a time, and the pose is judged again, in a
  box `after_align` times the kick's (until the next `reset`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, fields, replace
from enum import Enum
from pathlib import Path

import numpy as np

from models.geometry import Pose2, rotate, wrap
from skills.align import AlignParams
from skills.kicks.spec import KickSpec
from skills.navigate import walk_toward
from skills.params import PathLike, load_params, with_type_file
from skills.walk import WalkParams

DATA = Path(__file__).parent / "data"
BALL_PENALTY = 0.5  # UT's kick-cost penalty when the ball lies in the path
BALL_CLEARANCE = 0.15  # m: a path passing closer than this to the ball "runs into" it
BEHIND_CONE = math.radians(35.0)  # half-angle of the cone behind the pose that leads straight in


@dataclass(frozen=True)
class ApproachParams:
    """The approach's parameters (SI). `max_decel_*` and `buffer` are UT's MAXDECEL and
    BUFFER; the others say when to switch from walking to approaching, how to go
    round the ball and how to stop."""

    max_decel_x: float = 0.123  # m/s^2
    max_decel_y: float = 0.0615  # m/s^2
    buffer: float = 0.0101  # m
    turn_gain: float = 0.854  # turn input per rad of heading error (approach-to-kick set)
    max_turn: float = 0.235  # largest turn input near the ball
    max_speed: float = 0.645  # largest sideways and backward inputs near the ball
    near: float = 0.245  # m from the kick pose: the approach-to-kick set within it
    around: float = 0.38  # m: radius of the circle round the ball (the path keeps about 2/3 of it)
    stage: float = 0.0977  # m behind the kick pose: where the go-to-target walk aims
    stop: float = 0.1  # fraction of the tolerance box that counts as lined up (creep, fix)
    creep: float = 0.236  # least forward input creeping up to the ball
    lead: float = 0.00103  # m: the creep stops this far short of the pose (walking estimate)
    settle: float = 0.5  # s standing before the pose is judged again
    lookahead: float = 0.115  # m: steering aims this far beyond the pose along the kick line
    fast_creep: float = 0.166  # m: creeping farther than this from the pose may use the go-to-target set
    fast: float = 0.669  # m: the go-to-target set only for a waypoint farther than this and ahead
    back: float = 0.0339  # m: backing off (too close, off to the side or turned) ends this far behind
    fix_turn_gain: float = 1.5  # turn input per rad of heading error fixing on the spot
    fix_max_turn: float = 0.379  # largest turn input fixing on the spot
    fix_time: float = 0.768  # s: longest burst of steps fixing a small error before looking again
    smooth: float = 0.02  # s: time constant of the low-passed error used to line up
    after_align: float = 1.5  # the kick's box grows by this factor once an align has moved the robot
    enter_turn: float = math.radians(25.0)  # rad: the creep takes over only within this heading error
    around_turn_gain: float = 1.0  # going round the ball: turn input per heading error to the ball / pi

    @classmethod
    def load(cls, paths: Iterable[PathLike] = (), robot_type: int | None = None) -> ApproachParams:
        """Shipped values (`approach_param_paths(robot_type)`), then `paths` (later override)."""
        values = load_params([*approach_param_paths(robot_type), *paths], APPROACH_SCHEMA, "approach_")
        return replace(cls(), **values)


def approach_param_paths(robot_type: int | None = None) -> list[str]:
    """The shipped approach files: ``approach.params`` (every type), then
    ``approach_type<T>.params`` where robot type T has its own values."""
    return with_type_file(DATA / "approach.params", robot_type)


# Names in parameter files (with the "approach_" prefix) and their file units.
APPROACH_SCHEMA = {"max_decel_x": "1", "max_decel_y": "1", "buffer": "mm", "turn_gain": "1",
                   "max_turn": "1", "max_speed": "1", "near": "m", "around": "m", "stage": "m", "stop": "1",
                   "creep": "1", "lead": "m", "settle": "s", "smooth": "s",
                   "lookahead": "m", "fix_time": "s", "fix_turn_gain": "1", "fix_max_turn": "1",
                   "back": "m", "fast": "m", "fast_creep": "m", "after_align": "1", "enter_turn": "deg",
                   "around_turn_gain": "1"}
assert set(APPROACH_SCHEMA) == {f.name for f in fields(ApproachParams)}


def kick_pose(ball: Sequence[float], target: Sequence[float], spec: KickSpec) -> tuple[float, float, float]:
    """Where to stand (x, y) and face (heading) so that `spec` sends `ball` toward `target`.

    All in the caller's ground frame (m, rad): the robot faces the kick
    direction minus the kick's own angle, and the ball lies at `spec.ball` in
    its frame.
    """
    bx, by = float(ball[0]), float(ball[1])
    heading = wrap(math.atan2(target[1] - by, target[0] - bx) - spec.direction)
    kx, ky = rotate(*spec.ball, heading)
    return bx - kx, by - ky, heading


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance (m) from point p to the segment a-b."""
    ab = b - a
    t = 0.0 if not ab.any() else float(np.clip(np.dot(p - a, ab) / np.dot(ab, ab), 0.0, 1.0))
    return float(np.linalg.norm(a + t * ab - p))


def ball_in_path(robot: Sequence[float], pose: Sequence[float], ball: Sequence[float],
                 clearance: float = BALL_CLEARANCE) -> bool:
    """True when walking straight from `robot` to `pose` passes within `clearance` (m)
    of the ball, leaving out the last `clearance` before the pose (the kick pose
    itself lies next to the ball)."""
    a, b, p = (np.asarray(v[:2], dtype=float) for v in (robot, pose, ball))
    ab = b - a
    length = float(np.linalg.norm(ab))
    if length <= clearance:
        return False
    b = a + ab * (1.0 - clearance / length)
    return _segment_distance(p, a, b) < clearance


def kick_cost(robot: Sequence[float], ball: Sequence[float], target: Sequence[float],
              spec: KickSpec) -> float:
    """UT's cost of moving to the kick pose: distance (m) + |turn| / 360 deg + ball penalty.

    robot: (x, y, heading) in the same ground frame as `ball` and `target`."""
    pose = kick_pose(ball, target, spec)
    dist = math.hypot(pose[0] - robot[0], pose[1] - robot[1])
    turn = abs(wrap(pose[2] - robot[2])) / (2.0 * math.pi)
    return dist + turn + (BALL_PENALTY if ball_in_path(robot, pose, ball) else 0.0)


def choose_kick(robot: Sequence[float], ball: Sequence[float], target: Sequence[float],
                specs: Iterable[KickSpec], current: str | None = None, keep: float = 0.05) -> KickSpec:
    """The kick of least `kick_cost` (ties: the first given).

    current: the kick chosen last time; it is kept unless another costs at
    least `keep` less, so noise does not make the robot switch feet back and forth."""
    specs = list(specs)
    if not specs:
        raise ValueError("choose_kick needs at least one kick")
    costs = [kick_cost(robot, ball, target, k) for k in specs]
    best = int(np.argmin(costs))
    for i, k in enumerate(specs):
        if k.name == current and costs[i] < costs[best] + keep:
            return k
    return specs[best]


def decel_speed(d: float, max_decel: float, buffer: float) -> float:
    """UT's approach speed (m/s, signed as `d`) with `d` (m) still to go along one axis."""
    a = abs(d)
    left = a if a > 2.0 * buffer else a - buffer
    return math.copysign(math.sqrt(2.0 * max_decel * max(left, 0.0)), d)


class ApproachMode(str, Enum):
    """What the approach does this cycle (`ApproachCommand.mode`; a `str` Enum, equal to
    and printed as its value).

    Away from the kick pose: WALK (to the staging point behind it) or AROUND (the
    ball). Near it, the states of `Approach.phase`: CREEP in; STOP, stand and judge
    the pose (then ready, ALIGN, BACK, CREEP or FIX); FIX a small error stepping on
    the spot (then STOP); BACK off (then CREEP). ALIGN: standing, the caller should
    move the robot by `error` with `skills.align` (then `Approach.aligned`: STOP)."""

    WALK = "walk"
    AROUND = "around"
    CREEP = "creep"
    STOP = "stop"
    FIX = "fix"
    BACK = "back"
    ALIGN = "align"

    __str__ = str.__str__
    __format__ = str.__format__


Mode = ApproachMode


@dataclass
class ApproachCommand:
    """Walk inputs in [-1, 1], the walk set to use, and whether the kick may start."""

    x: float
    y: float
    turn: float
    set_name: str
    ready: bool
    error: tuple[float, float, float]  # (dx m, dy m, dheading rad) to the kick pose, robot frame
    mode: ApproachMode = ApproachMode.CREEP


@dataclass(frozen=True)
class _Near:
    """One cycle near the kick pose, as the states see it (robot frame, m and rad)."""

    error: tuple[float, float, float]  # (dx, dy, dheading) to the pose
    smooth: tuple[float, float, float, float]  # low-passed (dx, dy, dheading, lateral error to the kick line)
    box: tuple[float, float, float]  # the kick's tolerance (wider after an align)
    inside: bool  # the pose and the ball within the box
    set_name: str  # the walk set near the ball
    standing: bool  # the walk stands still now

    def command(self, x: float, y: float, turn: float, mode: ApproachMode, ready: bool = False,
                set_name: str | None = None) -> ApproachCommand:
        return ApproachCommand(x, y, turn, set_name or self.set_name, ready, self.error, mode)


def _to_kick_frame(point: Sequence[float], ball: Sequence[float], heading: float) -> tuple[float, float]:
    """A ground point in the kick frame: origin at the ball, u along `heading`, v left (m)."""
    return Pose2(float(ball[0]), float(ball[1]), heading).to_local(float(point[0]), float(point[1]))


def _from_kick_frame(u: float, v: float, ball: Sequence[float], heading: float) -> tuple[float, float]:
    return Pose2(float(ball[0]), float(ball[1]), heading).to_world(u, v)


class Approach:
    """Walk inputs toward a kick pose, cycle by cycle.

    walk_sets: the robot's walk sets (`skills.walk.load_walk_sets`), for the
    speed each walk input means; dt: the control period (s).
    """

    def __init__(self, walk_sets: dict[str, WalkParams], params: ApproachParams | None = None,
                 dt: float = 0.02, align: AlignParams | None = None) -> None:
        self.sets = walk_sets
        self.params = params or ApproachParams.load()
        self.dt = dt
        self.align = align  # None: no "align" mode (the caller cannot play `skills.align.Align`)
        self._states = {Mode.STOP: self._stop, Mode.BACK: self._back, Mode.CREEP: self._creep,
                        Mode.FIX: self._fix}
        self.reset()

    def reset(self) -> None:
        """Forget the stop (after a fall, a lost ball or a new target)."""
        self.in_box = 0.0  # s spent standing after a stop
        self.phase = Mode.CREEP  # near the pose: CREEP, STOP, FIX (on the spot) or BACK
        self.smooth: np.ndarray | None = None  # low-passed (dx, dy, dheading, lateral) error near the pose
        self.fix_time = 0.0  # s spent in the current FIX
        self.near = False  # using the approach-to-kick rule (hysteresis on `near`)
        self.aligns = 0  # aligns played since the reset: after one, the box is `after_align` wider

    def aligned(self) -> None:
        """The caller's `skills.align.Align` has moved the robot: stand, then judge again,
        in a box `after_align` times the kick's: a second align costs about 4 s, and
        the first one's miss is within the align's and the vision's few-mm errors."""
        self.phase, self.in_box, self.smooth = Mode.STOP, 0.0, None
        self.aligns += 1

    def _max_speed(self, set_name: str) -> tuple[float, float]:
        """Speeds (m/s) that walk inputs x = 1 and y = 1 of a set give, about."""
        p = self.sets[set_name]
        return p.max_step_size_x / p.phase_length, p.max_step_size_y / p.phase_length

    def step(self, robot: Sequence[float], ball: Sequence[float], target: Sequence[float],
             spec: KickSpec, standing: bool = True) -> ApproachCommand:
        """One cycle: robot (x, y, heading), ball (x, y) and target (x, y) in one ground frame.

        standing: whether the walk stands still now (time in the box counts
        toward `ready` only then)."""
        p = self.params
        gx, gy, gh = kick_pose(ball, target, spec)
        rx, ry, rh = (float(v) for v in robot[:3])
        me = Pose2(rx, ry, rh)
        dx, dy = me.to_local(gx, gy)  # the pose in the robot frame
        dh = wrap(gh - rh)
        error = (dx, dy, dh)
        tx, ty, th = spec.tolerance
        if self.aligns:
            tx, ty, th = tx * p.after_align, ty * p.after_align, th * p.after_align
        ru, rv = _to_kick_frame((rx, ry), ball, gh)
        pu, pv = _to_kick_frame((gx, gy), ball, gh)
        dist = math.hypot(dx, dy)
        # Behind the pose, inside a cone opening backward from just behind it.
        behind = ru < pu + 0.02 and abs(rv - pv) <= max(0.05, (pu + 0.05 - ru) * math.tan(BEHIND_CONE))
        near_set = "approach_to_kick" if "approach_to_kick" in self.sets else "go_to_target"
        if self.near:  # stay near unless well away or round in front of the ball
            self.near = dist < p.near * 1.6 and ru < pu + 0.08 and abs(rv - pv) < 0.25
        else:
            self.near = dist < p.near and behind and abs(dh) < p.enter_turn
        if not self.near:
            self.in_box, self.phase, self.smooth = 0.0, Mode.CREEP, None
            return self._walk(robot, ball, (gx, gy, gh), (ru, rv), (pu, pv), behind, error)
        # Ready needs the robot on the pose and the ball where the kick wants it in
        # the robot frame (the two differ by the heading error times the distance).
        bx, by = me.to_local(float(ball[0]), float(ball[1]))
        kx, ky = bx - spec.ball[0], by - spec.ball[1]
        inside = max(abs(dx), abs(kx)) < tx and max(abs(dy), abs(ky)) < ty and abs(dh) < th
        # Walking, the torso sways and twists with every step: steering watches the
        # error low-passed over about a step (`smooth` s).
        raw = np.array([dx, dy, dh, rv - pv])
        if self.smooth is None or self.phase is Mode.STOP:
            self.smooth = raw
        else:
            a = self.dt / (p.smooth + self.dt)
            d = raw - self.smooth
            d[2] = wrap(float(d[2]))
            self.smooth = self.smooth + a * d
        fx, fy, fh, fe = (float(v) for v in self.smooth)
        near = _Near(error, (fx, fy, fh, fe), (tx, ty, th), inside, near_set, standing)
        while True:  # a state either answers or hands over to the next one within the cycle
            cmd = self._states[self.phase](near)
            if cmd is not None:
                return cmd

    # One method per state near the pose: each returns this cycle's command, or None
    # after switching `phase` to a state that answers in the same cycle.

    def _stop(self, n: _Near) -> ApproachCommand | None:
        """Standing: once settled, judge the pose on what is seen standing still."""
        p = self.params
        self.in_box = self.in_box + self.dt if n.standing else 0.0
        if self.in_box < p.settle:
            return n.command(0.0, 0.0, 0.0, Mode.STOP)
        if n.inside:  # judged on sightings taken while standing still
            return n.command(0.0, 0.0, 0.0, Mode.STOP, ready=True)
        # Not there: a small error is stepped off precisely, one foot at a time
        # (`skills.align`); otherwise walk on when short of it, back off when too
        # close or far off to the side, else fix the error stepping in place.
        self.in_box, self.fix_time = 0.0, 0.0
        if self.align is not None and self.align.fits(n.error):
            return n.command(0.0, 0.0, 0.0, Mode.ALIGN)
        dx, dy, dh = n.error
        tx, ty, th = n.box
        if dx < -tx or abs(dy) > 2.5 * ty or abs(dh) > th:
            self.phase = Mode.BACK  # turning on the spot is poor: turn walking in again
        elif dx > tx + 0.02 and abs(dy) < 2.0 * ty:
            self.phase = Mode.CREEP
        else:
            self.phase = Mode.FIX
        return None

    def _back(self, n: _Near) -> ApproachCommand | None:
        """Backing off until `back` behind the pose, then creeping in again."""
        if n.smooth[0] > self.params.back:
            self.phase = Mode.CREEP
            return None
        return self._steer(n, backing=True)

    def _creep(self, n: _Near) -> ApproachCommand:
        """Creeping in; at the pose (or close enough for the align) stop and look again."""
        p, a = self.params, self.align
        fx, fy, fh, _ = n.smooth
        close = a is not None and fx < 0.5 * a.max_move and abs(fy) < 0.5 * a.max_move \
            and abs(fh) < 0.5 * a.max_turn  # the align steps off the rest more precisely
        if n.error[0] < p.lead or close:
            self.phase, self.in_box = Mode.STOP, 0.0
            return n.command(0.0, 0.0, 0.0, Mode.STOP)
        return self._steer(n, backing=False)

    def _fix(self, n: _Near) -> ApproachCommand:
        """A small error fixed stepping on the spot, for at most `fix_time`, then stop."""
        p = self.params
        fx, fy, fh, _ = n.smooth
        tx, ty, th = n.box
        self.fix_time += self.dt
        if (abs(fx) < p.stop * tx and abs(fy) < p.stop * ty and abs(fh) < p.stop * th) \
                or self.fix_time > p.fix_time:
            self.phase, self.in_box = Mode.STOP, 0.0
            return n.command(0.0, 0.0, 0.0, Mode.STOP)
        vx_max, vy_max = self._max_speed(n.set_name)
        x = 0.0 if abs(fx) < p.stop * tx else decel_speed(fx, p.max_decel_x, p.buffer) / vx_max
        y = 0.0 if abs(fy) < p.stop * ty else decel_speed(fy, p.max_decel_y, p.buffer) / vy_max
        turn = float(np.clip(p.fix_turn_gain * fh, -p.fix_max_turn, p.fix_max_turn))
        turn = 0.0 if abs(fh) < p.stop * th else turn
        lim = p.max_speed
        x, y = float(np.clip(x, -0.5 * lim, 0.5 * lim)), float(np.clip(y, -lim, lim))
        return n.command(x, y, turn, Mode.FIX)

    def _steer(self, n: _Near, backing: bool) -> ApproachCommand:
        """Creeping or backing: steer like a car onto the kick line (lateral error fe, m)
        with sideways steps; the heading comes round to the kick's as the line is
        reached, and in the last few cm only sideways steps correct."""
        p = self.params
        fx, fy, fh, fe = n.smooth
        ty = n.box[1]
        vx_max, vy_max = self._max_speed(n.set_name)
        ahead = max(fx, 0.0) + p.lookahead
        steer = min(1.0, max(0.0, (fx - 0.05) / 0.1))
        want = fh + steer * math.atan2(-fe, ahead)
        turn = float(np.clip(p.turn_gain * want, -p.max_turn, p.max_turn))
        y = decel_speed(fy, p.max_decel_y, p.buffer) / vy_max if abs(fy) > p.stop * ty else 0.0
        y = float(np.clip(y, -p.max_speed, p.max_speed)) * (1.0 - 0.5 * steer)
        set_name = n.set_name
        if backing:  # backward and sideways at once trips this walk
            x = -p.max_speed
            y = float(np.clip(y, -0.3 * p.max_speed, 0.3 * p.max_speed))
            turn = float(np.clip(turn, -0.5 * p.max_turn, 0.5 * p.max_turn))
        else:
            if fx > p.fast_creep and abs(want) < math.radians(20.0) and abs(fy) < 0.05:
                set_name = "go_to_target"  # still well short and lined up: longer steps
                vx_max = self._max_speed(set_name)[0]
            x = max(decel_speed(n.error[0] - p.lead, p.max_decel_x, p.buffer) / vx_max, p.creep)
        # Steps shrink while the heading is far off (rough steps sway the body).
        scale = max(0.0, 1.0 - abs(want) / math.radians(45.0))
        x = float(np.clip(x, -p.max_speed, scale))
        return n.command(x, y, turn, self.phase, set_name=set_name)

    def _walk(self, robot: Sequence[float], ball: Sequence[float], pose: tuple[float, float, float],
              r: tuple[float, float], g: tuple[float, float], behind: bool,
              error: tuple[float, float, float]) -> ApproachCommand:
        """Go-to-target walk to the staging point behind the pose, or round the ball."""
        p = self.params
        wu, wv, mode = self.waypoint(r, g, behind)
        if mode is Mode.WALK and abs(error[2]) >= p.enter_turn:  # turned far off: turn at the staging point
            wu, wv = g[0] - p.stage, g[1]
        wx, wy = _from_kick_frame(wu, wv, ball, pose[2])
        rx, ry, rh = (float(v) for v in robot[:3])
        wdx, wdy = Pose2(rx, ry, rh).to_local(wx, wy)
        dw = math.hypot(wdx, wdy)
        # The fast go-to-target set only for walking on ahead; turning, stepping
        # sideways and going round the ball with the steadier approach-to-kick set.
        fast = mode is Mode.WALK and dw > p.fast and abs(math.atan2(wdy, wdx)) < math.radians(35.0)
        set_name = "go_to_target" if fast or "approach_to_kick" not in self.sets else "approach_to_kick"
        if mode is Mode.AROUND:  # step toward the waypoint, always turning to face the ball
            face: float | None = wrap(math.atan2(float(ball[1]) - ry, float(ball[0]) - rx) - rh)
            beyond, gain = math.inf, p.around_turn_gain
        else:  # to the staging point facing it; near it, turn to the kick's heading
            face = wrap(pose[2] - rh) if dw < 0.3 else None
            beyond, gain = 0.3, 1.0
        x, y, turn = walk_toward(wdx, wdy, face, self.sets[set_name], brake=0.3, face_beyond=beyond,
                                 turn_gain=gain)
        return ApproachCommand(x, y, turn, set_name, False, error, mode)

    def waypoint(self, r: tuple[float, float], g: tuple[float, float], behind: bool
                 ) -> tuple[float, float, ApproachMode]:
        """The next waypoint (u, v) in the kick frame (origin at the ball, u along the
        kick heading) for the robot at `r` going to the pose at `g`, and the mode.

        Behind the pose (or with a clear way to the staging point `stage` behind
        it) the waypoint is the staging point; otherwise, from afar, the point
        where a straight path touches the circle of radius `around` round the ball
        on the robot's side, and on the circle a point on it at most 50 deg
        further round toward the back. Aimed at points on the circle, the path
        cuts inside it, to about two thirds of `around` from the ball (0.27-0.34 m at
        0.38 for the points of the tests; the walking robot, turning late, comes to
        0.2 m and nearer): `around` was tuned so."""
        p = self.params
        ru, rv = r
        pu, pv = g
        su, sv = pu - p.stage, pv
        if behind:
            return (pu, pv, Mode.WALK) if math.hypot(ru - pu, rv - pv) < p.near else (su, sv, Mode.WALK)
        if not ball_in_path((ru, rv), (su, sv), (0.0, 0.0), clearance=p.around * 0.8) \
                and ru < su + 0.05:
            return su, sv, Mode.WALK
        angle = math.atan2(rv, ru)  # the robot round the ball; pi (or -pi) is behind it
        side = 1.0 if rv >= 0.0 else -1.0
        goal = side * math.pi
        dist = math.hypot(ru, rv)
        if dist > p.around + 0.1:  # still off the circle: to where the path touches it
            tangent = angle + side * math.acos(p.around / dist)
            if side * (goal - tangent) <= 0.0:
                return su, sv, Mode.WALK
            return p.around * math.cos(tangent), p.around * math.sin(tangent), Mode.AROUND
        step = math.radians(50.0)
        nxt = angle + side * step if abs(goal - angle) > step else goal
        radius = max(p.around, min(math.hypot(ru, rv), p.around + 0.2))
        wu, wv = radius * math.cos(nxt), radius * math.sin(nxt)
        if abs(goal - angle) <= step:  # almost behind: straight to the staging point
            return su, sv, Mode.WALK
        return wu, wv, Mode.AROUND


__all__ = ["APPROACH_SCHEMA", "Approach", "ApproachCommand", "ApproachMode", "ApproachParams",
           "approach_param_paths", "ball_in_path", "choose_kick", "decel_speed", "kick_cost", "kick_pose"]

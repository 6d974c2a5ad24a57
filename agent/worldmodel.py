"""The agent's picture of the world, built only from its percepts (dissertation 8.2.1).

Every object that can ever be seen - the eight flags and posts, the ball, up to
eleven teammates and eleven opponents - is a `WorldObject` with its last
known position (team frame), when it was last seen, whether it is seen now,
and whether the memory is still valid: an object that should be in view at
its remembered place but is not seen there is no longer valid. Unseen objects
stay where they were last seen; teammates' messages update them too.

Per cycle `update(percept, odometry)`: IMU tilt and fall flag; odometry into
the particle filter; the ball filter's prediction; on vision frames (unless
fallen) the observations moved into the level frame, the particle filter's
update, and every seen object placed on the field with the new pose estimate;
then the heard messages. `message()` / `say()` give what to say in this
player's time slot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from agent import _kernels, comm
from agent.ballfilter import BallFilter
from agent.geometry import landmarks_in_team
from agent.localization import LocalizationParams, ParticleFilter
from agent.perception import Observation, observe
from models.geometry import Pose2, wrap
from models.messages import SEEN_PARTS, Percept
from models.rules import CYCLE, TEAM_SIZE, VIEW_CONE
from skills.imu import TiltEstimator

NOT_LOCALIZED_AFTER = 3.0  # s without a landmark or line before the robot calls itself lost
LOST_SPREAD = 1.0  # m of particle spread that also counts as lost
BALL_SIGMA_NEAR = 0.02  # m, own ball sighting at 0 m ...
BALL_SIGMA_PER_M = 0.01  # ... plus this per m of distance
HEARD_BALL_SIGMA = 0.4  # m, a teammate's ball report
PLAYER_MEMORY = 4.0  # s a player sighting is reported on to teammates
_PART = {n: i for i, n in enumerate(SEEN_PARTS)}
_HEAD = _PART["head"]
_HEADING_PAIRS = np.array([(_PART["llowerarm"], _PART["rlowerarm"]), (_PART["lfoot"], _PART["rfoot"])])
_HALF_CONE = VIEW_CONE / 2 - math.radians(5.0)  # margin for "should have been seen"
_NO_BALL = np.empty((0, 3))


def player_key(ours: bool, unum: int) -> str:
    """The `WorldModel.objects` key of a player: "T<unum>" for a teammate, "O<unum>" for an opponent."""
    return f"{'T' if ours else 'O'}{unum}"


_decoded: dict[tuple[str, float], comm.TeamMessage | None] = {}


def _decode_heard(heard) -> comm.TeamMessage | None:
    """`comm.decode_heard`, remembered for the messages of the latest time heard: every
    teammate hears the same text, and decoding is a pure function of it and its time
    (the messages are frozen), so one decode serves the team (in this process)."""
    if heard.team != "ours":
        return None
    key = (heard.text, heard.time)
    if key not in _decoded:
        if len(_decoded) > 64:
            _decoded.clear()
        _decoded[key] = comm.decode(heard.text, heard.time)
    return _decoded[key]


@dataclass
class WorldObject:
    """One object's memory. Positions are in the team frame (m); heading in rad."""

    name: str
    position: np.ndarray = field(default_factory=lambda: np.full(3, np.nan))
    vision: np.ndarray | None = None  # last polar reading (camera frame)
    heading: float = math.nan  # robots only
    last_seen: float = -math.inf  # s, by this robot's eyes
    last_heard: float = -math.inf  # s, from a teammate
    currently_seen: bool = False  # in the latest vision frame
    valid: bool = False
    fallen: bool = False  # robots: seen or reported fallen

    @property
    def known(self) -> bool:
        return math.isfinite(self.position[0])


class WorldModel:
    """World model of one player (`side` 'L'/'R', uniform number `unum`)."""

    def __init__(self, side: str, unum: int, seed: int = 0,
                 params: LocalizationParams | None = None) -> None:
        self.side = side
        self.unum = unum
        self.time = -math.inf
        # Vision is levelled by this estimate: it turns by the whole gyro (`exact`) and takes
        # 5 % of the accelerometer's answer a cycle, enough to correct the gyro's drift (the
        # accelerometer is the cycle's mean, unbiased by foot strikes). A fall the gyro did
        # not see is flagged about 0.6 s later.
        self.tilt = TiltEstimator(blend=0.05, exact=True)
        self.localizer = ParticleFilter(side, seed=seed, params=params)
        self.ball_filter = BallFilter()
        self.landmark_positions = landmarks_in_team(side)
        self._landmark_z = {n: float(p[2]) for n, p in self.landmark_positions.items()}
        self._heights: dict[tuple[str, ...], np.ndarray] = {}
        self.objects: dict[str, WorldObject] = {}
        for name, pos in self.landmark_positions.items():
            self.objects[name] = WorldObject(name, position=pos.copy(), valid=True)
        self.objects["ball"] = WorldObject("ball")
        for u in range(1, TEAM_SIZE + 1):
            for ours in (True, False):
                self.objects[player_key(ours, u)] = WorldObject(player_key(ours, u))
        # The players' memories, uniform number u at index u - 1 (this player's own included).
        self.teammates = tuple(self.objects[player_key(True, u)] for u in range(1, TEAM_SIZE + 1))
        self.opponents = tuple(self.objects[player_key(False, u)] for u in range(1, TEAM_SIZE + 1))
        # Other robots' memories by `_kernels.place_robots` slot: ours by uniform number, then
        # theirs (None for this player).
        self._robot_slots = [None if ours and u == unum else self.objects[player_key(ours, u)]
                             for ours in (True, False) for u in range(1, TEAM_SIZE + 1)]
        self._movable = [o for n, o in self.objects.items() if n not in self.landmark_positions]
        self._seen_now: list[WorldObject] = []  # the objects whose currently_seen is set
        self.last_fixed_seen = -math.inf  # s, last vision frame with a landmark or line
        self.torso_height = 0.36  # m, re-estimated from landmarks and lines
        self.observation: Observation | None = None
        self.heard: list[comm.TeamMessage] = []  # decoded teammates' messages this cycle
        self.teammate_lost: dict[int, float] = {}  # unum -> time it said it was not localized
        self.relocalized_by_teammate = -math.inf

    # ------------------------------------------------------------------ state

    @property
    def pose(self) -> np.ndarray:
        """Own (x, y, heading) in the team frame (m, m, rad)."""
        return self.localizer.pose

    @property
    def fallen(self) -> bool:
        """True while the accelerometer says the torso lies (see `skills.imu`)."""
        return self.tilt.fallen

    @property
    def not_localized(self) -> bool:
        """True when no landmark or line was seen for NOT_LOCALIZED_AFTER s, or the
        particles are spread over more than LOST_SPREAD m."""
        return (self.time - self.last_fixed_seen > NOT_LOCALIZED_AFTER
                or self.localizer.spread > LOST_SPREAD)

    @property
    def ball(self) -> WorldObject:
        """The ball's memory; its position is the ball filter's estimate."""
        return self.objects["ball"]

    def teammate(self, unum: int) -> WorldObject:
        return self.teammates[unum - 1] if 0 < unum <= TEAM_SIZE else self.objects[player_key(True, unum)]

    def opponent(self, unum: int) -> WorldObject:
        return self.opponents[unum - 1] if 0 < unum <= TEAM_SIZE else self.objects[player_key(False, unum)]

    def to_field(self, level_xyz: np.ndarray) -> np.ndarray:
        """Level-frame points (..., 3) relative to the torso -> team frame (m)."""
        p = np.asarray(level_xyz, dtype=float)
        out = np.empty(p.shape)
        out[..., 0], out[..., 1] = self._pose2().to_world(p[..., 0], p[..., 1])
        out[..., 2] = self.torso_height + p[..., 2]
        return out

    def to_level(self, xyz: np.ndarray) -> np.ndarray:
        """Team-frame points (..., 3) -> level frame relative to the torso (m)."""
        p = np.asarray(xyz, dtype=float)
        out = np.empty(p.shape)
        out[..., 0], out[..., 1] = self._pose2().to_local(p[..., 0], p[..., 1])
        out[..., 2] = p[..., 2] - self.torso_height
        return out

    def _pose2(self) -> Pose2:
        x, y, t = (float(v) for v in self.pose)
        return Pose2(x, y, t)

    def ball_relative(self) -> tuple[float, float] | None:
        """(bearing rad in the torso's yaw, ground distance m) of the ball estimate, if any."""
        if not self.ball_filter.initialized:
            return None
        bx, by = self.ball_filter.x[:2].tolist()
        x, y, t = self.pose.tolist()
        return float(wrap(math.atan2(by - y, bx - x) - t)), math.hypot(bx - x, by - y)

    # ----------------------------------------------------------------- update

    def beamed(self, x: float, y: float, heading: float) -> None:
        """Tell the localizer about a beam to (x, y, heading) (team frame)."""
        self.localizer.reset_around(x, y, heading, sigma_xy=0.1, sigma_theta=0.2, fraction=0.8)

    def update(self, percept: Percept, odometry: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Fold one cycle's percept in; odometry is the walk's (dx, dy, dtheta) since the
        last cycle (m, m, rad; torso frame)."""
        dt = CYCLE if not math.isfinite(self.time) else max(0.0, percept.time - self.time)
        self.time = percept.time
        self.tilt.update(percept.gyro, percept.accel, dt)
        self.localizer.predict(*odometry)
        if self.ball_filter.initialized:
            self.ball_filter.predict(dt)
        if percept.vision is not None:
            for obj in self._seen_now:
                obj.currently_seen = False
            self._seen_now = []
            if not self.tilt.fallen:  # a falling or lying camera misleads more than it tells
                self._see(percept)
        self._hear(percept)
        if self.ball_filter.initialized:
            b = self.ball
            x, y = self.ball_filter.x[:2].tolist()
            b.position = np.array((x, y, b.position[2] if b.known else 0.042))

    def _see(self, percept: Percept) -> None:
        obs = observe(percept.vision, percept.time, float(percept.joints[0]), float(percept.joints[1]),
                      tilt=(self.tilt.roll, self.tilt.pitch))
        self.observation = obs
        if self.localizer.update(obs.landmark_names, obs.landmarks, obs.lines):
            self.last_fixed_seen = percept.time
        # Torso height from landmarks and lines of known height, then ball and robots placed
        # with it, in one kernel.
        x, y, h = self.pose.tolist()
        seen = _kernels.place_seen(
            self._landmark_heights(obs.landmark_names), obs.landmarks, obs.lines,
            _NO_BALL if obs.ball is None else obs.ball[None], obs.players, obs.player_ours, obs.player_unum,
            obs.player_part, x, y, h, self.torso_height, self.unum, TEAM_SIZE, len(SEEN_PARTS), _HEAD,
            _HEADING_PAIRS)
        self.torso_height, *_, dist = seen[0, :5].tolist()
        t = percept.time
        v = percept.vision
        seen_now = self._seen_now
        for name, pol in zip(v.landmark_names, v.landmarks):
            o = self.objects.get(name)
            if o is not None:
                o.vision, o.last_seen, o.currently_seen = pol, t, True
                seen_now.append(o)
        if obs.ball is not None:
            pos = seen[0, 1:4]
            self.ball_filter.update(pos[:2], BALL_SIGMA_NEAR + BALL_SIGMA_PER_M * dist, t)
            b = self.ball
            b.position, b.vision, b.last_seen, b.currently_seen, b.valid = pos, v.ball, t, True, True
            seen_now.append(b)
        if len(obs.players):
            self._see_players(seen[1:], t)
        self._invalidate(obs)

    def _landmark_heights(self, names: tuple[str, ...]) -> np.ndarray:
        """Heights (m) of the named landmarks (nan: not a landmark), one array per name set."""
        z = self._heights.get(names)
        if z is None:
            if len(self._heights) > 256:
                self._heights.clear()
            z = self._heights[names] = np.array([self._landmark_z.get(n, math.nan) for n in names])
        return z

    def _see_players(self, seen: np.ndarray, t: float) -> None:
        """Robots' memories from `_kernels.place_robots` rows (one per robot seen at time t)."""
        robots = self._robot_slots
        for p, v, (hd, down, r) in zip(seen[:, 0:3], seen[:, 3:6], seen[:, 6:9].tolist()):
            o = robots[int(r)]
            o.position, o.vision, o.fallen = p, v, down > 0.0
            if hd == hd:  # not nan: a pair of parts gave the heading
                o.heading = hd
            o.last_seen, o.currently_seen, o.valid = t, True, True
            self._seen_now.append(o)

    def _invalidate(self, obs: Observation) -> None:
        """Mark unseen ball and robots whose remembered place is in view as not valid."""
        # `o.known` spelled out (a position is NaN until known): this runs every vision frame
        movable = [o for o in self._movable
                   if o.valid and not o.currently_seen and math.isfinite(o.position[0])]
        if not movable:
            return
        x, y, h = self.pose.tolist()
        inside = _kernels.in_view(np.array([o.position for o in movable]), x, y, h, self.torso_height,
                                  obs.camera_position, obs.camera_rotation, _HALF_CONE)
        for i, o in enumerate(movable):
            if inside >> i & 1:
                o.valid = False

    # ---------------------------------------------------------- communication

    def _hear(self, percept: Percept) -> None:
        self.heard = []
        for h in percept.heard:
            msg = _decode_heard(h) if h.team == "ours" else None
            if msg is None or msg.unum == self.unum:
                continue
            self.heard.append(msg)
            t = msg.time
            mate = self.teammate(msg.unum)
            ball = self.ball
            if not msg.not_localized and not mate.currently_seen:
                mate.position = np.array([msg.x, msg.y, 0.0])
                mate.heading, mate.valid = msg.heading, True
            mate.last_heard = t
            mate.fallen = msg.fallen
            if msg.not_localized:
                self.teammate_lost[msg.unum] = t
            else:
                self.teammate_lost.pop(msg.unum, None)
            if msg.ball is not None and not ball.currently_seen and percept.time - ball.last_seen > 0.5:
                self.ball_filter.update(np.array(msg.ball), HEARD_BALL_SIGMA, percept.time)
                ball.valid = True
                ball.last_heard = t
            for r in msg.teammates:
                if r.unum == self.unum:
                    if self.not_localized:
                        self.localizer.reset_around(r.x, r.y, r.heading, sigma_xy=0.25, sigma_theta=0.3,
                                                    fraction=0.5)
                        self.relocalized_by_teammate = percept.time
                    continue
                o = self.teammate(r.unum)
                if not o.currently_seen:
                    o.position = np.array([r.x, r.y, 0.0])
                    o.heading, o.last_heard, o.valid = r.heading, t, True
            for r in msg.opponents:
                o = self.opponent(r.unum)
                if not o.currently_seen and t - o.last_seen > 0.5:
                    o.position = np.array([r.x, r.y, 0.0])
                    o.heading, o.last_heard, o.valid, o.fallen = r.heading, t, True, r.fallen

    def message(self, robot_type: int | None = None, role_vote: tuple[int, ...] | None = None,
                kick: comm.KickTarget | None = None) -> comm.TeamMessage:
        """What this player would say now (Table 8.1), most important reports first: where
        it sees teammates that said they are lost, then other teammates and opponents it
        sees."""
        x, y, h = self.pose
        ball = None
        if self.ball.currently_seen or self.time - self.ball.last_seen < 0.2:
            bx, by = self.ball_filter.position
            ball = (float(bx), float(by))
        mates, opps = [], []
        lost = sorted(self.teammate_lost, key=lambda u: -self.teammate_lost[u])
        for u in lost + [u for u in range(1, TEAM_SIZE + 1) if u not in self.teammate_lost]:
            o = self.teammate(u)
            recent = self.time - o.last_seen < (0.5 if u in lost else PLAYER_MEMORY)
            if u != self.unum and o.known and recent and math.isfinite(o.heading):
                mates.append(comm.PlayerReport(u, float(o.position[0]), float(o.position[1]), o.heading))
        for u in range(1, TEAM_SIZE + 1):
            o = self.opponent(u)
            if o.known and self.time - o.last_seen < PLAYER_MEMORY:
                hd = o.heading if math.isfinite(o.heading) else 0.0
                opps.append(comm.PlayerReport(u, float(o.position[0]), float(o.position[1]), hd, o.fallen))
        return comm.TeamMessage(
            unum=self.unum, x=float(x), y=float(y), heading=float(h), ball=ball, fallen=self.fallen,
            not_localized=self.not_localized, role_vote=role_vote, kick=kick,
            teammates=tuple(mates), opponents=tuple(opps), robot_type=robot_type, time=self.time)

    def say(self, robot_type: int | None = None, **kwargs) -> str | None:
        """The say text for this cycle if it is this player's time slot, else None."""
        if not comm.may_speak(self.unum, self.time):
            return None
        return comm.encode(self.message(robot_type=robot_type, **kwargs))

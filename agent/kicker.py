"""Go to the ball and kick it toward a target, from percepts alone.

The behavior of a lone striker (and of the kick benchmark and kick training
tasks): it sees the ball through vision percepts (`agent.perception.observe`,
every third cycle), keeps it in a dead-reckoning frame (`skills.navigate.Odometry`
fed with the walk's odometry), chooses the kick of least cost
(`skills.approach.choose_kick`), walks to the kick pose (`skills.approach.Approach`)
and plays the kick (`skills.kicks.KickSkill`) through `skills.motion.Motion`.
A fall is recovered by the getups, after which it approaches again.

Frames: the dead-reckoning frame is the ground frame in which the caller
places the robot at `start` (for example its beam pose in the field frame);
the ball and the kick target are kept in it (m, rad).

What it knows comes from percepts only: the heading from the gyro, pulled
toward what seen flags and goal posts say (when `start` is given in the team
frame); x/y from the walk's odometry, corrected the same way; the torso's tilt
for vision from the leg kinematics with the loaded sole flat (the IMU estimate
wobbles with every step); the ball averaged over sightings, plainly while
standing. Near the ball the approach steers where the torso will stand once
the walk stops (`stance_pose`), and a stop comes at the next change of support
instead of after the walk's half second of stepping in place. The getup
machinery takes over only when the fused tilt estimate leans beyond `LEAN`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import Enum

import numpy as np

from agent.geometry import landmarks_in_team
from agent.perception import Observation, observe
from models.geometry import Pose2, rotate, wrap
from models.messages import Percept
from models.rules import CYCLE
from skills.align import Align
from skills.approach import Approach, ApproachCommand, ApproachMode, ApproachParams, choose_kick
from skills.imu import TiltEstimator
from skills.kicks import KickSkill
from skills.motion import Motion
from skills.navigate import Odometry
from skills.walk import DATA as WALK_DATA
from skills.walk import WalkEngine, WalkParams, load_walk_sets

HEAD_PITCH = -0.6  # rad: looking down enough to see the ball at the feet
SMOOTHING = 0.3  # weight of a new ball sighting in the kept estimate while walking
STILL_WEIGHT = 0.1  # least weight of a new sighting while standing still
LOST = 4.0  # s without a sighting before the robot turns to look for the ball
LEAN = math.radians(40.0)  # torso tilt (rad) beyond which the getup machinery takes over
SOLE_FORCE = 10.0  # N under a sole before it counts as flat on the ground
LANDMARK_GAIN = 0.2  # share of a landmark fix taken into the dead-reckoned pose per vision frame
LANDMARK_GATE = math.radians(30.0)  # heading fixes farther off than this are ignored
LANDMARK_GATE_M = 1.0  # m: pose fixes farther than this from the dead-reckoned position are ignored
# Joint gains (kp 1/s, feed-forward factor) of the kicks, the align and the stand before a
# kick, whatever walk set ran last: the kicks were tuned at walk_defaults.txt's joint_kp,
# and at a softer walk's gain (type 3's) they fall short.
SKILL_GAINS = (load_walk_sets([WALK_DATA / "walk_defaults.txt"])["go_to_target"].joint_kp, 1.0)



class KickerState(str, Enum):
    """What the Kicker does (a `str` Enum, equal to and printed as its value).

    APPROACH the ball (then KICK when the approach says ready, ALIGN when it hands
    over a small error); ALIGN, step the error off (then APPROACH); KICK (then DONE);
    DONE, hold the kick's last pose; WATCH, stand watching the ball until `kick_now`
    (then KICK). A fall in KICK or ALIGN goes back to APPROACH."""

    APPROACH = "approach"
    KICK = "kick"
    DONE = "done"
    WATCH = "watch"
    ALIGN = "align"

    __str__ = str.__str__
    __format__ = str.__format__


APPROACH, KICK, DONE, WATCH, ALIGN = (KickerState.APPROACH, KickerState.KICK, KickerState.DONE,
                                      KickerState.WATCH, KickerState.ALIGN)


@dataclass
class BallMemory:
    """The ball (x, y) in the dead-reckoning frame (m), smoothed over sightings, and when
    it was last seen (s, server time).

    While walking a new sighting weighs `SMOOTHING` (the torso sways and the
    tilt estimate wobbles); while the robot stands still the estimate is the
    plain mean of the sightings since it stopped (`still` counts them).
    """

    position: np.ndarray | None = None
    seen_at: float = -math.inf
    still: int = 0  # sightings averaged since the robot last stood still

    def see(self, obs: Observation | None, odo: Odometry, standing: bool = False) -> None:
        """One cycle: `obs` is this cycle's vision in the level frame (None without vision)."""
        if not standing:
            self.still = 0
        if obs is None or obs.ball is None:
            return
        bx, by = float(obs.ball[0]), float(obs.ball[1])
        seen = np.array(odo.pose.to_world(bx, by))
        fresh = self.position is None or obs.time - self.seen_at > 1.0
        if standing:
            self.still += 1
            weight = max(1.0 / self.still, STILL_WEIGHT)
        else:
            weight = SMOOTHING
        self.position = seen if fresh else self.position + weight * (seen - self.position)
        self.seen_at = obs.time


class Kicker:
    """Approach and kick toward a target, cycle by cycle (`act` returns joint velocities).

    kicks: the kicks it may choose from, by name; walk_sets: the walk sets
    (default: the robot type's shipped ones); approach: the approach's parameters
    (default: the type's shipped ones, `skills.approach.approach_param_paths`).
    """

    def __init__(self, robot_type: int, kicks: Mapping[str, KickSkill],
                 walk_sets: Mapping[str, WalkParams] | None = None,
                 approach: ApproachParams | None = None) -> None:
        if not kicks:
            raise ValueError("Kicker needs at least one kick")
        engine = WalkEngine(robot_type, dict(walk_sets)) if walk_sets else WalkEngine(robot_type)
        self.motion = Motion(robot_type, engine)
        self.kicks = dict(kicks)
        self.align = Align(robot_type, kin=engine.kin)
        self.approach = Approach(engine.sets, approach or ApproachParams.load(robot_type=robot_type),
                                 align=self.align.params)
        self._align_start = (0.0, 0.0, 0.0)  # dead-reckoned pose where the align began
        self.odo = Odometry()
        self.ball = BallMemory()
        self.target = (0.0, 0.0)
        self.state = APPROACH
        self.kick: KickSkill | None = None  # the kick chosen (or playing)
        self.kick_started: float | None = None  # s, server time the kick began
        self._final: np.ndarray | None = None  # the finished kick's last targets (held while DONE)
        self.last: ApproachCommand | None = None
        self.tilt = TiltEstimator()  # its own, updated every cycle (the walk's only while walking)
        self.use_landmarks = True
        self._set = "go_to_target"  # the walk set in use
        self._recovering = False  # a getup (or the stand after it) has the body
        self._landmarks: dict[str, np.ndarray] | None = None
        self._states = {APPROACH: self._approach, ALIGN: self._aligning, KICK: self._kicking,
                        DONE: self._standing_by, WATCH: self._standing_by}

    def start(self, pose: tuple[float, float, float], target: tuple[float, float],
              landmarks: bool = True, approach: bool = True) -> None:
        """Begin: the robot stands at `pose` (x, y, heading) and should kick toward `target`.

        landmarks: the pose and target are in the robot's team frame (the field
        frame for the left team), so seen flags and goal posts correct the
        dead-reckoned heading and position; False for any other frame.
        approach: False to stand still watching the ball (state WATCH) until
        `kick_now`, for a robot already placed behind the ball."""
        self.odo = Odometry(*pose)
        self.use_landmarks = landmarks
        self.ball = BallMemory()
        self.target = (float(target[0]), float(target[1]))
        self.state = APPROACH if approach else WATCH
        self.kick = None
        self.kick_started = None
        self._final = None
        self.approach.reset()
        self.motion.reset()

    def kick_now(self, percept: Percept) -> bool:
        """Start the kick of least cost from where the robot stands, if it has seen the
        ball; returns whether it started (the kick plays from the next `act`)."""
        if self.ball.position is None or self.state == KICK:
            return False
        spec = choose_kick(self.pose, self.ball.position, self.target, [k.spec for k in self.kicks.values()])
        self.kick = self.kicks[spec.name]
        self.state = KICK
        self.kick_started = percept.time
        self.kick.reset(self.ball_relative(), self.motion.held_target)
        return True

    @property
    def pose(self) -> tuple[float, float, float]:
        """Dead-reckoned (x, y, heading) (m, rad)."""
        return self.odo.x, self.odo.y, self.odo.heading

    def ball_relative(self) -> tuple[float, float] | None:
        """The remembered ball in the robot frame (m), if any."""
        if self.ball.position is None:
            return None
        return self.odo.relative(*self.ball.position)

    def act(self, percept: Percept) -> np.ndarray:
        """Joint velocities (rad/s, league order) for this cycle."""
        self.tilt.update(percept.gyro, percept.accel, CYCLE)
        self._turned(percept)
        last = self.motion.last
        standing = self.state not in (KICK, ALIGN) and last is not None and last.standing
        obs = None
        if percept.vision is not None:
            obs = observe(percept.vision, percept.time, float(percept.joints[0]), float(percept.joints[1]),
                          self._level(percept))
            if self.use_landmarks and not self._recovering:  # lying, the level frame is a guess
                self.landmark_fix(obs, percept.side)
        self.ball.see(obs, self.odo, standing)
        # The getup machinery only once the fused tilt estimate says the torso leans
        # far (its fall detector alone reads the accelerometer, which the walk's
        # footfalls shake), and then until it hands the body back.
        leaning = max(abs(self.tilt.pitch), abs(self.tilt.roll)) > LEAN
        v = self.motion.recover(percept) if leaning or self._recovering else None
        self._recovering = v is not None
        if v is not None:  # down or getting up: start the approach over afterwards
            if self.state in (KICK, ALIGN):
                self.state = APPROACH
            self.approach.reset()
            return v
        return self._states[self.state](percept)

    # One method per state: this cycle's joint velocities (each may switch `state`).

    def _kicking(self, percept: Percept) -> np.ndarray:
        """The kick plays; when it ends, DONE holds its last pose."""
        assert self.kick is not None
        target = self.kick.step(percept)
        if not self.kick.done:
            return self._skill_command(target, percept)
        self.state = DONE
        self._final = target.copy()
        return self._standing_by(percept)

    def _standing_by(self, percept: Percept) -> np.ndarray:
        """DONE and WATCH: stand still."""
        if self._final is not None:  # after a kick: hold its last (standing) pose; the walk's
            return self._skill_command(self._final, percept)  # stop-jog tips robots over
        return self._walk(percept, 0.0, 0.0, 0.0, kp=SKILL_GAINS[0])  # the stand a kick starts from

    def _head(self, percept: Percept) -> np.ndarray:
        rel = self.ball_relative()
        yaw = 0.0 if rel is None else max(-1.0, min(1.0, math.atan2(rel[1], rel[0])))
        return np.array([yaw, HEAD_PITCH])

    def _walk(self, percept: Percept, x: float, y: float, turn: float,
              set_name: str = "go_to_target", kp: float | None = None) -> np.ndarray:
        walk = self.motion.walk
        if set_name != self._set and walk.walking and not walk.step_begins():
            set_name = self._set  # change sets only as a step begins (mid-swing it can trip)
        self._set = set_name
        self.motion.skill_gains(None)  # the walk's own gains again after a kick or an align
        v = self.motion.walk_step(percept, x, y, turn, set_name, head=self._head(percept), kp=kp)
        if self.motion.last is not None:
            dx, dy, _ = self.motion.last.odometry
            self.odo.update(dx, dy, 0.0)
        return v

    def _turned(self, percept: Percept) -> None:
        """Heading from the gyro: the yaw rate about the world's vertical (the gyro
        turned level by the tilt estimate), every cycle, walking or not."""
        rate = float((self.tilt.level @ np.asarray(percept.gyro, dtype=float))[2])
        self.odo.heading = wrap(self.odo.heading + rate * CYCLE)

    def stance_pose(self, percept: Percept) -> tuple[float, float, float]:
        """Where the torso will stand (x, y, heading; dead-reckoning frame, m, rad) if the
        walk stopped now: over the middle of the feet, facing their mean yaw.

        Walking, the torso sways and twists over the feet; on stopping it settles
        into the standing pose over the feet where they are. Near the ball the
        approach steers this pose rather than the swaying torso."""
        walk = self.motion.walk
        if self.motion.last is None or self.motion.last.standing:
            return self.pose
        level = self._level(percept)
        ankles = walk.kin.ankle_positions(percept.joints)
        soles = walk.kin.foot_poses(percept.joints)
        yaw = 0.0
        for sole in soles:
            r = level @ sole[:3, :3]
            yaw += 0.5 * math.atan2(r[1, 0], r[0, 0])
        mid = level @ (0.5 * (ankles[0] + ankles[1]))
        stand = walk.foot_targets(standing=True)
        mid0 = 0.5 * (stand["l"][0] + stand["r"][0])
        rx, ry = rotate(mid0[0], mid0[1], yaw)
        ox, oy = mid[0] - rx, mid[1] - ry
        x, y = self.odo.pose.to_world(ox, oy)
        return x, y, wrap(self.odo.heading + yaw)

    def _level(self, percept: Percept) -> np.ndarray:
        """Torso-to-level rotation for vision: from the leg's kinematics with the
        sole that bears more weight taken as flat on the ground (steadier than the
        IMU estimate while stepping, when the accelerometer feels the sway); the
        IMU estimate when neither foot bears weight."""
        forces = np.asarray(percept.foot_forces, dtype=float)
        if forces.size < 2 or float(np.max(forces)) < SOLE_FORCE:
            return self.tilt.level
        soles = self.motion.walk.kin.foot_poses(percept.joints)
        m = soles[int(np.argmax(forces[:2]))][:3, :3].T  # the torso's axes in the sole frame
        yaw = math.atan2(m[1, 0], m[0, 0])
        c, s = math.cos(yaw), math.sin(yaw)
        return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]]) @ m

    def landmark_fix(self, obs: Observation, side: str) -> None:
        """Pull the dead-reckoned pose toward what seen flags and goal posts say.

        Two or more landmarks give a pose (the rigid 2D fit of their seen
        positions onto their known ones); one gives the heading from its bearing
        and the dead-reckoned position. Each fix moves the pose by `LANDMARK_GAIN`; fixes
        more than `LANDMARK_GATE` (heading) or `LANDMARK_GATE_M` (position) off are ignored."""
        if self._landmarks is None or getattr(self, "_side", None) != side:
            self._landmarks = landmarks_in_team(side)
            self._side = side
        pairs = [(self._landmarks[n][:2], obs.landmarks[i][:2]) for i, n in enumerate(obs.landmark_names)
                 if n in self._landmarks]
        if not pairs:
            return
        known = np.array([k for k, _ in pairs])
        seen = np.array([o for _, o in pairs])
        odo = self.odo
        if len(pairs) >= 2:
            kc, sc = known.mean(axis=0), seen.mean(axis=0)
            a, b = known - kc, seen - sc
            heading = math.atan2(float(np.sum(b[:, 0] * a[:, 1] - b[:, 1] * a[:, 0])),
                                 float(np.sum(b[:, 0] * a[:, 0] + b[:, 1] * a[:, 1])))
            rx, ry = rotate(sc[0], sc[1], heading)
            px, py = kc[0] - rx, kc[1] - ry
        else:
            bearing = math.atan2(seen[0, 1], seen[0, 0])
            heading = math.atan2(known[0, 1] - odo.y, known[0, 0] - odo.x) - bearing
            px, py = odo.x, odo.y
        dh = wrap(heading - odo.heading)
        if abs(dh) > LANDMARK_GATE or math.hypot(px - odo.x, py - odo.y) > LANDMARK_GATE_M:
            return  # a misfit (a flag misread while the torso tilts) would drag the pose away
        rel = self.ball_relative()
        odo.heading = wrap(odo.heading + LANDMARK_GAIN * dh)
        odo.x += LANDMARK_GAIN * (px - odo.x)
        odo.y += LANDMARK_GAIN * (py - odo.y)
        if rel is not None:  # the ball was seen from the robot: it moves with the correction
            self.ball.position = np.array(odo.pose.to_world(*rel))

    def _approach(self, percept: Percept) -> np.ndarray:
        b = self.ball.position
        if b is None or percept.time - self.ball.seen_at > LOST:
            self.approach.reset()
            return self._walk(percept, 0.0, 0.0, 0.4)  # turn on the spot to look for it
        robot = self.pose
        current = None if self.kick is None else self.kick.spec.name
        spec = choose_kick(robot, b, self.target, [k.spec for k in self.kicks.values()], current)
        if current is not None and spec.name != current:
            self.approach.reset()
        self.kick = self.kicks[spec.name]
        standing = self.motion.last is not None and self.motion.last.standing
        # Near the ball the approach steers where the torso will stand, not the swaying torso.
        pose = self.stance_pose(percept) if self.approach.near else robot
        cmd = self.approach.step(pose, b, self.target, spec, standing)
        self.last = cmd
        if cmd.ready and standing:
            self.state = KICK
            self.kick_started = percept.time
            self.kick.reset(self.ball_relative(), self.motion.held_target)
            return self._skill_command(self.kick.step(percept), percept)
        if cmd.mode is ApproachMode.ALIGN and standing:
            self.state = ALIGN
            self._align_start = self.pose
            self.align.reset(cmd.error)
            self.motion.walk.reset()
            return self._aligning(percept)
        if cmd.mode in (ApproachMode.STOP, ApproachMode.ALIGN):
            self._quick_stop()
        return self._walk(percept, cmd.x, cmd.y, cmd.turn, cmd.set_name)

    def _aligning(self, percept: Percept) -> np.ndarray:
        """One cycle of the align: its targets, and the dead-reckoned position moved as
        its plan moves the torso (the heading follows the gyro as always)."""
        self.motion.sense(percept)  # keep the body's tilt estimate current for the stand after
        target = self.align.step(percept)
        tx, ty, _ = self.align.torso()
        self.odo.x, self.odo.y = Pose2(*self._align_start).to_world(tx, ty)
        if self.align.done:
            self.state = APPROACH
            self.approach.aligned()
            self.motion.walk.reset()
        return self._skill_command(target, percept)

    def _skill_command(self, target: np.ndarray, percept: Percept) -> np.ndarray:
        """Joint velocities toward a kick's or the align's `target`, at `SKILL_GAINS`."""
        self.motion.skill_gains(SKILL_GAINS)
        return self.motion.command(target, percept)

    def _quick_stop(self) -> None:
        """Stand at the next change of support rather than after the walk's half second
        of stepping in place (in which this walk drifts back and turns): the feet
        are both down then."""
        if self.motion.walk.walking and self.motion.walk.step_begins():
            self.motion.walk.reset()


__all__ = ["ALIGN", "APPROACH", "DONE", "KICK", "WATCH", "BallMemory", "Kicker", "KickerState"]

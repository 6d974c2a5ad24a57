"""From skills to joint commands: the walk (and skills) through PID with feed-forward.

`Motion` is what an agent's body layer holds: every cycle it takes the
percept's proprioception, estimates the torso's tilt and roll, asks the walk
engine (or a skill's keyframes) for joint targets and turns them into joint
velocities. The command is the target's own rate of change (feed-forward)
plus a PID on the remaining error, clamped at each joint's maximum speed, so
fast motions are followed without lag.
"""

from __future__ import annotations

import numpy as np

from models import nao
from models.messages import Percept
from models.rules import CYCLE
from skills import _kernels as kernels
from skills.control import UT_KP, JointPid, PidGains
from skills.falls import Getup
from skills.imu import TiltEstimator
from skills.walk import WalkEngine, WalkOutput

HEAD = ("hj1", "hj2")
HOLD_AFTER_GETUP = 1.0  # s the getup's last pose holds once the robot is up
_EMPTY = np.zeros(0)  # joint_command's previous target or error when there is none
SETTLE_AFTER_GETUP = 0.5  # s of the walk's stand after that, before the walk may go on
GETUP_GAINS = (UT_KP, 0.0)  # joint kp (1/s) and feed-forward factor while a getup plays
# s to blend from wherever the joints are into the walk's stand (`Motion.enter_stand`). Sent
# straight to the stand from straight legs, each joint at its own top speed, type 2 (its faster
# ankles) rocked back onto its heels and fell within 2.5 s.
STAND_IN = 0.4


class Motion:
    """Walk engine, tilt estimate and joint control of one robot."""

    def __init__(self, robot_type: int, walk: WalkEngine | None = None, feedforward: float = 1.0) -> None:
        self.robot_type = robot_type
        self.walk = walk or WalkEngine(robot_type)
        self.names = nao.joint_names(robot_type)
        self.max_speed = np.array([j.max_speed for j in nao.joints(robot_type)])
        self.pid = JointPid(self.max_speed, PidGains(kp=self.walk.params.joint_kp))
        self.tilt = TiltEstimator()
        self.feedforward = feedforward
        self._prev_target: np.ndarray | None = None
        self.head = np.array([self.names.index(n) for n in HEAD])
        self.last: WalkOutput | None = None
        self.getup = Getup(robot_type)
        self._recovering = False
        self._settle_until = -1.0
        self._hold_until = -1.0
        self._getup_pose: np.ndarray | None = None
        self._saved_gains: tuple[np.ndarray, float] | None = None  # while a skill's gains are on
        self._enter: tuple[float, np.ndarray] | None = None  # (s, joints) where enter_stand began

    def reset(self) -> None:
        """After a beam, a getup or anything that moved the body by other means."""
        self.walk.reset()
        self.pid.reset()
        self.tilt = TiltEstimator()
        self._prev_target = None
        self._enter = None

    def sense(self, percept: Percept) -> tuple[float, float]:
        """Update the tilt estimate from the percept; returns (pitch, roll) in rad."""
        self.tilt.update(percept.gyro, percept.accel, CYCLE)
        return self.tilt.pitch, self.tilt.roll

    def command(self, target: np.ndarray, percept: Percept) -> np.ndarray:
        """Joint velocities (rad/s) toward `target` angles (rad, league order; NaN = hold)."""
        q = percept.joints
        prev = self._prev_target
        pid = self.pid
        # The usual case, no integral: one compiled pass, the same floats, into the
        # previous target and error's own arrays.
        target = np.asarray(target, dtype=float)
        n = len(target)
        has_prev, has_err = prev is not None, pid._prev is not None
        new = prev if has_prev else np.empty(n)
        err = pid._prev if has_err else np.empty(n)
        v = np.empty(n)
        if kernels.joint_command(target, np.asarray(q, dtype=float), new if has_prev else _EMPTY, has_prev,
                                 err if has_err else _EMPTY, has_err, pid.kp, pid.ki, pid.kd, pid.dt,
                                 self.max_speed, float(self.feedforward), CYCLE, new, err, pid._out, v):
            pid._prev = err
            self._prev_target = new
            return v
        nan = np.isnan(target)
        if nan.any():  # walks leave the head NaN: hold it where it was (else where it is)
            target = np.where(nan, q if prev is None else np.where(np.isnan(prev), q, prev), target)
        else:
            target = np.array(target, dtype=float)
        self._prev_target = target.copy()
        v = self.pid(target, q)
        if prev is None:
            v = v + self.feedforward * 0.0
        else:
            v = v + self.feedforward * ((target - prev) / CYCLE)
        # np.clip as minimum(maximum()): the same values without np.clip's Python layers.
        return np.minimum(np.maximum(v, -self.max_speed), self.max_speed)

    def enter_stand(self, percept: Percept, duration: float = STAND_IN) -> np.ndarray:
        """Joint velocities that take every joint together, linearly in time, from its angle at
        the first call after `reset` to the walk's stand in `duration` s, then hold the stand
        (head held). For a body moved by other means, such as a beam from straight legs."""
        if self._enter is None:
            self._enter = (percept.time, np.array(percept.joints, dtype=float))
        t0, q0 = self._enter
        share = min(1.0, (percept.time - t0 + CYCLE) / duration) if duration > 0.0 else 1.0
        self.pid.kp[:] = self.walk.select("go_to_target").joint_kp
        pitch, roll = self.sense(percept)
        stand = self.last = self.walk.update(0.0, 0.0, 0.0, tilt=pitch, roll=roll, gyro=percept.gyro,
                                             joints=percept.joints)
        return self.command(q0 + share * (stand.targets - q0), percept)  # NaN (the head) stays NaN

    def recover(self, percept: Percept) -> np.ndarray | None:
        """Joint velocities of a getup while the robot is down (or getting up), else None.

        Call it every cycle before walking; when it returns None the body is
        upright and free for the walk (which restarts from standing after a getup).
        The getups play with UT's joint gains and no feed-forward (they were
        tuned so; with the walk's stiffer gains most fail), then their last pose
        holds `HOLD_AFTER_GETUP` s (`Getup.hold`: the ankles balance the torso's
        lean) before the walk's stand takes over for `SETTLE_AFTER_GETUP` s.
        """
        target = self.getup.step(percept.time, percept.joints, percept.accel, percept.gyro)
        if target is None and (self.tilt.fallen or (self._recovering and self.getup.detector.fallen)):
            # Down (the fused tilt past its fall angle) but no getup yet: hold still until
            # the fall detector has seen the robot lie still on one side.
            target = percept.joints.copy() if self._getup_pose is None else self._getup_pose
        if target is not None:
            self.sense(percept)  # the walk, which feeds the tilt estimate, is off
            if not self._recovering:
                self._recovering = True
                self.skill_gains(GETUP_GAINS)
                self._prev_target = None
            self._getup_pose = target.copy()
            self._hold_until = percept.time + HOLD_AFTER_GETUP
            return self.command(target, percept)
        if self._recovering:
            if percept.time < self._hold_until and self._getup_pose is not None:
                hold = self.getup.hold()  # the end pose, balanced (step above read the lean)
                return self.command(self._getup_pose if hold is None else hold, percept)
            # Up: the walk's gains again, and its stand before walking.
            self._recovering = False
            self._getup_pose = None
            self.getup.last = None  # a later recovery holds its own getup's pose, not this one
            self.skill_gains(None)
            self.pid.reset()
            self._prev_target = None
            self.walk.reset()
            self._settle_until = percept.time + SETTLE_AFTER_GETUP
        if percept.time < self._settle_until:
            return self.walk_step(percept, 0.0, 0.0, 0.0)
        return None

    def skill_gains(self, gains: tuple[float, float] | None) -> None:
        """Joint gains (kp 1/s, feed-forward factor) for a skill tuned with them, e.g.
        `GETUP_GAINS`; None gives back the gains in use before (the walk's). The walk
        sets its own kp again at its next step anyway."""
        if gains is None:
            if self._saved_gains is not None:
                self.pid.kp[:], self.feedforward = self._saved_gains
                self._saved_gains = None
            return
        if self._saved_gains is None:
            self._saved_gains = (self.pid.kp.copy(), self.feedforward)
        self.pid.kp[:] = gains[0]
        self.feedforward = gains[1]

    @property
    def held_target(self) -> np.ndarray | None:
        """The joint targets (rad, league order) of the last `command`, held where a later
        target is NaN; None after `reset` or a getup's start."""
        return None if self._prev_target is None else self._prev_target.copy()

    @property
    def recovering(self) -> bool:
        """True while a getup plays or its last pose holds."""
        return self._recovering

    def walk_step(self, percept: Percept, x: float, y: float, turn: float,
                  set_name: str = "go_to_target", head: np.ndarray | None = None,
                  kp: float | None = None) -> np.ndarray:
        """Joint velocities for one walk cycle; `head` angles (hj1, hj2) if given; `kp`
        (1/s) instead of the walk set's joint gain.

        The tilt estimate, the walk and the joint command run as one compiled call
        (`skills._kernels.walk_step`) unless a head is given (or the set is unknown).
        """
        walk, pid = self.walk, self.pid
        if kp is not None:
            pid.kp[:] = kp
        elif set_name in walk.sets:
            pid.kp[:] = walk.select(set_name).joint_kp
        if head is not None or set_name not in walk.sets:
            pitch, roll = self.sense(percept)
            out = self.last = walk.update(x, y, turn, set_name, tilt=pitch, roll=roll, gyro=percept.gyro,
                                          joints=percept.joints)
            target = out.targets
            if head is not None:  # on a copy: `last` keeps the walk's own targets
                target = target.copy()
                target[self.head] = head
            return self.command(target, percept)
        tilt = self.tilt
        joints = np.ascontiguousarray(percept.joints, dtype=float)
        n = len(walk.names)
        q, v = np.empty(n), np.empty(n)
        prev, err = self._prev_target, pid._prev
        has_prev, has_err = prev is not None, err is not None
        new = prev if has_prev else np.empty(n)  # the command writes over the last target and error
        err = err if has_err else np.empty(n)
        status, standing, ox, oy, oth = kernels.walk_step(
            tilt._st, np.ascontiguousarray(percept.gyro, dtype=float),
            np.ascontiguousarray(percept.accel, dtype=float), CYCLE, float(tilt.blend),
            float(tilt.accel_smoothing), bool(tilt.exact), float(x), float(y), float(turn), joints,
            *walk._kernel_args(set_name), q, new if has_prev else _EMPTY, has_prev,
            err if has_err else _EMPTY, has_err, pid.kp, pid.ki, pid.kd, pid.dt, self.max_speed,
            float(self.feedforward), CYCLE, new, err, pid._out, v)
        if status == kernels.STEP_TILT_ERROR:
            raise ValueError("math domain error")  # as the tilt estimate's math.remainder
        self.last = WalkOutput(q, (ox, oy, oth), standing)
        if status == kernels.STEP_NO_COMMAND:  # an integral gain: numpy's PID
            return self.command(q, percept)
        pid._prev = err
        self._prev_target = new
        return v

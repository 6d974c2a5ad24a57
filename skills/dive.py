"""Goalie dives and the getup after them (dissertation Appendix D.3.3).

Five dives in ``skills/data/dive.skl`` (their ``$parameters`` in
``dive.params``, degrees and seconds): the central split DIVE_CENTER, the
side-wards splits DIVE_LEFT / DIVE_RIGHT and the lateral lunges LUNGE_LEFT /
LUNGE_RIGHT ("left" is the robot's left, torso frame y > 0).

`Dive` plays one of them from the robot's percepts and then gets it up again:

1. DIVE: the dive's keyframes (`skills.skill.SkillPlayer`);
2. DOWN: it holds the dive's last pose for `hold` seconds (blocking the ball);
3. RELAX: DIVE_RELAX brings every joint to zero (legs together), the pose the
   getups start well from (with it, 59 of 60 dives were followed by a
   successful getup in a trial over types 0-4, against 53 without);
4. GETUP: `skills.falls.Getup` (its `FallDetector` decides front, back or a side;
   a side is rolled off first). A robot that sits upright after a dive, its
   weight off its feet (foot force percepts), plays DIVE_LIE_BACK to lie on its
   back, where GETUP_BACK takes over;
5. SETTLE: once the robot stands (upright within `stand_tilt`, gyro quiet, feet
   loaded), its joints move from the getup's last pose to the walk's stand pose
   in `settle` / 2 seconds and hold it to the end of `settle`; a robot that
   tips over on the way goes back to GETUP. Then `done`: `step` hands the
   joints to the walk engine's stand, and falls are no longer the dive's
   business (the caller's `Motion.recover`).

Joint targets become joint velocities through `skills.motion.Motion.command`
(PID plus feed-forward). The getup skills were tuned for UT's plain joint PID
(`skills.control.PidGains`, no feed-forward), so while a getup plays the
command uses those gains (`getup_gains`) until `done`; with the walk's stiffer
gains and feed-forward the getups fail far more often (see
`optimization.getup`, controller "motion").

Only percepts are read (joint angles, accelerometer, gyro, foot forces).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

import numpy as np

from models import nao
from models.messages import Percept
from models.rules import CYCLE
from skills.falls import UPRIGHT, Getup
from skills.motion import GETUP_GAINS, Motion
from skills.params import PathLike, load_params
from skills.skill import Skill, SkillPlayer, read_skills, skill_path

DIVE_FILE = "dive.skl"  # in skills/data/
DIVE_PARAMS = ("dive.params",)  # in skills/data/: values of the dives' $parameters
DIVES = ("DIVE_CENTER", "DIVE_LEFT", "DIVE_RIGHT", "LUNGE_LEFT", "LUNGE_RIGHT")
LIE_BACK = "DIVE_LIE_BACK"
RELAX = "DIVE_RELAX"

DIVE, DOWN, RELAXING, GETUP, SETTLE, DONE = "dive", "down", "relax", "getup", "settle", "done"


def load_dive_skills(param_paths: Iterable[PathLike] = ()) -> dict[str, Skill]:
    """The dive skills of ``skills/data/dive.skl`` bound to ``dive.params``, then to
    `param_paths` (later files override earlier ones)."""
    src = read_skills(skill_path(DIVE_FILE))
    params = load_params([skill_path(p) for p in DIVE_PARAMS] + list(param_paths), src.schema)
    return src.bind(params)


class Dive:
    """One dive from percepts, then the getup: call `step` every cycle for joint velocities.

    robot_type: 0-4; name: one of `DIVES`; skills: the dive skills (default
    `load_dive_skills()`); motion: the agent's `Motion` (its walk is reset; its
    gains are changed during the getup and given back at `done` or `release`);
    hold: s to stay down after the dive;
    settle: s of standing after the getup before `done`; sit_force: N, feet
    carrying less than this while the torso is upright means sitting (after
    `sit_time` s of it the robot lies back); stand_tilt: rad, the torso's tilt
    under which a still robot with loaded feet counts as standing;
    getup_gains: joint-PID gain kp (1/s) and feed-forward factor used while a
    getup plays (None: the motion's own).
    """

    def __init__(self, robot_type: int, name: str = "DIVE_CENTER", skills: Mapping[str, Skill] | None = None,
                 motion: Motion | None = None, hold: float = 0.2, settle: float = 1.0,
                 sit_force: float | None = None, sit_time: float = 0.5,
                 stand_tilt: float = math.radians(15.0),
                 getup_gains: tuple[float, float] | None = GETUP_GAINS) -> None:
        if name not in DIVES:
            raise ValueError(f"unknown dive {name!r}; dives are {', '.join(DIVES)}")
        skills = skills or load_dive_skills()
        self.name = name
        self.robot_type = robot_type
        self.motion = motion or Motion(robot_type)
        self.player = SkillPlayer(skills[name], robot_type)
        self.lie_back = SkillPlayer(skills[LIE_BACK], robot_type)
        self.relax = SkillPlayer(skills[RELAX], robot_type)
        self.getup = Getup(robot_type)
        self.hold = hold
        self.settle = settle
        self.sit_time = sit_time
        self.stand_tilt = stand_tilt
        self.sit_force = 0.7 * nao.total_mass(robot_type) * 9.81 if sit_force is None else sit_force
        self.getup_gains = getup_gains
        self.phase = DIVE
        self.times: dict[str, float] = {}  # s: when each phase started (percept time)
        self._target: np.ndarray | None = None
        self._sitting = 0.0  # s the robot has sat upright with its weight off its feet
        self._lying_back = False
        self._stand_pose = self._walk_stand()  # rad, league order; NaN where the walk sets nothing
        self._settle_from = self._stand = self._stand_pose

    @property
    def done(self) -> bool:
        """True once the robot has got up and stood for `settle` seconds."""
        return self.phase == DONE

    def _enter(self, phase: str, time: float) -> None:
        self.phase = phase
        self.times[phase] = time

    def _walk_stand(self) -> np.ndarray:
        """The walk engine's standing pose (rad, league order)."""
        self.motion.walk.reset()
        q = self.motion.walk.update(0.0, 0.0, 0.0).targets.copy()
        self.motion.walk.reset()
        return q

    def release(self) -> None:
        """Give the motion its own gains back (call when abandoning a dive before `done`)."""
        self._gains(False)

    def _gains(self, getup: bool) -> None:
        self.motion.skill_gains(self.getup_gains if getup else None)

    def step(self, percept: Percept) -> np.ndarray:
        """Joint velocities (rad/s, league order) for this cycle."""
        t = percept.time
        if not self.times:
            self.times[DIVE] = t
            self.motion.reset()
        if self.phase == DIVE:
            self._target = self.player.step(t, percept.joints).copy()
            if self.player.done:
                self._enter(DOWN, t)
            return self.motion.command(self._target, percept)
        if self.phase in (DOWN, RELAXING):
            self.getup.detector.update(percept.accel, percept.gyro)  # keep the filter current
        if self.phase == DOWN:
            if t - self.times[DOWN] < self.hold - 1e-9:
                return self.motion.command(self._target, percept)
            self._enter(RELAXING, t)
        if self.phase == RELAXING:
            self._target = self.relax.step(t, percept.joints).copy()
            if self.relax.done:
                self._enter(GETUP, t)
                self._gains(True)
            return self.motion.command(self._target, percept)
        if self.phase == GETUP:
            return self._getting_up(percept)
        if self.phase == DONE:  # the dive is over: the walk's stand (falls are the caller's again)
            return self.motion.walk_step(percept, 0.0, 0.0, 0.0)
        # SETTLE: from the getup's last pose to the walk's stand, with the getup's gains,
        # unless the robot tips over again.
        target = self.getup.step(t, percept.joints, percept.accel, percept.gyro)
        if target is not None or self.getup.detector.state != UPRIGHT:
            self._enter(GETUP, t)
            self._target = target.copy() if target is not None else percept.joints.copy()
            return self.motion.command(self._target, percept)
        s = min(1.0, (t - self.times[SETTLE]) / (0.5 * self.settle))
        self._target = self._settle_from + s * (self._stand - self._settle_from)
        if t - self.times[SETTLE] >= self.settle - 1e-9:
            self._enter(DONE, t)
            self._gains(False)
            self.motion.reset()
            self.motion.walk.reset()
        return self.motion.command(self._target, percept)

    def _standing(self, percept: Percept) -> bool:
        """Upright within `stand_tilt`, hardly turning (gyro under the detector's
        `rest_rate`) and the weight on the feet (percepts)."""
        det = self.getup.detector
        return (det.state == UPRIGHT and det.tilt < self.stand_tilt
                and float(np.linalg.norm(percept.gyro)) < det.rest_rate
                and float(np.sum(percept.foot_forces)) >= self.sit_force)

    def _getting_up(self, percept: Percept) -> np.ndarray:
        t = percept.time
        if self._lying_back:
            target = self.lie_back.step(t, percept.joints)
            self.getup.detector.update(percept.accel, percept.gyro)
            if self.lie_back.done:
                self._lying_back = False
                self._sitting = 0.0
            self._target = target.copy()
            return self.motion.command(self._target, percept)
        target = self.getup.step(t, percept.joints, percept.accel, percept.gyro)
        if target is not None:
            self._target = target.copy()
            self._sitting = 0.0
            return self.motion.command(self._target, percept)
        # No getup plays: the robot is upright (tilt under 60 deg). Standing, or sitting?
        if self._standing(percept):
            self._enter(SETTLE, t)
            self._settle_from = (percept.joints if self._target is None else self._target).copy()
            self._stand = np.where(np.isnan(self._stand_pose), self._settle_from, self._stand_pose)
            return self.motion.command(self._settle_from, percept)
        det = self.getup.detector
        sitting = (det.state == UPRIGHT and det.tilt < det.falling_tilt
                   and float(np.sum(percept.foot_forces)) < self.sit_force)
        self._sitting = self._sitting + CYCLE if sitting else 0.0
        if self._sitting >= self.sit_time - 1e-9:
            self._lying_back = True
            self.lie_back.reset()
            self.getup.last = None  # lying back, the last getup's end pose no longer holds
        hold = self.getup.hold()  # the getup's end pose, balanced
        if hold is not None:
            self._target = hold
        return self.motion.command(self._target if self._target is not None else percept.joints, percept)

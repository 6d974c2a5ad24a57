"""Optimization tasks built of phases (dissertation Appendix A.1.2, UT's ``OptPhase``).

A task is a list of phases run in order in one MuJoCo world. Each phase is a
logically distinct action with its own utility and a maximum duration; when
the action is done or the time is up the next phase starts. A robot that
falls ends its phase with the fall penalty (UT: 5) and gets up before the
next phase starts. The task's fitness is the sum of the phases' utilities.

* `WaypointPhase`: walk to a target; utility = distance gained toward it,
  extrapolated to the whole phase if reached early
  (``d_target * t_total / t_taken``).
* `StopPhase`: stand still; utility = minus the distance the torso moves away.
* `MovePhase`: walk with fixed inputs; utility = distance along a direction.

Who knows what: the robot's control (`WalkAgent`) reads only its percepts and
its own walk odometry. Utilities read ground truth through the trainer
interface. At the start of a waypoint phase the task tells the robot where
the target lies relative to its true pose (as a localized agent would know)
and resets its dead reckoning; within the phase the robot walks on its own
odometry.

Getting up: until the walk tasks use the getup skills, `TrainerRecovery`
stands a fallen robot upright where it lies (a trainer command) and lets it
settle; the fall still costs the phase's penalty. `GetupRecovery` is the
hook for the getup skill (`skills.falls.Getup`), driven only by percepts,
with the trainer as the fallback if it fails within its time limit.

Frames: the *course frame* is the robot's start pose (x forward, y left; m,
rad); `Sim.course_to_world` maps it to the field frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from models.geometry import Pose2
from models.messages import Action, Percept
from models.rules import CYCLE
from models.scene import Lineup
from server.trainer import Trainer
from skills.motion import Motion
from skills.navigate import SPRINT_BEYOND, Odometry, sprints, walk_toward
from skills.walk import WalkEngine, WalkParams

FALL_PENALTY = 5.0  # utility lost by a phase in which the robot fell (UT's Fall)
FALLEN_UP = 0.5  # torso up-vector z below this counts as fallen (ground truth)
REACHED = 0.25  # m: a waypoint within this (ground truth) is reached
SETTLE = 0.5  # s standing after a trainer recovery
# Zigzag: full forward input, the turn input swinging between +0.4 and -0.4 every
# second. On the course the falls come mostly while walking and turning, and this
# stresses that alone: type 3 fell in 10 of 20 twelve-second runs, walking straight
# ahead in 3 of 20 twenty-second ones.
ZIGZAG_TURN = 0.4
ZIGZAG_HALF = 1.0  # s


class WalkAgent:
    """One robot's walk control from its percepts: `Motion` plus dead reckoning.

    sets: the walk parameter sets by name (`skills.walk.WALK_SETS`);
    sprint_within: use the "sprint" set when the target lies within this bearing
    (rad) and farther than `sprint_beyond` (m), "go_to_target" otherwise (A.1.4).
    """

    def __init__(self, robot_type: int, sets: Mapping[str, WalkParams],
                 sprint_within: float | None = None, sprint_beyond: float = SPRINT_BEYOND) -> None:
        self.motion = Motion(robot_type, WalkEngine(robot_type, dict(sets)))
        self.odo = Odometry()
        self.sprint_within = sprint_within
        self.sprint_beyond = sprint_beyond
        self.set_name = "go_to_target"
        self.set_cycles: dict[str, int] = {}

    def reset_pose(self) -> None:
        """Dead reckoning restarts at the origin (the robot's current pose)."""
        self.odo = Odometry()

    def walk(self, percept: Percept, x: float, y: float, turn: float, set_name: str = "go_to_target",
             head: np.ndarray | None = None) -> np.ndarray:
        """Joint velocities for walk inputs in [-1, 1] (head angles hj1, hj2 in rad if
        given); odometry integrated."""
        self.set_name = set_name
        self.set_cycles[set_name] = self.set_cycles.get(set_name, 0) + 1
        v = self.motion.walk_step(percept, x, y, turn, set_name, head=head)
        if self.motion.last is not None:
            self.odo.update(*self.motion.last.odometry)
        return v

    def goto(self, percept: Percept, tx: float, ty: float) -> np.ndarray:
        """Walk toward (tx, ty) in the dead-reckoning frame, turning to face it."""
        dx, dy = self.odo.relative(tx, ty)
        set_name = "sprint" if sprints(dx, dy, self.sprint_within, self.sprint_beyond) else "go_to_target"
        params = self.motion.walk.sets[set_name]
        return self.walk(percept, *walk_toward(dx, dy, None, params), set_name=set_name)

    def stand_pose(self) -> np.ndarray:
        """Standing joint angles (rad, league order; unset joints 0) of the go-to-target set."""
        self.motion.reset()
        q = self.motion.walk.update(0.0, 0.0, 0.0).targets
        self.motion.reset()
        return np.where(np.isnan(q), 0.0, q)


@dataclass
class Sim:
    """One trial's world: the trainer, the robot's control, the course frame and a clock."""

    trainer: Trainer
    agent: WalkAgent
    origin: tuple[float, float, float]  # course frame in the field frame (x, y, heading)
    mirror: bool = False  # course mirrored left-right (y -> -y)
    falls: int = 0
    memory: dict = field(default_factory=dict)  # the robot's state kept across phases (e.g. the ball)

    @property
    def world(self):
        return self.trainer.world

    @property
    def time(self) -> float:
        return self.trainer.world.time

    def percept(self) -> Percept:
        return self.trainer.percepts()[0]

    def step(self, velocities: np.ndarray) -> list[int]:
        return self.trainer.step({0: Action(velocities)})

    def pose(self) -> tuple[float, float, float]:
        """The robot's true torso pose (field frame)."""
        return self.trainer.world.player_pose(0)

    def fallen(self) -> bool:
        return bool(self.trainer.world.torso_up()[0] < FALLEN_UP)

    def course_to_world(self, x: float, y: float) -> tuple[float, float]:
        y = -y if self.mirror else y
        return Pose2(*self.origin).to_world(x, y)

    def stand_upright(self, x: float, y: float, heading: float) -> None:
        """Trainer command: the robot upright at (x, y, heading), standing pose, still."""
        q = self.agent.stand_pose()
        self.trainer.world.place_robot(0, x, y, heading, joints=q)
        self.trainer.world.settle_height(0)
        self.agent.motion.reset()

    def hold(self, seconds: float) -> None:
        """Stand (walk inputs zero) for `seconds`."""
        for _ in range(round(seconds / CYCLE)):
            self.step(self.agent.walk(self.percept(), 0.0, 0.0, 0.0))


class Recovery(Protocol):
    """What happens when the robot falls: afterwards it must stand, ready for the next phase."""

    def recover(self, sim: Sim) -> None: ...


@dataclass(frozen=True)
class TrainerRecovery:
    """Stand the robot upright where it lies (trainer command), then let it settle."""

    settle: float = SETTLE

    def recover(self, sim: Sim) -> None:
        x, y, h = sim.pose()
        sim.stand_upright(x, y, h)
        sim.hold(self.settle)


@dataclass(frozen=True)
class GetupRecovery:
    """The getup skills from percepts (`skills.falls.Getup`), `limit` seconds at most;
    the trainer stands the robot up if they have not by then."""

    limit: float = 6.0
    fallback: TrainerRecovery = field(default_factory=TrainerRecovery)

    def recover(self, sim: Sim) -> None:
        from skills.control import JointPid
        from skills.falls import Getup

        getup = Getup(sim.agent.motion.robot_type)
        pid = JointPid.for_robot(sim.agent.motion.robot_type)
        t0 = sim.time
        hold: np.ndarray | None = None
        while sim.time - t0 < self.limit:
            pc = sim.percept()
            target = getup.step(pc.time, pc.joints, pc.accel, pc.gyro)
            if target is None and getup.count > 0 and not sim.fallen():
                break
            if target is None:
                target = getup.hold()  # the end pose, balanced
            if target is not None:
                hold = target
            sim.step(pid(hold if hold is not None else pc.joints.copy(), pc.joints))
        sim.agent.motion.reset()
        if sim.fallen():
            self.fallback.recover(sim)
        else:
            sim.hold(self.fallback.settle)


@dataclass
class PhaseResult:
    """One phase's utility and what it saw."""

    kind: str
    utility: float
    seconds: float
    fell: bool
    info: dict = field(default_factory=dict)


class Phase(Protocol):
    """One step of a task: `start`, then `act` every cycle until `done` or `duration`,
    then `utility` (before the fall penalty)."""

    duration: float  # s, maximum

    def start(self, sim: Sim) -> None: ...
    def act(self, sim: Sim, percept: Percept) -> np.ndarray: ...
    def after_step(self, sim: Sim) -> None: ...
    def done(self, sim: Sim) -> bool: ...
    def utility(self, sim: Sim, elapsed: float) -> tuple[float, dict]: ...


@dataclass
class WaypointPhase:
    """Walk to (x, y) in the course frame within `duration` seconds."""

    x: float
    y: float
    duration: float
    reach: float = REACHED

    def start(self, sim: Sim) -> None:
        self._target = sim.course_to_world(self.x, self.y)
        px, py, ph = sim.pose()
        ex, ey = self._target[0] - px, self._target[1] - py
        self._d0 = math.hypot(ex, ey)
        # The robot is told the target relative to where it truly is, then walks on odometry.
        sim.agent.reset_pose()
        self._rel = Pose2(px, py, ph).to_local(*self._target)
        self._taken: float | None = None
        self._t0 = sim.time

    def _dist(self, sim: Sim) -> float:
        px, py, _ = sim.pose()
        return math.hypot(self._target[0] - px, self._target[1] - py)

    def act(self, sim: Sim, percept: Percept) -> np.ndarray:
        return sim.agent.goto(percept, *self._rel)

    def after_step(self, sim: Sim) -> None:
        if self._taken is None and self._dist(sim) < self.reach:
            self._taken = sim.time - self._t0

    def done(self, sim: Sim) -> bool:
        return self._taken is not None

    def utility(self, sim: Sim, elapsed: float) -> tuple[float, dict]:
        gained = self._d0 - self._dist(sim)
        if self._taken is not None and self._taken > 0:
            gained *= self.duration / self._taken
        return gained, {"reached": self._taken is not None}


@dataclass
class StopPhase:
    """Stand still for `duration` seconds; utility = minus the distance moved (m): the
    farthest the torso got from where it was at the phase's start (ground truth, over
    the ground), so that walking off and back costs, the torso's sway in a step does not."""

    duration: float

    def start(self, sim: Sim) -> None:
        self._p0 = sim.pose()[:2]
        self._moved = 0.0

    def act(self, sim: Sim, percept: Percept) -> np.ndarray:
        return sim.agent.walk(percept, 0.0, 0.0, 0.0)

    def after_step(self, sim: Sim) -> None:
        p = sim.pose()[:2]
        self._moved = max(self._moved, math.hypot(p[0] - self._p0[0], p[1] - self._p0[1]))

    def done(self, sim: Sim) -> bool:
        return False

    def utility(self, sim: Sim, elapsed: float) -> tuple[float, dict]:
        return -self._moved, {"moved": self._moved}


@dataclass
class MovePhase:
    """Walk with fixed inputs (x, y, turn in [-1, 1]) of `set_name` for `duration`;
    utility = distance (m) along `direction` (rad, robot frame at the phase's start)."""

    x: float
    y: float
    turn: float
    duration: float
    direction: float = 0.0
    set_name: str = "go_to_target"

    def start(self, sim: Sim) -> None:
        self._p0 = sim.pose()

    def act(self, sim: Sim, percept: Percept) -> np.ndarray:
        return sim.agent.walk(percept, self.x, self.y, self.turn, self.set_name)

    def after_step(self, sim: Sim) -> None:
        pass

    def done(self, sim: Sim) -> bool:
        return False

    def utility(self, sim: Sim, elapsed: float) -> tuple[float, dict]:
        x0, y0, h0 = self._p0
        x, y, _ = sim.pose()
        a = h0 + self.direction
        return (x - x0) * math.cos(a) + (y - y0) * math.sin(a), {}


def run_phases(sim: Sim, phases: Sequence[Phase], recovery: Recovery,
               fall_penalty: float = FALL_PENALTY) -> list[PhaseResult]:
    """Run the phases in order; a fall ends its phase, costs `fall_penalty`, and the
    robot recovers before the next phase starts."""
    out = []
    for phase in phases:
        phase.start(sim)
        t0 = sim.time
        fell = False
        n = round(phase.duration / CYCLE)
        for _ in range(n):
            sim.step(phase.act(sim, sim.percept()))
            phase.after_step(sim)
            if sim.fallen():
                fell = True
                break
            if phase.done(sim):
                break
        elapsed = sim.time - t0
        u, info = phase.utility(sim, elapsed)
        if fell:
            u -= fall_penalty
            sim.falls += 1
        out.append(PhaseResult(type(phase).__name__, float(u), elapsed, fell, info))
        if fell:
            recovery.recover(sim)
    return out


def new_sim(robot_type: int, sets: Mapping[str, WalkParams], origin: tuple[float, float, float],
            rng: np.random.Generator, joint_noise: float = 0.0, mirror: bool = False,
            sprint_within: float | None = None, ball: tuple[float, float] = (12.0, 8.0),
            vision: bool = False) -> Sim:
    """A fresh one-robot world with the robot standing at `origin` (field frame), joints
    perturbed by `joint_noise` (rad, sigma, from `rng`), the ball at `ball`; with
    `vision`, percepts carry (noisy, seeded from `rng`) vision every third cycle."""
    trainer = Trainer(Lineup((robot_type,), ()), seed=int(rng.integers(2**31)), vision=vision)
    agent = WalkAgent(robot_type, sets, sprint_within=sprint_within)
    sim = Sim(trainer, agent, origin, mirror)
    q = agent.stand_pose()
    if joint_noise > 0:
        q = q + rng.normal(0.0, joint_noise, q.shape)
    trainer.world.place_ball(ball)
    trainer.world.place_robot(0, origin[0], origin[1], origin[2], joints=q)
    trainer.world.settle_height(0)
    return sim

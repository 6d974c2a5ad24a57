"""The optimization tasks: what a trial does and the fitness it earns (higher is better).

A task is a small picklable dataclass (it travels to worker processes) with

* ``name``; ``sets``: the parameter sets it uses (`optimization.paramvec.PARAM_SETS`);
* ``optimize``: the sets (and optionally parameter names) it learns by default;
* ``worst``: the fitness given to a trial that could not be evaluated;
* ``trial(values, seed) -> TrialResult``: one seeded run with the sets' values
  (file units, ``{set: {name: value}}``).

Registered tasks (`TASKS`, built by `make_task(name, robot_type, **options)`):

* ``go_to_target`` (Appendix A.1.3): the obstacle course of Figure A.1 as
  waypoint and stop phases, about 30 simulated seconds, learning the
  go-to-target walk set; ``fall_penalty`` (utility lost per fall, default
  UT's 5) weighs falls against speed.
* ``sprint`` (A.1.4): the same course; the robot uses the "sprint" set when
  the target is within 15 degrees, "go_to_target" (frozen) otherwise.
* ``walk_forward``: a stop phase, then walking straight forward for
  ``seconds`` (default 10) from a standstill; utility = distance forward.
* ``position_to_dribble`` (A.1.5): drive the ball toward the goal for 15 s from
  varied starts around it, seeing it only through vision percepts; learns the
  position-to-dribble set with go-to-target and sprint frozen
  (`optimization.dribble`).
* ``dribble_walk`` (``seconds``, ``away_cost``): the team's own dribble (the body
  walks through the ball) for 20 s; learns the position-to-dribble set for a
  dribble that keeps the ball within 1 m (`optimization.dribble_walk`).
* ``position_walk`` (``seconds``, ``fall_penalty``): the team's positioning walk to
  moving targets, as in open play; learns the go-to-target set's gait with its
  stand frozen (`optimization.position_walk`).
* ``getup_front``, ``getup_back`` (A, L1,1 / L1,2): lying on the front or back,
  get up from percepts; fitness -(time not standing) over 4 s (`optimization.getup`).
* ``sphere``, ``rosenbrock``: shifted analytic functions of ``dim``
  coordinates (``noise``: Gaussian noise per trial), for testing the machinery.

* ``kick_distance`` (``distance``, ``set``), ``long_kick``, ``kick_walking``
  (Appendix A's fixed-distance kicks, long kick and kick from a walking
  approach): keyframe kicks in physics, fitness from where the ball stops
  (`optimization.kick`).
* ``approach`` (``kick``): the ball approach's parameters with a frozen kick,
  from a walking start 1-2 m from the ball (`optimization.kick`).

A new task plugs in as a dataclass with the fields above and an entry in
`TASKS`, its parameter set (the skill file's ``$parameters``:
`skills.skill.SkillSource.schema`) in `PARAM_SETS`.

Trial randomness: every trial draws its variations (mirrored course, a
heading of the course on the field, joint angles perturbed at the start)
from its seed alone, so a trial's result does not depend on which process
runs it or what ran there before.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

import numpy as np

from optimization.dribble_walk import dribble_walk
from optimization.getup import getup_back, getup_front
from optimization.kick import approach, kick_distance, kick_walking, long_kick
from optimization.paramvec import ANALYTIC_NAMES, walk_sets
from optimization.phases import (
    FALL_PENALTY,
    ZIGZAG_HALF,
    ZIGZAG_TURN,
    GetupRecovery,
    MovePhase,
    Recovery,
    StopPhase,
    TrainerRecovery,
    WaypointPhase,
    new_sim,
    run_phases,
)
from optimization.position_walk import position_walk
from optimization.types import Task, TrialResult, Values

RECOVERIES = ("trainer", "getup")


def _check_recovery(name: str) -> None:
    if name not in RECOVERIES:
        raise ValueError(f"recovery must be one of {', '.join(RECOVERIES)}, not {name!r}")


# The go-to-target course (Figure A.1), in the course frame (the start pose): phases
# in order, ("wp", x, y, seconds) or ("stop", seconds). About 30 s.
GO_TO_TARGET_COURSE: tuple[tuple, ...] = (
    ("wp", 2.5, 0.0, 5.0),      # long walk forward
    ("wp", 2.5, 1.2, 3.0),      # long walk left
    ("stop", 1.0),              # stop and go
    ("wp", 1.5, 1.2, 2.5),      # backward
    ("wp", 2.0, 0.7, 1.2),      # weave at 45 degrees
    ("wp", 1.5, 0.2, 1.2),
    ("wp", 2.0, -0.3, 1.2),
    ("wp", 1.6, -0.3, 0.4),     # quick changes of target (a noisy target)
    ("wp", 1.6, 0.1, 0.4),
    ("wp", 1.7, -0.2, 0.4),
    ("wp", 0.5, -0.5, 3.5),     # extreme change of direction
    ("stop", 1.0),
    ("wp", 0.5, 0.5, 1.5),      # quick alternation left and right
    ("wp", 0.5, -0.3, 1.5),
    ("wp", 0.5, 0.5, 1.5),
    ("wp", 1.2, 0.9, 1.5),      # spiral, counter-clockwise then clockwise
    ("wp", 1.0, 1.6, 1.3),
    ("wp", 0.4, 1.0, 1.3),
    ("wp", 1.0, 0.7, 1.0),
    ("stop", 1.0),
)


def course_phases(course: tuple[tuple, ...], scale_time: float = 1.0) -> tuple:
    out = []
    for item in course:
        if item[0] == "wp":
            out.append(WaypointPhase(item[1], item[2], item[3] * scale_time))
        else:
            out.append(StopPhase(item[1] * scale_time))
    return tuple(out)


START = (-6.0, 0.0)  # m, field frame: the course start, with room on every side


@dataclass(frozen=True)
class PhaseTask:
    """A walk task made of phases (`optimization.phases`), run in a fresh one-robot world.

    joint_noise: sigma (rad) of the start pose's joint perturbation; mirror: the
    trial mirrors the course with probability 1/2; yaw: the course's heading on
    the field is uniform in +-yaw (rad); sprint_within: bearing (rad) under which
    the sprint set is used; recovery: "trainer" (stand up by trainer command) or
    "getup" (the getup skills, trainer as fallback).
    """

    name: str
    phases: tuple
    robot_type: int = 0
    sets: tuple[str, ...] = ("go_to_target",)
    optimize: Mapping[str, tuple[str, ...] | None] = field(default_factory=lambda: {"go_to_target": None})
    sprint_within: float | None = None
    joint_noise: float = 0.01
    mirror: bool = True
    yaw: float = math.pi
    recovery: str = "trainer"
    fall_penalty: float = FALL_PENALTY

    def __post_init__(self) -> None:
        _check_recovery(self.recovery)

    @property
    def worst(self) -> float:
        """Every phase fell: the penalty and more, per phase."""
        return -2.0 * self.fall_penalty * len(self.phases)

    @property
    def seconds(self) -> float:
        """Simulated seconds of a trial without falls (phases at their maximum)."""
        return sum(p.duration for p in self.phases)

    def _recovery(self) -> Recovery:
        return GetupRecovery() if self.recovery == "getup" else TrainerRecovery()

    def trial(self, values: Values, seed: int) -> TrialResult:
        rng = np.random.default_rng(seed)
        mirror = bool(self.mirror and rng.random() < 0.5)
        heading = float(rng.uniform(-self.yaw, self.yaw)) if self.yaw > 0 else 0.0
        sim = new_sim(self.robot_type, walk_sets(values), (START[0], START[1], heading), rng,
                      joint_noise=self.joint_noise, mirror=mirror, sprint_within=self.sprint_within)
        phases = [replace(p) for p in self.phases]  # fresh per-trial state
        results = run_phases(sim, phases, self._recovery(), self.fall_penalty)
        fitness = float(sum(r.utility for r in results))
        return TrialResult(fitness, {"falls": sim.falls, "sim_seconds": round(sim.time, 2),
                                     "mirror": mirror, "set_cycles": dict(sim.agent.set_cycles)})


def zigzag_phases(seconds: float) -> tuple:
    """`seconds` (whole ZIGZAG_HALF periods) of full forward input with the turn input
    swinging between +ZIGZAG_TURN and -ZIGZAG_TURN, from a 0.5 s stand: one phase a swing."""
    swings = round(seconds / ZIGZAG_HALF)
    return (StopPhase(0.5),) + tuple(MovePhase(1.0, 0.0, ZIGZAG_TURN * (-1) ** k, ZIGZAG_HALF)
                                     for k in range(swings))


def turn_phases(seconds: float) -> tuple:
    """Turning in place at the full turn input, `seconds` / 2 each way, from a 0.5 s stand."""
    return (StopPhase(0.5), MovePhase(0.0, 0.0, 1.0, seconds / 2), MovePhase(0.0, 0.0, -1.0, seconds / 2))


def step_phases(seconds: float) -> tuple:
    """Walking backward for `seconds`, then sideways `seconds` / 2 each way, each from a
    0.5 s stand; utility: the distance (m) made in the walked direction."""
    half = seconds / 2
    return (StopPhase(0.5), MovePhase(-1.0, 0.0, 0.0, seconds, direction=math.pi),
            StopPhase(0.5), MovePhase(0.0, 1.0, 0.0, half, direction=math.pi / 2),
            StopPhase(0.5), MovePhase(0.0, -1.0, 0.0, half, direction=-math.pi / 2))


def go_to_target(robot_type: int = 0, scale_time: float = 1.0, recovery: str = "trainer",
                 fall_penalty: float = FALL_PENALTY, zigzag: float = 0.0, turn: float = 0.0,
                 steps: float = 0.0) -> PhaseTask:
    """The course; then, each if > 0: `zigzag` seconds of zigzag (the walk benchmark's
    stress of walking while turning), `turn` seconds of turning in place (scored by its
    falls alone) and `steps` seconds of walking backward and as many sideways."""
    if min(zigzag, turn, steps) < 0:
        raise ValueError(f"zigzag, turn and steps must not be negative, not {zigzag}, {turn}, {steps}")
    phases = (course_phases(GO_TO_TARGET_COURSE, scale_time) + (zigzag_phases(zigzag) if zigzag else ())
              + (turn_phases(turn) if turn else ()) + (step_phases(steps) if steps else ()))
    return PhaseTask("go_to_target", phases, robot_type, recovery=recovery, fall_penalty=fall_penalty)


def sprint(robot_type: int = 0, scale_time: float = 1.0, recovery: str = "trainer",
           within_deg: float = 15.0) -> PhaseTask:
    return PhaseTask("sprint", course_phases(GO_TO_TARGET_COURSE, scale_time), robot_type,
                     sets=("go_to_target", "sprint"), optimize={"sprint": None},
                     sprint_within=math.radians(within_deg), recovery=recovery)


def walk_forward(robot_type: int = 0, seconds: float = 10.0, stand: float = 0.5,
                 recovery: str = "trainer") -> PhaseTask:
    return PhaseTask("walk_forward", (StopPhase(stand), MovePhase(1.0, 0.0, 0.0, seconds)), robot_type,
                     mirror=False, recovery=recovery)


@dataclass(frozen=True)
class DribbleTask:
    """Position-to-dribble (A.1.5): drive the ball toward the goal for `seconds` from a
    start `distance` m (uniform range) from the ball at any angle around it, facing the
    ball within +-45 deg; learns the "position_to_dribble" set, go-to-target and sprint
    frozen. The ball starts at the center spot. See `optimization.dribble`."""

    name: str = "position_to_dribble"
    robot_type: int = 0
    seconds: float = 15.0
    blocks: int = 3
    distance: tuple[float, float] = (0.5, 1.5)
    joint_noise: float = 0.01
    recovery: str = "trainer"
    sets: tuple[str, ...] = ("go_to_target", "sprint", "position_to_dribble")

    def __post_init__(self) -> None:
        _check_recovery(self.recovery)

    @property
    def optimize(self) -> dict[str, tuple[str, ...] | None]:
        return {"position_to_dribble": None}

    @property
    def worst(self) -> float:
        return -2.0 * FALL_PENALTY * self.blocks

    def trial(self, values: Values, seed: int) -> TrialResult:
        from optimization.dribble import DribblePhase
        from skills.navigate import Odometry

        rng = np.random.default_rng(seed)
        d = float(rng.uniform(*self.distance))
        a = float(rng.uniform(-math.pi, math.pi))
        rx, ry = d * math.cos(a), d * math.sin(a)
        heading = math.atan2(-ry, -rx) + float(rng.uniform(-math.pi / 4, math.pi / 4))
        sim = new_sim(self.robot_type, walk_sets(values), (rx, ry, heading), rng,
                      joint_noise=self.joint_noise, ball=(0.0, 0.0), vision=True)
        sim.agent.odo = Odometry(rx, ry, heading)  # told its pose once, as after a beam
        recovery = GetupRecovery() if self.recovery == "getup" else TrainerRecovery()
        results = run_phases(sim, [DribblePhase(self.seconds / self.blocks) for _ in range(self.blocks)],
                             recovery)
        return TrialResult(float(sum(r.utility for r in results)),
                           {"falls": sim.falls, "sim_seconds": round(sim.time, 2),
                            "ball": [round(float(v), 3) for v in sim.world.ball_position()[:2]],
                            "set_cycles": dict(sim.agent.set_cycles)})


def position_to_dribble(robot_type: int = 0, seconds: float = 15.0, recovery: str = "trainer"
                        ) -> DribbleTask:
    return DribbleTask(robot_type=robot_type, seconds=seconds, recovery=recovery)


@dataclass(frozen=True)
class AnalyticTask:
    """fitness = -f(x - shift) (+ noise), x the first `dim` coordinates of the "analytic" set.

    function: "sphere" (sum of squares) or "rosenbrock"; the optimum is at
    x = shift = (1, -1, 2, -2, ...) / 2 with fitness 0. noise: sigma of Gaussian
    noise added per trial (from the trial's seed); delay: seconds each trial
    sleeps, standing for an expensive one (tests of kills and parallelism)."""

    name: str = "sphere"
    dim: int = 4
    noise: float = 0.0
    delay: float = 0.0
    sets: tuple[str, ...] = ("analytic",)

    @property
    def optimize(self) -> dict[str, tuple[str, ...]]:
        return {"analytic": ANALYTIC_NAMES[:self.dim]}

    @property
    def worst(self) -> float:
        return -1e6

    def shift(self) -> np.ndarray:
        k = np.arange(self.dim)
        return 0.5 * (k // 2 + 1) * np.where(k % 2 == 0, 1.0, -1.0)

    def trial(self, values: Values, seed: int) -> TrialResult:
        x = np.array([values["analytic"][n] for n in ANALYTIC_NAMES[:self.dim]])
        y = x - self.shift()
        if self.name == "rosenbrock":
            z = y + 1.0  # optimum of the standard function at 1
            f = float(np.sum(100.0 * (z[1:] - z[:-1] ** 2) ** 2 + (1.0 - z[:-1]) ** 2))
        else:
            f = float(y @ y)
        noise = float(np.random.default_rng(seed).normal(0.0, self.noise)) if self.noise > 0 else 0.0
        if self.delay > 0:
            time.sleep(self.delay)
        return TrialResult(-f + noise, {"f": f})


def _analytic(name: str) -> Callable[..., AnalyticTask]:
    def make(robot_type: int = 0, dim: int = 4, noise: float = 0.0, delay: float = 0.0) -> AnalyticTask:
        if not 1 <= int(dim) <= len(ANALYTIC_NAMES):
            raise ValueError(f"dim must be 1 to {len(ANALYTIC_NAMES)}, not {dim}")
        if noise < 0 or delay < 0:
            raise ValueError("noise and delay must not be negative")
        return AnalyticTask(name, int(dim), float(noise), float(delay))
    return make


TASKS: dict[str, Callable[..., Task]] = {
    "go_to_target": go_to_target,
    "sprint": sprint,
    "walk_forward": walk_forward,
    "position_to_dribble": position_to_dribble,
    "getup_front": getup_front,  # optimization.getup
    "getup_back": getup_back,
    "kick_distance": kick_distance,  # optimization.kick
    "long_kick": long_kick,
    "kick_walking": kick_walking,
    "approach": approach,  # the ball approach, kick frozen
    "dribble_walk": dribble_walk,  # optimization.dribble_walk
    "position_walk": position_walk,  # optimization.position_walk
    "sphere": _analytic("sphere"),
    "rosenbrock": _analytic("rosenbrock"),
}


def make_task(name: str, robot_type: int = 0, **options) -> Task:
    """Build a registered task; options are the factory's keywords (strings are converted
    to the type of the keyword's default)."""
    import inspect

    try:
        factory = TASKS[name]
    except KeyError:
        raise ValueError(f"unknown task {name!r}; tasks are {', '.join(TASKS)}") from None
    sig = inspect.signature(factory)
    kw = {}
    for k, v in options.items():
        if k not in sig.parameters or k == "robot_type":
            known = [p for p in sig.parameters if p != "robot_type"]
            raise ValueError(f"task {name} has no option {k!r}; options are {', '.join(known) or 'none'}")
        default = sig.parameters[k].default
        if isinstance(v, str) and not isinstance(default, str):
            try:
                v = type(default)(v)
            except ValueError:
                raise ValueError(f"option {k} of task {name} must be a {type(default).__name__}, "
                                 f"not {v!r}") from None
        kw[k] = v
    return factory(robot_type=robot_type, **kw)

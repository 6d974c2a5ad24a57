"""Getup optimization tasks (dissertation Appendix A, L1,1 / L1,2: Getup_Front/Back_Primitive).

The trainer lays the robot on its front or back (`World.place_robot(...,
lying=...)`) at a seeded random heading and spot, with seeded random joint
angles (about 0, or with ``start="walk"`` about the walk's stand pose, as a
robot that falls while walking lands), and lets it settle holding them for
`settle` seconds. Then the getup skills (`skills.falls.Getup`: fall detection,
GETUP_FRONT / GETUP_BACK, the side rolls) play from the robot's percepts alone for
`seconds` (4 s, as UT's),
their joint targets turned into velocities as an agent's body does in a match
(`skills.motion.Motion.recover`: PID plus feed-forward, then the walk's stand),
or, with ``controller="pid"``, by the plain joint PID the getup benchmark and
tests use.

fitness = -(time not standing) over those seconds (s), where standing is judged
from ground truth every 20 ms cycle: torso up-vector z above `UP_MIN` and
torso height above `HEIGHT_FRACTION` of the robot type's standing height.

Parameter sets: "getup_front" (the ``front_*`` ``$parameters`` of
``getup_front.skl``) and "getup_back" (``back_*`` of ``getup_back.skl``),
file units (degrees, seconds); defaults from ``skills/data/getup.params``.
A learned file (``front_k1_arm<TAB>...``) loads with
`skills.falls.load_getup_skills([path])`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from models import nao
from models.messages import Action
from models.rules import CYCLE
from models.scene import Lineup
from optimization.types import ParamSetDef, ParamSpec, TrialResult, Values
from server.trainer import Trainer
from skills.control import JointPid
from skills.falls import GETUP_FILES, Getup, getup_param_paths
from skills.motion import Motion
from skills.params import UNITS, load_params
from skills.skill import Skill, read_skills, skill_path
from skills.walk import WalkEngine

UP_MIN = 0.9  # torso up-vector z above this counts as upright (ground truth)
HEIGHT_FRACTION = 0.8  # torso height above this fraction of the standing height counts as standing
CONTROLLERS = ("motion", "pid")
STARTS = ("flat", "walk")  # the joints the robot lies with: about 0, or about the walk's stand pose
TASK_STARTS = STARTS + ("mixed",)  # the task's: "mixed" draws flat or walk each trial
WALK_NOISE = 0.05  # rad, sigma of the joint angles about the walk's stand pose (start "walk")
SIDES = {"getup_front": ("front", "front_"), "getup_back": ("back", "back_")}  # set -> (lying, prefix)

# Scales (CMA-ES sigma) and bounds by the slot a parameter fills, file units.
# Angles may pass a joint's range (the player clips targets to it): the optimizer
# learned such values (a knee target of -188 deg drives the knee to its stop fast).
_SLOT_SIGMA = {"arm": 10.0, "aroll": 8.0, "elbow": 8.0, "yaw": 6.0, "hip": 6.0, "knee": 6.0,
               "ankle": 6.0, "wait": 0.05}
ANGLE_BOUNDS = (-200.0, 200.0)  # deg
WAIT_BOUNDS = (0.02, 1.5)  # s


def lying_joints(robot_type: int, rng: np.random.Generator, start: str = "flat",
                 joint_noise: float = 0.15) -> np.ndarray:
    """Joint angles (rad, league order, within the joints' limits) a robot lies with for a
    getup: about 0 (start "flat", sigma `joint_noise`; the start the getups were learned
    from) or about the walk's stand pose (start "walk", sigma WALK_NOISE), knees bent and
    arms at the sides, as a robot that falls while walking lands."""
    if start not in STARTS:
        raise ValueError(f"start must be one of {', '.join(STARTS)}, not {start!r}")
    specs = nao.joints(robot_type)
    lo, hi = np.array([j.lower for j in specs]), np.array([j.upper for j in specs])
    if start == "flat":
        return np.clip(rng.normal(0.0, joint_noise, len(specs)), lo, hi)
    return np.clip(_walk_stand(robot_type) + rng.normal(0.0, WALK_NOISE, len(specs)), lo, hi)


@functools.cache
def _walk_stand(robot_type: int) -> np.ndarray:
    """The walk's stand pose (rad, league order; 0 where the walk sets nothing), built
    once a type (a walk engine takes about 6 ms, a getup trial about 100)."""
    stand = WalkEngine(robot_type).update(0.0, 0.0, 0.0).targets
    out = np.where(np.isnan(stand), 0.0, stand)
    out.flags.writeable = False
    return out


def getup_schema() -> dict[str, str]:
    """Every ``$parameter`` of the getup skill files and its unit ("deg" or "s")."""
    schema: dict[str, str] = {}
    for name in GETUP_FILES:
        schema.update(read_skills(skill_path(name)).schema)
    return schema


def getup_param_set(set_name: str) -> ParamSetDef:
    """The "getup_front" or "getup_back" parameter set: prefix ``front_``/``back_``,
    every parameter of that skill optimized with a sigma by its slot."""
    prefix = SIDES[set_name][1]
    schema = {n[len(prefix):]: u for n, u in getup_schema().items() if n.startswith(prefix)}
    specs = []
    for n, unit in schema.items():
        sigma = _SLOT_SIGMA.get(n.rsplit("_", 1)[-1], 6.0 if unit == "deg" else 0.05)
        lo, hi = WAIT_BOUNDS if unit == "s" else ANGLE_BOUNDS
        specs.append(ParamSpec(n, sigma, lo, hi))
    return ParamSetDef(name=set_name, prefix=prefix, schema=schema, specs=tuple(specs),
                       defaults=getup_param_files)


def getup_param_files(robot_type: int) -> list[str]:
    """The shipped getup parameter files of a robot type (`skills.falls.getup_param_paths`)."""
    return getup_param_paths(robot_type)


def getup_skills(values: Mapping[str, Mapping[str, float]],
                 robot_type: int | None = None) -> dict[str, Skill]:
    """The getup and roll skills bound to the shipped parameters of `robot_type`,
    overridden by `values` (``{"getup_front": {"k1_arm": deg, ...}, ...}``, file
    units) where given."""
    sources = [read_skills(skill_path(name)) for name in GETUP_FILES]
    schema = getup_schema()
    params = load_params(getup_param_paths(robot_type), schema)
    for set_name, vals in values.items():
        if set_name not in SIDES:
            continue
        prefix = SIDES[set_name][1]
        for n, v in vals.items():
            params[prefix + n] = float(v) * UNITS[schema[prefix + n]]
    out: dict[str, Skill] = {}
    for src in sources:
        out.update(src.bind(params))
    return out


@dataclass(frozen=True)
class GetupTask:
    """Lie on the front or back, then get up from percepts; fitness -(s not standing).

    name: "getup_front" or "getup_back" (also the learned set); seconds: the
    measured span after the getup starts (s); settle: s lying still first;
    joint_noise: sigma (rad) of the random joint angles held while lying;
    place_noise: the lying pose's height above the ground is raised by up to this (m),
    so the robot drops onto the ground a little differently every trial;
    all_types: 1 draws the robot type of each trial from its seed among 0-4
    (the getup parameters are shared by every type), 0 uses `robot_type`;
    controller: "motion" drives the joints as an agent does in a match
    (`Motion.recover`: the getup through `Motion.command`, then the walk's stand),
    "pid" as `benchmarks/getup.py` does (plain `JointPid`, the getup's last pose held);
    fail_penalty: s taken off a trial that does not end standing (0, UT's fitness,
    trades a surer getup for a faster one; the benchmark wants it sure);
    start: "flat" lies with joint angles about 0 (sigma joint_noise), "walk" about
    the walk's stand pose (sigma WALK_NOISE), as `benchmarks.getup --start walk`;
    "mixed" draws one of the two from each trial's seed (a getup learned from one
    start alone got worse from the other).
    """

    name: str = "getup_front"
    robot_type: int = 0
    seconds: float = 4.0
    settle: float = 0.5
    joint_noise: float = 0.15
    place_noise: float = 0.03
    all_types: int = 0
    controller: str = "motion"
    fail_penalty: float = 0.0
    start: str = "flat"

    def __post_init__(self) -> None:
        if self.name not in SIDES:
            raise ValueError(f"getup task must be one of {', '.join(SIDES)}, not {self.name!r}")
        if self.controller not in CONTROLLERS:
            raise ValueError(f"controller must be one of {', '.join(CONTROLLERS)}, not {self.controller!r}")
        if self.start not in TASK_STARTS:
            raise ValueError(f"start must be one of {', '.join(TASK_STARTS)}, not {self.start!r}")
        if not self.fail_penalty >= 0.0:
            raise ValueError(f"fail_penalty must be at least 0 s, not {self.fail_penalty!r}")

    @property
    def sets(self) -> tuple[str, ...]:
        return (self.name,)

    @property
    def optimize(self) -> dict[str, tuple[str, ...] | None]:
        return {self.name: None}

    @property
    def worst(self) -> float:
        """Never standing."""
        return -self.seconds - self.fail_penalty

    def trial(self, values: Values, seed: int) -> TrialResult:
        rng = np.random.default_rng(seed)
        robot_type = int(rng.integers(5)) if self.all_types else self.robot_type
        lying = SIDES[self.name][0]
        trainer = Trainer(Lineup((robot_type,), ()), seed=int(rng.integers(2**31)), vision=False)
        world = trainer.world
        start = STARTS[int(rng.integers(2))] if self.start == "mixed" else self.start
        q0 = lying_joints(robot_type, rng, start, self.joint_noise)
        world.place_ball((10.0, 8.0))
        world.place_robot(0, float(rng.uniform(-2.0, 2.0)), float(rng.uniform(-2.0, 2.0)),
                          float(rng.uniform(-math.pi, math.pi)), joints=q0, lying=lying)
        world.settle_height(0)
        world.data.qpos[world.players[0].root_qpos + 2] += float(rng.uniform(0.0, self.place_noise))

        motion = Motion(robot_type)
        for _ in range(round(self.settle / CYCLE)):
            pc = trainer.percepts()[0]
            trainer.step({0: Action(motion.command(q0, pc))})
        motion.reset()
        getup = Getup(robot_type, getup_skills(values, robot_type))
        pid = JointPid.for_robot(robot_type)
        if self.controller == "motion":
            motion.getup = getup
        stand = nao.standing_height(robot_type)
        hold: np.ndarray | None = None
        down = 0
        first_up: float | None = None
        up = False
        for k in range(round(self.seconds / CYCLE)):
            pc = trainer.percepts()[0]
            if self.controller == "motion":  # as an agent: getup, then the walk's stand
                v = motion.recover(pc)
                if v is None:
                    v = motion.walk_step(pc, 0.0, 0.0, 0.0)
            else:  # as benchmarks/getup.py: plain joint PID, the getup's last pose held
                target = getup.step(pc.time, pc.joints, pc.accel, pc.gyro)
                if target is None:
                    target = getup.hold()  # the end pose, balanced
                if target is not None:
                    hold = target.copy()
                elif hold is None:
                    hold = pc.joints.copy()
                v = pid(hold, pc.joints).copy()
            trainer.step({0: Action(v)})
            up = bool(world.torso_up()[0] > UP_MIN
                      and world.torso_positions()[0, 2] > HEIGHT_FRACTION * stand)
            if up:
                first_up = (k + 1) * CYCLE if first_up is None else first_up
            else:
                down += 1
        not_standing = down * CYCLE
        fitness = -not_standing - (0.0 if up else self.fail_penalty)
        return TrialResult(fitness, {"robot_type": robot_type, "first_up": first_up,
                                     "getups": getup.count, "standing_at_end": up,
                                     "start": start})


def getup_front(robot_type: int = 0, seconds: float = 4.0, joint_noise: float = 0.15,
                all_types: int = 0, controller: str = "motion", fail_penalty: float = 0.0,
                start: str = "flat") -> GetupTask:
    return GetupTask("getup_front", robot_type, seconds, joint_noise=joint_noise, all_types=all_types,
                     controller=controller, fail_penalty=fail_penalty, start=start)


def getup_back(robot_type: int = 0, seconds: float = 4.0, joint_noise: float = 0.15,
               all_types: int = 0, controller: str = "motion", fail_penalty: float = 0.0,
               start: str = "flat") -> GetupTask:
    return GetupTask("getup_back", robot_type, seconds, joint_noise=joint_noise, all_types=all_types,
                     controller=controller, fail_penalty=fail_penalty, start=start)

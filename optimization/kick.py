"""Kick trials and the kick optimization tasks (dissertation Appendix A: fixed-distance
kicks, the long kick, the kick from a walking approach).

`kick_trial` is one kick in a fresh one-robot world, shared with
`benchmarks/kick.py`. The robot is driven by `agent.kicker.Kicker` from its
percepts alone (vision every third cycle, dead reckoning from the start pose,
as after a beam); ground truth only measures:

* standing: the robot stands at the kick's pose behind the ball (within 1 cm
  and 2 deg), watches the ball for a random `LOOK` s (seeded; by then its stand
  rocks on its feet at about 6.5 Hz, at a random phase, as after any wait in play),
  then kicks toward the kick's own direction;
* walking: it starts 1 to 2 m from the ball at a random bearing, facing the
  ball, and must approach and kick toward a target in a random direction.

Measured: the ball's travel until it stops (rolled in physics for `ROLL_LIMIT` s
after contact, then extrapolated under its drag and rolling friction),
its progress toward the target, its direction (deg, signed: + to the left of the
target) and direction error, whether the robot fell
(torso up-vector z < 0.5 at any time), the time from the start to the
robot's first contact with the ball during the kick, and how far the ball was
moved before a kick began (`bumped`: the approach running into it).

Tasks (fitness higher is better; `FALL_PENALTY` per fall):

* ``kick_distance`` (``distance=D``): a standing kick should stop the ball at
  D m straight along its direction; fitness = -(distance from the ball's stop
  to that point) (m). Learns the keyframe kick set given by ``set=`` (default
  ``kick``).
* ``long_kick`` (``fall=P``: P m per fall instead of `FALL_PENALTY`): a standing
  kick as far as possible along its direction; fitness = progress toward the
  target (m) - |lateral miss| / 2.
* ``kick_walking``: approach from 1-2 m and kick; fitness = progress toward
  the target (m) - 0.2 x seconds until contact.
* ``approach`` (``kick=NAME``, default ``ik_forward``; ``any``: each trial
  draws one of the type's shipped kicks): learns the ball approach (the
  ``approach`` set, starting from the type's shipped files,
  `skills.approach.approach_param_paths`) with the kick frozen: a walking trial
  as ``kick_walking``, feet drawn at random; fitness =
  progress toward the target capped at `APPROACH_CAP` m (the kick's own reach
  is not the approach's merit) - 0.2 x seconds until contact.

Frames: the field frame (m, rad).
"""

from __future__ import annotations

import copy
import functools
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from agent.kicker import DONE, KICK, Kicker
from models.messages import Action
from models.scene import Lineup
from optimization.phases import FALL_PENALTY, WalkAgent
from optimization.types import ParamSetDef, ParamSpec, TrialResult, Values
from server.trainer import Trainer
from skills.approach import APPROACH_SCHEMA, ApproachParams, approach_param_paths, kick_pose
from skills.kicks import KickSkill, all_kicks
from skills.kicks.keyframe import (
    BASE_SET,
    FOOT_NAME,
    KICK_FILE,
    KeyframeKick,
    kick_schema,
    load_kick_sets,
    make_keyframe_kick,
)
from skills.kicks.keyframe import default_param_files as kick_param_files
from skills.params import UNITS
from skills.skill import read_skills, skill_path
from skills.walk import WalkParams

if TYPE_CHECKING:
    from server.world import World

BALL = (-5.0, 0.0)  # m, field frame: where the ball starts
APPROACH_LIMIT = 25.0  # s to reach the ball and start the kick
ROLL_LIMIT = 4.0  # s after contact that the ball rolls in physics; the rest is extrapolated
STOPPED = 0.02  # m/s: the ball counts as stopped below this speed
FALLEN_UP = 0.5  # torso up-vector z below which the robot has fallen
MIN_TOWARD = 1.0  # m toward the target for a success
LOOK = (0.6, 1.2)  # s: a standing robot watches the ball this long (uniform) before kicking
MODES = ("standing", "walking")


def kick_trial(robot_type: int, kick: KickSkill, mode: str, rng: np.random.Generator,
               seed: int, approach: ApproachParams | None = None,
               observe: Callable[[World], None] | None = None,
               spread: tuple[float, float] = (0.01, 2.0),
               walk_sets: Mapping[str, WalkParams] | None = None) -> dict:
    """One kick (`mode` "standing" or "walking"); its measurements (m, deg, s; ground truth).

    approach: the ball approach's parameters (default: the type's shipped ones);
    walk_sets: the walk's sets (default: the type's shipped ones);
    observe: called with the world after every cycle (measurements of a benchmark);
    spread: standing, the standard deviations of the robot's placement about the
    kick pose (m on x and y, deg on the heading)."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
    tr = Trainer(Lineup((robot_type,), ()), seed=seed)
    w = tr.world
    ball = np.array(BALL)
    w.place_ball(ball)
    kicker = Kicker(robot_type, {kick.spec.name: kick}, walk_sets, approach=approach)
    if mode == "standing":
        target_dir = kick.spec.direction
        target = ball + 10.0 * np.array([math.cos(target_dir), math.sin(target_dir)])
        x, y, h = kick_pose(ball, target, kick.spec)
        x, y = x + rng.normal(0.0, spread[0]), y + rng.normal(0.0, spread[0])
        heading = h + math.radians(rng.normal(0.0, spread[1]))
        look = float(rng.uniform(*LOOK))
    else:
        d, a = rng.uniform(1.0, 2.0), rng.uniform(-math.pi, math.pi)
        x, y = ball[0] + d * math.cos(a), ball[1] + d * math.sin(a)
        heading = math.atan2(ball[1] - y, ball[0] - x)
        target_dir = rng.uniform(-math.pi, math.pi)
        target = ball + 10.0 * np.array([math.cos(target_dir), math.sin(target_dir)])
        look = 0.0
    stand = WalkAgent(robot_type, kicker.motion.walk.sets).stand_pose()
    w.place_robot(0, x, y, heading, joints=stand)
    w.settle_height(0)
    kicker.start((x, y, heading), (float(target[0]), float(target[1])), approach=mode == "walking")
    t0 = w.time
    contact = None
    fell = False
    bumped = 0.0  # m: farthest the ball moved from its spot before a kick began
    end = t0 + APPROACH_LIMIT
    while w.time < end:
        percept = tr.percepts()[0]
        if mode == "standing" and kicker.kick_started is None and w.time - t0 >= look:
            kicker.kick_now(percept)  # after watching the ball `look` s
        touched = tr.step({0: Action(kicker.act(percept))})
        if kicker.kick_started is None:  # the approach ran into the ball?
            bumped = max(bumped, float(np.linalg.norm(w.ball_position()[:2] - ball)))
        if observe is not None:
            observe(w)
        fell = fell or bool(w.torso_up()[0] < FALLEN_UP)
        if kicker.state == KICK and contact is None:
            end = max(end, w.time + 1.0)  # a kick that started always gets to finish
        if contact is None and 0 in touched and kicker.state in (KICK, DONE):
            contact = w.time - t0
            end = w.time + ROLL_LIMIT
        if contact is not None and kicker.state == DONE and np.linalg.norm(w.ball_velocity()[:2]) < STOPPED:
            break
    moved = w.ball_rest_position() - ball  # a ball still rolling is carried on to its stop
    u = np.array([math.cos(target_dir), math.sin(target_dir)])
    toward = float(moved @ u)
    lateral = float(moved[1] * u[0] - moved[0] * u[1])
    dist = float(np.linalg.norm(moved))
    # deg, + = counterclockwise (left) of the target's direction
    direction = (math.degrees(math.remainder(math.atan2(moved[1], moved[0]) - target_dir, 2 * math.pi))
                 if dist > 0.1 else None)
    err = abs(direction) if direction is not None else None
    return {"distance": dist, "toward": toward, "lateral": lateral, "direction": direction,
            "direction_error": err,
            "fell": fell, "contact_s": contact, "kicked": kicker.kick_started is not None, "bumped": bumped,
            "success": toward >= MIN_TOWARD and not fell, "sim_s": round(w.time, 2)}


# ----------------------------------------------------------------- parameter sets

# Optimization scales (CMA-ES sigma) and bounds by unit, file units (waits in s; the
# balance gains and the slew rate have their own below).
_SIGMA = {"deg": 6.0, "s": 0.04, "mm": 8.0}
_BOUNDS = {"deg": (-200.0, 200.0), "s": (0.02, 1.5), "mm": (-300.0, 300.0)}
FIXED = ("tol_x", "tol_y", "tol_angle", "distance", "direction")  # spec fields never learned
# k3b, the start of the swing, is skipped at a wait of 0 (every kick but the long kick)
_OWN_BOUNDS = {"k3b_wait": (0.0, 1.5)}


def kick_param_set(set_name: str) -> ParamSetDef:
    """A keyframe kick's parameter set (prefix ``<set>_``): the skill's ``$parameters``
    and the ball offset, with sigma and bounds by unit; it inherits the ``kick`` set."""
    schema = kick_schema()
    specs = []
    for n, u in schema.items():
        if n in FIXED:
            continue
        if n.startswith("bal_"):  # balance feedback gains (1, or s for the gyro terms): any sign
            specs.append(ParamSpec(n, 0.02 if u == "s" else 0.1))
        elif n == "slew":  # deg/s of the slow keyframes
            specs.append(ParamSpec(n, 20.0, 10.0, 2000.0))
        elif n == "base_slew":  # deg/s into the base pose (0: at once)
            specs.append(ParamSpec(n, 20.0, 0.0, 2000.0))
        else:
            bounds = _OWN_BOUNDS.get(n, _BOUNDS.get(u, (-math.inf, math.inf)))
            specs.append(ParamSpec(n, _SIGMA.get(u, 0.05), *bounds))
    specs = tuple(specs)
    return ParamSetDef(name=set_name, prefix=f"{set_name}_", schema=schema, specs=specs,
                       defaults=kick_param_files, inherit=None if set_name == BASE_SET else BASE_SET)


def shipped_kick_sets() -> tuple[str, ...]:
    """The keyframe kick sets of the shipped files ("kick", "long_kick", "kick_5m", ...)."""
    return tuple(load_kick_sets(kick_param_files(None)))


def keyframe_kick(values: Values, set_name: str, robot_type: int, foot: str = "l") -> KeyframeKick:
    """The keyframe kick of `set_name` bound to `values[set_name]` (file units) over the shipped
    values of the robot type."""
    source = read_skills(skill_path(KICK_FILE))
    sets = load_kick_sets(kick_param_files(robot_type), source)
    base = dict(sets.get(set_name, sets[BASE_SET]))
    schema = kick_schema(source)
    for n, v in values.get(set_name, {}).items():
        base[n] = float(v) * UNITS[schema[n]]
    return make_keyframe_kick(source, set_name, base, foot, robot_type)


# Optimization scales and bounds of the approach's parameters (file units: m, mm, s, 1).
APPROACH_SPECS = {
    "max_decel_x": (0.03, 0.02, 1.0), "max_decel_y": (0.02, 0.02, 1.0), "buffer": (2.0, 0.0, 30.0),
    "turn_gain": (0.2, 0.1, 4.0), "max_turn": (0.06, 0.05, 1.0), "max_speed": (0.1, 0.1, 1.0),
    "near": (0.05, 0.15, 0.8), "around": (0.05, 0.25, 0.8), "stage": (0.03, 0.0, 0.5),
    "stop": (0.05, 0.02, 1.0), "creep": (0.05, 0.05, 1.0), "lead": (0.01, -0.1, 0.1),
    "settle": (0.06, 0.1, 1.5), "smooth": (0.03, 0.0, 1.0), "lookahead": (0.02, 0.0, 0.5),
    "fix_time": (0.1, 0.1, 2.0), "fix_turn_gain": (0.2, 0.1, 4.0), "fix_max_turn": (0.06, 0.05, 1.0),
    "back": (0.015, 0.0, 0.3), "fast": (0.1, 0.1, 2.0), "fast_creep": (0.03, 0.0, 0.6),
    "after_align": (0.1, 1.0, 2.5), "enter_turn": (10.0, 10.0, 180.0),
    "around_turn_gain": (0.5, 0.5, 4.0),
}
assert set(APPROACH_SPECS) == set(APPROACH_SCHEMA)
ANY_KICK = "any"  # the approach task's kick option: a shipped kick drawn per trial
APPROACH_CAP = 4.0  # m of progress toward the target that an approach trial counts


def approach_param_set() -> ParamSetDef:
    """The ball approach's parameter set ``approach`` (prefix ``approach_``, the walk set
    approach_to_kick shares the prefix with disjoint names)."""
    specs = tuple(ParamSpec(n, *APPROACH_SPECS[n]) for n in APPROACH_SCHEMA)
    return ParamSetDef(name="approach", prefix="approach_", schema=APPROACH_SCHEMA, specs=specs,
                       defaults=lambda robot_type: [str(p) for p in approach_param_paths(robot_type)])


def approach_params(values: Values, robot_type: int | None = None) -> ApproachParams:
    """The approach bound to `values["approach"]` (file units) over the shipped values
    (robot_type's own where it has them)."""
    base = ApproachParams.load(robot_type=robot_type)
    si = {n: float(v) * UNITS[APPROACH_SCHEMA[n]] for n, v in values.get("approach", {}).items()}
    return replace(base, **si)


# ----------------------------------------------------------------------- tasks

KINDS = ("kick_distance", "long_kick", "kick_walking")


@dataclass(frozen=True)
class KickTask:
    """A keyframe kick trial; see the module docstring for the kinds and their fitness.

    kind: one of `KINDS`; set: the learned keyframe kick set; distance: m, the
    fixed-distance kick's target; feet: trials alternate feet when 2, else left;
    fall: fitness lost per fall (m; `FALL_PENALTY` unless a task asks for more).
    """

    name: str = "kick_distance"
    robot_type: int = 0
    set: str = BASE_SET
    distance: float = 5.0
    feet: int = 2
    fall: float = FALL_PENALTY

    def __post_init__(self) -> None:
        if self.name not in KINDS:
            raise ValueError(f"kick task must be one of {', '.join(KINDS)}, not {self.name!r}")
        if self.distance <= 0:
            raise ValueError(f"distance must be positive, not {self.distance}")
        if self.fall < 0:
            raise ValueError(f"fall must not be negative, not {self.fall}")

    @property
    def sets(self) -> tuple[str, ...]:
        return (self.set,)

    @property
    def optimize(self) -> Mapping[str, tuple[str, ...] | None]:
        return {self.set: None}

    @property
    def worst(self) -> float:
        return -self.fall - 2.0 * self.distance - 10.0

    def trial(self, values: Values, seed: int) -> TrialResult:
        rng = np.random.default_rng(seed)
        foot = "lr"[int(rng.integers(2))] if self.feet == 2 else "l"
        kick = keyframe_kick(values, self.set, self.robot_type, foot)
        mode = "walking" if self.name == "kick_walking" else "standing"
        r = kick_trial(self.robot_type, kick, mode, rng, int(rng.integers(2**31)))
        if self.name == "kick_distance":
            fitness = -math.hypot(r["toward"] - self.distance, r["lateral"])
        elif self.name == "long_kick":
            fitness = r["toward"] - 0.5 * abs(r["lateral"])
        else:
            fitness = r["toward"] - 0.2 * (r["contact_s"] if r["contact_s"] is not None else APPROACH_LIMIT)
        fitness -= self.fall * r["fell"]
        return TrialResult(float(fitness), {**r, "foot": FOOT_NAME[foot]})


@functools.lru_cache(maxsize=5)
def _shipped_kicks(robot_type: int) -> dict[str, KickSkill]:
    """Every shipped kick of a type, built once per process (60 ms: not per trial)."""
    return all_kicks(robot_type)


@dataclass(frozen=True)
class ApproachTask:
    """Walking approach and kick with a frozen kick; learns the ``approach`` set.

    kick: the kick's name without its foot (``ik_forward``, ``kick``, ...), or
    ``any``: each trial draws one of the type's shipped kicks."""

    name: str = "approach"
    robot_type: int = 0
    kick: str = "ik_forward"

    def __post_init__(self) -> None:
        names = {n.rsplit("_", 1)[0] for n in _shipped_kicks(self.robot_type)} | {ANY_KICK}
        if self.kick not in names:
            raise ValueError(f"kick must be one of {', '.join(sorted(names))}, not {self.kick!r}")

    @property
    def sets(self) -> tuple[str, ...]:
        return ("approach",)

    @property
    def optimize(self) -> Mapping[str, tuple[str, ...] | None]:
        return {"approach": None}

    @property
    def worst(self) -> float:
        return -FALL_PENALTY - 0.2 * APPROACH_LIMIT - 10.0

    def draw_kick(self, rng: np.random.Generator) -> str:
        """The shipped kick (with its foot) a trial plays, drawn from `rng`."""
        if self.kick == ANY_KICK:
            names = sorted(_shipped_kicks(self.robot_type))
            return names[int(rng.integers(len(names)))]
        return f"{self.kick}_{('left', 'right')[int(rng.integers(2))]}"

    def trial(self, values: Values, seed: int) -> TrialResult:
        rng = np.random.default_rng(seed)
        name = self.draw_kick(rng)
        kick = copy.deepcopy(_shipped_kicks(self.robot_type)[name])  # fresh state
        r = kick_trial(self.robot_type, kick, "walking", rng, int(rng.integers(2**31)),
                       approach_params(values, self.robot_type))
        fitness = min(r["toward"], APPROACH_CAP) - 0.2 * (
            r["contact_s"] if r["contact_s"] is not None else APPROACH_LIMIT)
        fitness -= FALL_PENALTY * r["fell"]
        return TrialResult(float(fitness), {**r, "kick": name})


def approach(robot_type: int = 0, kick: str = "ik_forward") -> ApproachTask:
    return ApproachTask("approach", robot_type, kick)


def kick_distance(robot_type: int = 0, distance: float = 5.0, set: str = BASE_SET) -> KickTask:
    return KickTask("kick_distance", robot_type, set, distance)


def long_kick(robot_type: int = 0, set: str = "long_kick", fall: float = FALL_PENALTY) -> KickTask:
    return KickTask("long_kick", robot_type, set, fall=fall)


def kick_walking(robot_type: int = 0, set: str = BASE_SET) -> KickTask:
    return KickTask("kick_walking", robot_type, set)


__all__ = ["APPROACH_CAP", "ApproachTask", "KINDS", "KickTask", "approach", "approach_param_set",
           "approach_params", "kick_distance", "kick_param_set", "kick_trial", "kick_walking",
           "keyframe_kick", "long_kick", "shipped_kick_sets"]

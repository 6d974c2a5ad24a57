"""Fall detection from the accelerometer and gyro (dissertation section 8.2.4).

At rest the accelerometer reads the specific force, +9.81 m/s^2 along the
world's up axis, in the torso frame (x forward, y left, z up). Upright it is
all on z; lying face down the up axis is the torso's -x, face up its +x. UT
Austin Villa thresholds the x and y components; here a low-pass filtered
accelerometer gives the torso's tilt from vertical, and the robot counts as
fallen when the tilt passes `fallen_tilt`. The gyro flags a fall in progress
(tilted past `falling_tilt` and still turning fast), so a behavior can
brace (`FALL_ARMS` in ``roll.skl`` stretches the arms sideways so that the
robot lands on its front or back, never on its side).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from models import nao
from skills.imu import GRAVITY
from skills.params import PathLike, load_params, with_type_file
from skills.skill import Skill, SkillPlayer, read_skills, skill_path

UPRIGHT, FALLING, FRONT, BACK, LEFT, RIGHT = "upright", "falling", "front", "back", "left", "right"


@dataclass
class FallDetector:
    """Classifies the torso's posture every cycle from accelerometer (m/s^2) and gyro (rad/s).

    `state` is UPRIGHT, FALLING, or, once fallen, the side the robot lies on:
    FRONT (face down), BACK (face up), LEFT or RIGHT (its left or right side down).
    """

    fallen_tilt: float = math.radians(60.0)  # rad from vertical: fallen beyond
    falling_tilt: float = math.radians(30.0)  # rad: falling beyond, if also turning fast
    falling_rate: float = 1.5  # rad/s of gyro x-y rate that counts as "fast"
    rest_rate: float = 1.0  # rad/s: a fallen robot turning slower than this has landed
    # m/s^2: at rest the accelerometer reads gravity alone. Walking, foot strikes swing
    # it by 20-30 m/s^2 (z even reads -20 upright), enough to tip the low-passed vector
    # past fallen_tilt for several calm-gyro cycles: a getup then started on an upright
    # walking robot (benchmarks.walk's course, type 3).
    rest_accel: float = 2.5
    settle_cycles: int = 5  # cycles on one side, at rest, before that side is reported
    smoothing: float = 0.3  # weight of a new accelerometer sample in the low-pass filter

    def __post_init__(self) -> None:
        self.reset()

    def reset(self) -> None:
        """Forget the filtered accelerometer (assume upright)."""
        self.accel = np.array([0.0, 0.0, GRAVITY])
        self.state = UPRIGHT
        self._side = UPRIGHT
        self._count = 0

    @property
    def tilt(self) -> float:
        """Angle (rad) between the torso's z axis and the filtered specific force (vertical at rest)."""
        a = self.accel
        return math.atan2(math.hypot(a[0], a[1]), a[2])

    @property
    def fallen(self) -> bool:
        return self.state in (FRONT, BACK, LEFT, RIGHT)

    def update(self, accel: np.ndarray, gyro: np.ndarray) -> str:
        """Take one cycle's accelerometer and gyro (torso frame) and return the new `state`.

        A side is reported once the robot has lain on it at rest (turning slower than
        `rest_rate`, the accelerometer within `rest_accel` of gravity) for
        `settle_cycles` cycles; until then a tilted robot is FALLING.
        """
        accel = np.asarray(accel, dtype=float)
        self.accel += self.smoothing * (accel - self.accel)
        tilt = self.tilt
        rate = math.hypot(gyro[0], gyro[1])
        if tilt > self.fallen_tilt:
            ax, ay = self.accel[0], self.accel[1]
            if abs(ax) >= abs(ay):
                side = BACK if ax > 0 else FRONT
            else:
                side = RIGHT if ay > 0 else LEFT
            resting = (math.hypot(rate, gyro[2]) < self.rest_rate
                       and abs(math.sqrt(float(accel @ accel)) - GRAVITY) < self.rest_accel)
            self._count = self._count + 1 if side == self._side and resting else int(resting)
            self._side = side
            self.state = side if self._count >= self.settle_cycles else FALLING
        else:
            self._side, self._count = UPRIGHT, 0
            if tilt > self.falling_tilt and rate > self.falling_rate:
                self.state = FALLING
            else:
                self.state = UPRIGHT
        return self.state


GETUP_FILES = ("getup_front.skl", "getup_back.skl", "roll.skl")  # in skills/data/
GETUP_PARAMS = "getup.params"  # in skills/data/: tuned values of the getups' $parameters
SKILL_FOR = {FRONT: "GETUP_FRONT", BACK: "GETUP_BACK", LEFT: "ROLL_LEFT", RIGHT: "ROLL_RIGHT"}
# Holding a getup's last pose, the ankles pitch against the torso's fore-aft lean (from
# the filtered accelerometer): rad of ankle pitch per rad of lean. A getup that ends
# tipped back onto its heels (type 2 from the back: 26 deg, only the heels touching)
# comes down onto its soles; one that ends upright holds its pose nearly as played.
HOLD_ANKLE_GAIN = -0.5
HOLD_ANKLE_MAX = 0.3  # rad: the most the hold turns the ankles
ANKLE_PITCH = ("llj5", "rlj5")


def getup_param_paths(robot_type: int | None = None) -> list[str]:
    """The shipped getup parameter files: ``getup.params`` (every type), then
    ``getup_type<T>.params`` where robot type T has its own values."""
    return with_type_file(skill_path(GETUP_PARAMS), robot_type)


def load_getup_skills(param_paths: Iterable[PathLike] = (),
                      robot_type: int | None = None) -> dict[str, Skill]:
    """The getup and roll skills of `skills/data/`.

    Their ``$parameters`` come from `getup_param_paths` (``getup.params``, then
    the robot type's own file if it has one), then from `param_paths` (later
    files override earlier ones; e.g. a CMA-ES result). One schema covers all
    the files, so one parameter file may tune them all.
    """
    sources = [read_skills(skill_path(name)) for name in GETUP_FILES]
    schema: dict[str, str] = {}
    for src in sources:
        for name, unit in src.schema.items():
            if schema.setdefault(name, unit) != unit:
                raise ValueError(f"getup parameter {name} is used as both {schema[name]} and {unit}")
    params = load_params(getup_param_paths(robot_type) + list(param_paths), schema)
    out: dict[str, Skill] = {}
    for src in sources:
        out.update(src.bind(params))
    return out


class Getup:
    """Fall detection plus the getup skills: percept data in, joint targets out.

    Call `step` every cycle. It returns target angles (rad, league order) while
    a getup (or a roll off the side) plays, and None while the robot is upright
    and nothing plays, so that the caller's own skill (walk, kick) drives the
    joints. A getup plays to its end (open loop, as UT's); if the robot is
    still down afterwards it starts again.
    """

    def __init__(self, robot_type: int, skills: dict | None = None,
                 detector: FallDetector | None = None) -> None:
        skills = skills or load_getup_skills(robot_type=robot_type)
        self.players = {side: SkillPlayer(skills[name], robot_type) for side, name in SKILL_FOR.items()}
        self.detector = detector or FallDetector()
        self.active = None  # the side whose skill plays
        self.count = 0  # getups started
        # The last targets (rad, league order) a getup played; None (also set by a caller
        # whose recovery is over) stops `hold`.
        self.last: np.ndarray | None = None
        names = nao.joint_names(robot_type)
        self._ankles = np.array([names.index(n) for n in ANKLE_PITCH])

    @property
    def busy(self) -> bool:
        """True while a getup skill plays."""
        return self.active is not None

    def reset(self) -> None:
        self.detector.reset()
        self.active = None
        self.last = None

    def step(self, time: float, joints: np.ndarray, accel: np.ndarray, gyro: np.ndarray) -> np.ndarray | None:
        """Targets (rad) of the playing getup at `time` (s), or None when none plays."""
        state = self.detector.update(accel, gyro)
        if self.active is not None and self.players[self.active].done:
            self.active = None
        if self.active is None and state in SKILL_FOR:
            self.active = state
            self.players[state].reset()
            self.count += 1
        if self.active is None:
            return None
        self.last = self.players[self.active].step(time, joints)
        return self.last

    def hold(self) -> np.ndarray | None:
        """Targets (rad, league order) that hold the last getup's end pose while the robot
        stands up from it: the pose as played, the ankle pitches turned against the
        torso's fore-aft lean (`HOLD_ANKLE_GAIN`; the lean from `detector`'s filtered
        accelerometer, so call `step` every cycle); None before any getup has played."""
        if self.last is None:
            return None
        a = self.detector.accel
        lean = math.atan2(a[0], a[2])  # rad, + leaning back (gravity's reaction toward torso +x)
        out = self.last.copy()
        out[self._ankles] += float(np.clip(HOLD_ANKLE_GAIN * lean, -HOLD_ANKLE_MAX, HOLD_ANKLE_MAX))
        return out

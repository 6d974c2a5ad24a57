"""Keyframe kicks (dissertation 8.2.7): ``kick.skl`` played with the parameter sets of ``kick.params``.

One skill file (``skills/data/kick.skl``: KICK_LEFT and its mirror KICK_RIGHT)
serves every keyframe kick; a *parameter set* (a prefix in the parameter
files: ``kick_``, ``long_kick_``, ``kick_2m_``, ...) gives its joint angles
and waits and the kick's standing offset from the ball. Every set starts from
the ``kick_`` set and overrides what its own prefixed names give, so a
fixed-distance kick may change only its swing.

Besides the skill's ``$parameters`` (degrees, seconds) a set holds its
`KickSpec` fields, for the left foot (the right foot mirrors them):

    ball_x, ball_y   mm, robot frame: the ball's center when the kick starts
    tol_x, tol_y     mm: half-widths of the box the approach must stop in
    tol_angle        deg: half-width of the facing tolerance
    distance         m: nominal distance the ball travels (to its stop)
    direction        deg, robot frame: where the ball goes (+ left)

and the control's own values: ``bal_*`` (`Balance`, feedback from the IMU on the
support ankle) and ``slew`` (deg/s: how fast targets move outside the pull-back
and the swing, so the weight shift is gentle and only the kick is fast).

Parameter files load in order: ``kick.params``, then ``kick_type<T>.params``
when it exists for the robot type, then the caller's files (e.g. a CMA-ES
result); later files override earlier ones. Values are SI inside.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

from models.messages import Percept
from models.rules import CYCLE
from skills.imu import TiltEstimator
from skills.kicks.spec import KickSpec
from skills.params import ParamError, PathLike, convert, read_entries, require, with_type_file
from skills.skill import Skill, SkillPlayer, SkillSource, read_skills, skill_path

KICK_FILE = "kick.skl"  # in skills/data/
KICK_PARAMS = "kick.params"  # in skills/data/; kick_type<T>.params beside it: a type's overrides
BASE_SET = "kick"  # every set starts from this one's values
SKILL_FOR_FOOT = {"l": "KICK_LEFT", "r": "KICK_RIGHT"}
FOOT_NAME = {"l": "left", "r": "right"}

# The KickSpec fields of a parameter set and their units in the files.
SPEC_SCHEMA: dict[str, str] = {
    "ball_x": "mm", "ball_y": "mm", "tol_x": "mm", "tol_y": "mm", "tol_angle": "deg",
    "distance": "m", "direction": "deg",
}
# The support ankle's balance feedback (`Balance`): gains on the torso's tilt and rate.
BALANCE_SCHEMA: dict[str, str] = {"bal_roll": "1", "bal_droll": "s", "bal_pitch": "1", "bal_dpitch": "s",
                                   "bal_hip": "1"}
# How fast the targets may move outside the swing: "slew" is in deg/s in the files (read as
# "deg", so rad/s inside); 0 lets every keyframe jump. "base_slew" (deg/s too) is the move
# from the stand into the base pose (k0); 0 jumps there.
SLEW_SCHEMA: dict[str, str] = {"slew": "deg", "base_slew": "deg"}
# The stand rocks on its feet at about 6.5 Hz (torso pitch rate up to 0.4 rad/s, every
# type, even under a joint PID run every 5 ms). A keyframe kick that starts while the
# torso's pitch rate is below zero falls far more often: long kick, type 0, 160 starts
# at random times after standing, 35 of 72 started below zero fell, 6 of 88 otherwise.
# So a kick holds the stand (at most `START_WAIT`) until the gyro's pitch rate reaches
# `START_PITCH_RATE`.
START_PITCH_RATE = 0.1  # rad/s, gyro y (0.0-0.2 do about as well)
START_WAIT = 0.3  # s
FAST_KEYFRAMES = (4, 5, 6)  # indices of k3, k3b and k4 (pull back, swing) in KICK_LEFT: their targets jump


def default_param_files(robot_type: int | None = None) -> list[str]:
    """The shipped parameter files for `robot_type`, in load order."""
    return with_type_file(skill_path(KICK_PARAMS), robot_type)


def kick_schema(source: SkillSource | None = None) -> dict[str, str]:
    """Every name a kick parameter set may hold, with its unit."""
    source = source or read_skills(skill_path(KICK_FILE))
    return {**source.schema, **SPEC_SCHEMA, **BALANCE_SCHEMA, **SLEW_SCHEMA}


def load_kick_sets(paths: Iterable[PathLike],
                   source: SkillSource | None = None) -> dict[str, dict[str, float]]:
    """The parameter sets of the files (later files override earlier), SI values by set name.

    A name ``<set>_<param>`` belongs to set ``<set>`` when ``<param>`` is in the
    schema (the longest such ``<param>`` wins). Unknown names raise `ParamError`
    with file:line; a set missing a parameter (after inheriting ``kick_``) raises
    ValueError.
    """
    schema = kick_schema(source)
    entries = read_entries(list(paths))
    prefixes = {BASE_SET + "_"}
    for e in entries.values():
        names = [s for s in schema if e.name.endswith("_" + s) and len(e.name) > len(s) + 1]
        if not names:
            raise ParamError(e.path, e.line, "unknown kick parameter", e.name)
        prefixes.add(e.name[:-len(max(names, key=len))])
    raw = convert(entries, schema, prefixes)
    base = raw[BASE_SET + "_"]
    out = {}
    for prefix, values in raw.items():
        merged = {**base, **values}
        try:
            require(merged, schema)
        except ValueError as err:
            raise ValueError(f"kick set {prefix[:-1]!r}: {err}") from None
        out[prefix[:-1]] = merged
    return out


def kick_spec(set_name: str, values: Mapping[str, float], foot: str, duration: float) -> KickSpec:
    """The `KickSpec` of a parameter set (SI values, left-foot offsets) for `foot` ("l" or "r")."""
    sign = 1.0 if foot == "l" else -1.0
    return KickSpec(
        name=f"{set_name}_{FOOT_NAME[foot]}", foot=foot,
        ball=(values["ball_x"], sign * values["ball_y"]),
        tolerance=(values["tol_x"], values["tol_y"], values["tol_angle"]),
        direction=sign * values["direction"], distance=values["distance"], duration=duration)


@dataclass(frozen=True)
class Balance:
    """Feedback on the support foot's ankle while the kick plays.

    The ankle roll target gains ``roll * (roll - roll0) + droll * gyro_x``, the hip
    roll target ``hip`` times that, and the ankle pitch target
    ``pitch * (pitch - pitch0) + dpitch * gyro_y`` (rad), where
    roll and pitch are the torso's tilt estimate (rad, from the percept's IMU),
    roll0 = pitch0 = 0 (the stand pose's torso is level) and gyro the percept's (rad/s,
    torso frame). The same signs serve both feet: mirroring negates the roll
    joints and the roll readings alike.
    """

    roll: float = 0.0  # rad/rad
    droll: float = 0.0  # rad per rad/s (s)
    pitch: float = 0.0  # rad/rad
    dpitch: float = 0.0  # rad per rad/s (s)
    hip: float = 0.0  # share of the ankle roll correction also put on the hip roll (1)

    @classmethod
    def from_values(cls, values: Mapping[str, float]) -> Balance:
        return cls(values.get("bal_roll", 0.0), values.get("bal_droll", 0.0),
                   values.get("bal_pitch", 0.0), values.get("bal_dpitch", 0.0), values.get("bal_hip", 0.0))


class KeyframeKick:
    """A keyframe kick: the KICK_LEFT/KICK_RIGHT skill bound to one parameter set.

    `step` plays the keyframes on the percept's clock from the joint angles the
    robot has when it starts (the walk's stand pose) and ends in the stand pose.
    Outside the pull-back and swing (k3, k3b, k4) the targets move toward the keyframe's at most `slew`
    rad/s, so the weight shift and the lift are gentle and only the swing is fast; the move from
    the stand into the base pose slews at `base_slew` rad/s (from the `start` targets given to
    `reset`), or, at 0, jumps.
    Between the first and the last keyframe the support ankle follows `balance`
    (feedback on the torso's tilt from the percept's gyro and accelerometer).
    """

    def __init__(self, skill: Skill, spec: KickSpec, robot_type: int,
                 balance: Balance | None = None, slew: float = 0.0, base_slew: float = 0.0) -> None:
        self.spec = spec
        self.slew = slew
        self.base_slew = base_slew
        self.skill = skill
        self.robot_type = robot_type
        self.balance = balance or Balance()
        self.player = SkillPlayer(skill, robot_type)
        names = self.player.names
        side = "r" if spec.foot == "l" else "l"
        self._ankle_roll = names.index(f"{side}lj6")
        self._ankle_pitch = names.index(f"{side}lj5")
        self._hip_roll = names.index(f"{side}lj2")
        self.tilt = TiltEstimator(from_first=True)  # as the kick was tuned
        self._ref: tuple[float, float] | None = None
        self._target: np.ndarray | None = None
        self._asked: float | None = None  # s: when the first step came (the kick waits for its phase)
        self._started = False
        self.start: np.ndarray | None = None

    @classmethod
    def load(cls, set_name: str = BASE_SET, foot: str = "l", robot_type: int = 0,
             param_paths: Iterable[PathLike] = ()) -> KeyframeKick:
        """The kick of parameter set `set_name` with `foot` ("l" or "r"), from the shipped
        files followed by `param_paths`."""
        kicks = keyframe_kicks(robot_type, param_paths)
        name = f"{set_name}_{FOOT_NAME[foot]}"
        if name not in kicks:
            sets = sorted({k.rsplit("_", 1)[0] for k in kicks})
            raise KeyError(f"no keyframe kick set {set_name!r}; sets: {sets}")
        return kicks[name]

    def reset(self, ball: tuple[float, float] | None = None, start: np.ndarray | None = None) -> None:
        """Start over at the next `step` (the ball estimate is not used: the kick is fixed).

        start: the joint targets (rad, league order; NaN = none) the robot holds as the
        kick begins, usually the walk's stand (`Motion.held_target`). With a `base_slew`, the
        move into the base pose (k0) slews from them along a straight line in joint space;
        without (or without them) the base pose's targets apply at once, and the jump (the
        knees straighten by about 33 deg) makes the robot hop: its feet land up to 20-40 mm
        from where they stood."""
        self.start = None if start is None else np.array(start, dtype=float)
        self.player.reset()
        self.tilt = TiltEstimator(from_first=True)  # as the kick was tuned
        self._ref = None
        self._target = None
        self._asked = None
        self._started = False

    def step(self, percept: Percept) -> np.ndarray:
        """Joint targets (rad, league order) for this cycle."""
        if not self._started:  # wait for the stand's rocking to pitch the right way
            if self._asked is None:
                self._asked = percept.time
            if percept.gyro[1] < START_PITCH_RATE and percept.time - self._asked < START_WAIT - 1e-9:
                return np.full(len(percept.joints), np.nan)  # hold the stand
            self._started = True  # from here on as if it had started now
        self.tilt.update(percept.gyro, percept.accel, CYCLE)
        if self._ref is None:  # upright: the stand pose's torso is level (the first reading may not be)
            self._ref = (0.0, 0.0)
        raw = self.player.step(percept.time, percept.joints)
        k = self.player.keyframe
        if self._target is None and self.base_slew > 0.0 and self.start is not None:
            self._target = np.where(np.isnan(self.start), raw, self.start)
        if self._target is None or k in FAST_KEYFRAMES or (self.base_slew if k == 0 else self.slew) <= 0.0:
            self._target = raw.copy()
        elif k == 0:  # from the stand: all joints in proportion (a straight line), so the torso
            # stays upright and the soles flat; clipped joint by joint, the hip and ankle would
            # arrive before the knee and tip the torso back (type 3 fell every time)
            d = raw - self._target
            big = float(np.max(np.abs(d)))
            self._target += d * (min(1.0, self.base_slew * CYCLE / big) if big > 0 else 0.0)
        else:  # outside the swing the targets move at most `slew` rad/s
            step = self.slew * CYCLE
            self._target += np.clip(raw - self._target, -step, step)
        target = self._target.copy()
        b = self.balance
        if 0 < self.player.keyframe < len(self.skill.keyframes) - 1:
            gx, gy = percept.gyro[0], percept.gyro[1]
            roll = b.roll * (self.tilt.roll - self._ref[0]) + b.droll * gx
            target[self._ankle_roll] += roll
            target[self._hip_roll] += b.hip * roll
            target[self._ankle_pitch] += b.pitch * (self.tilt.pitch - self._ref[1]) + b.dpitch * gy
        return target

    @property
    def done(self) -> bool:
        return self.player.done


def make_keyframe_kick(source: SkillSource, set_name: str, values: Mapping[str, float], foot: str,
                       robot_type: int) -> KeyframeKick:
    """The kick of one parameter set: `values` are the set's SI values (skill parameters, spec,
    balance and slew), `foot` "l" or "r". Use this rather than the constructor, so the kick
    gets the set's balance feedback and slew too."""
    skill = source.bind(values)[SKILL_FOR_FOOT[foot]]
    return KeyframeKick(skill, kick_spec(set_name, values, foot, skill.duration), robot_type,
                        Balance.from_values(values), values.get("slew", 0.0), values.get("base_slew", 0.0))


def keyframe_kicks(robot_type: int = 0, param_paths: Iterable[PathLike] = ()) -> dict[str, KeyframeKick]:
    """Every keyframe kick for `robot_type`, both feet, by spec name ("kick_left", "long_kick_right",
    "kick_5m_left", ...): the shipped parameter files, then `param_paths`."""
    source = read_skills(skill_path(KICK_FILE))
    sets = load_kick_sets(default_param_files(robot_type) + list(param_paths), source)
    out: dict[str, KeyframeKick] = {}
    for set_name, values in sets.items():
        for foot in SKILL_FOR_FOOT:
            kick = make_keyframe_kick(source, set_name, values, foot, robot_type)
            out[kick.spec.name] = kick
    return out


def keyframe_kick_specs(robot_type: int = 0, param_paths: Iterable[PathLike] = ()) -> list[KickSpec]:
    """The specs of `keyframe_kicks`, sorted by nominal distance then name."""
    return sorted((k.spec for k in keyframe_kicks(robot_type, param_paths).values()),
                  key=lambda s: (s.distance, s.name))


def angle_error(a: float, b: float) -> float:
    """a - b wrapped to (-pi, pi] (rad)."""
    return math.remainder(a - b, 2.0 * math.pi)


__all__ = ["Balance", "KeyframeKick", "keyframe_kick_specs", "keyframe_kicks", "load_kick_sets",
           "make_keyframe_kick"]

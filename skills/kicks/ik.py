"""Inverse-kinematics kicks (dissertation 8.2.7): the kicking foot follows waypoints
placed relative to the ball through a cubic Hermite spline on normalized time.

A kick plays these phases, cycle by cycle, from the robot's percepts:

1. shift: both feet stay planted while the torso moves over the support foot
   (IK of both legs; a cosine ease over `shift_time`);
2. swing: the kicking sole follows a C1 cubic Hermite spline (Catmull-Rom
   tangents on non-uniform knots, zero velocity at both ends) through its stand
   spot, the waypoints given relative to the ball, and a point `end_z` above its
   stand spot, sampled on normalized time s = t / swing_time in [0, 1]; the foot's
   roll, pitch and yaw are interpolated linearly between the waypoints;
3. land: the foot comes down onto its stand spot (`land_time`);
4. unshift: the torso moves back between the feet (`unshift_time`);
5. settle: the stand pose is held (`settle_time`), then the kick is done.

Frames: the *ground frame* is the robot frame at the start of the kick (the
torso's position projected on the ground, x forward, y left, z up from the
ground; m, rad). Feet are placed in it; the torso sits `height` above its origin
plus the shift, upright, so a ground point p is p - torso in the torso frame.
Waypoints are sole-center positions relative to the ball's center projected on
the ground (z is the sole's height above the ground) and foot roll/pitch/yaw
(R = Rz(yaw) Ry(pitch) Rx(roll)).

Parameters (`skills/data/ikkick.params`) are written for LEFT-foot kicks (y
positive outward); right-foot kicks mirror them (y, roll, yaw and direction
negated). Kick names: ``ik_<kind>_<left|right>`` with kind ``forward``,
``45_in``, ``45_out``, ``90_in``, ``90_out`` ("in" sends the ball across the
body, toward the support foot's side).

Unreachable waypoints: `reset` checks the whole swing with IK; `reachable` is
then False and `unreachable` lists the normalized times and sole targets the leg
cannot reach. The kick still plays (IK clamps to the nearest posture inside the
limits) unless the kick was made with ``strict=True``, which raises
`UnreachableKick` from `reset`. `IkKick.check(ball)` answers without resetting.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from models import nao
from models.messages import Percept
from models.rules import CYCLE
from skills.ik import LegIK
from skills.imu import TiltEstimator
from skills.kicks.spec import KickSpec
from skills.kinematics import LEG_JOINTS, RobotKinematics, leg_geometry
from skills.params import PathLike, load_param_sets, with_type_file
from skills.walk import WalkEngine

DATA = Path(__file__).parent.parent / "data"  # skills/data/
PARAMS_FILE = DATA / "ikkick.params"
MAX_WAYPOINTS = 8
KINDS: dict[str, str] = {  # kind -> parameter prefix
    "forward": "forward_", "45_in": "45_in_", "45_out": "45_out_", "90_in": "90_in_", "90_out": "90_out_",
}
CHECK_SAMPLES = 60  # samples of the swing checked for reachability at reset
CHECKS_KEPT = 1024  # reachability checks remembered (`IkKick._checked`)
_CHECKS: dict[tuple, tuple[Unreachable, ...]] = {}

# Units as the file writes them (converted to SI once at load).
SCHEMA: dict[str, str] = {
    "ball_x": "mm", "ball_y": "mm", "tol_x": "mm", "tol_y": "mm", "tol_theta": "deg",
    "direction": "deg", "distance": "mm",
    "shift_time": "s", "shift_x": "mm", "shift_y": "mm", "shift_z": "mm",
    "swing_time": "s", "end_z": "mm", "land_time": "s", "unshift_time": "s", "settle_time": "s",
    "balance_pitch": "1", "balance_roll": "1",
}
for _i in range(1, MAX_WAYPOINTS + 1):
    SCHEMA.update({f"wp{_i}_t": "1", f"wp{_i}_x": "mm", f"wp{_i}_y": "mm", f"wp{_i}_z": "mm",
                   f"wp{_i}_roll": "deg", f"wp{_i}_pitch": "deg", f"wp{_i}_yaw": "deg"})


class UnreachableKick(ValueError):
    """A kick whose swing the kicking leg cannot reach (with `strict=True`)."""


@dataclass(frozen=True)
class Waypoint:
    """One control point: normalized time, sole position relative to the ball (m,
    ground axes; z above the ground) and foot roll/pitch/yaw (rad)."""

    t: float
    pos: tuple[float, float, float]
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class IkKickParams:
    """One kick's parameters for the LEFT foot, SI units (m, rad, s)."""

    ball: tuple[float, float]
    tolerance: tuple[float, float, float]
    direction: float
    distance: float
    waypoints: tuple[Waypoint, ...]
    shift_time: float = 0.6
    shift: tuple[float, float, float] = (0.0, -0.05, 0.0)  # torso offset (m); y toward the support foot
    swing_time: float = 0.8
    end_z: float = 0.02
    land_time: float = 0.3
    unshift_time: float = 0.6
    settle_time: float = 0.3
    balance_pitch: float = 0.0
    balance_roll: float = 0.0

    def mirrored(self) -> IkKickParams:
        """The same kick for the other foot (y, roll, yaw, direction negated)."""
        def m(w: Waypoint) -> Waypoint:
            return Waypoint(w.t, (w.pos[0], -w.pos[1], w.pos[2]), (-w.rpy[0], w.rpy[1], -w.rpy[2]))

        return IkKickParams(
            (self.ball[0], -self.ball[1]), self.tolerance, -self.direction, self.distance,
            tuple(m(w) for w in self.waypoints), self.shift_time,
            (self.shift[0], -self.shift[1], self.shift[2]), self.swing_time, self.end_z,
            self.land_time, self.unshift_time, self.settle_time, self.balance_pitch, self.balance_roll)

    @property
    def duration(self) -> float:
        return self.shift_time + self.swing_time + self.land_time + self.unshift_time + self.settle_time


# ------------------------------------------------------------------ the spline

def hermite_tangents(t: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Catmull-Rom tangents (dp/dt) at knots `t` (n,) of points `p` (n, d); zero at both ends."""
    m = np.zeros_like(p)
    if len(t) > 2:
        m[1:-1] = (p[2:] - p[:-2]) / (t[2:] - t[:-2])[:, None]
    return m


def hermite(t: np.ndarray, p: np.ndarray, m: np.ndarray, s: float) -> np.ndarray:
    """The cubic Hermite spline through points `p` with tangents `m` at knots `t`, at `s`
    (clamped to [t0, tn])."""
    s = min(max(s, float(t[0])), float(t[-1]))
    k = int(np.clip(np.searchsorted(t, s, side="right") - 1, 0, len(t) - 2))
    h = float(t[k + 1] - t[k])
    u = (s - float(t[k])) / h
    u2, u3 = u * u, u * u * u
    h00, h10, h01, h11 = 2 * u3 - 3 * u2 + 1, u3 - 2 * u2 + u, -2 * u3 + 3 * u2, u3 - u2
    return h00 * p[k] + h10 * h * m[k] + h01 * p[k + 1] + h11 * h * m[k + 1]


def stand_stance(robot_type: int, kin: RobotKinematics, stand: np.ndarray
                 ) -> tuple[dict[str, np.ndarray], float, dict[str, np.ndarray]]:
    """Per side, the leg's joint indices (league order); the torso's height above the
    ground (m) and the sole spots (x, y; torso frame, m) in the stand pose `stand`
    (rad, league order; NaN read as 0)."""
    names = nao.joint_names(robot_type)
    legs = {s: np.array([names.index(s + j) for j in LEG_JOINTS]) for s in "lr"}
    soles = kin.foot_poses(np.where(np.isnan(stand), 0.0, stand))
    height = -0.5 * float(soles[0][2, 3] + soles[1][2, 3])
    return legs, height, {s: T[:2, 3].copy() for s, T in zip("lr", soles)}


def ease(u: float) -> float:
    """Cosine ease from 0 to 1 over u in [0, 1] (zero speed at both ends)."""
    u = min(max(u, 0.0), 1.0)
    return 0.5 * (1.0 - math.cos(math.pi * u))


@dataclass(frozen=True)
class Unreachable:
    """A sample of the swing the leg cannot reach: normalized time and sole target (m,
    ground frame); s = -1 marks the support foot's spot with the torso shifted."""

    s: float
    target: tuple[float, float, float]


# ------------------------------------------------------------------ the kick

@dataclass(eq=False)
class IkKick:
    """One IK kick of one robot type; see the module docstring for phases and frames."""

    robot_type: int
    spec: KickSpec
    params: IkKickParams  # already for `spec.foot` (mirrored for the right foot)
    strict: bool = False
    ik: LegIK | None = None
    kin: RobotKinematics | None = None
    stand: np.ndarray | None = None  # stand joint targets (rad, league order; NaN = hold)
    unreachable: list[Unreachable] = field(default_factory=list)

    def __post_init__(self) -> None:
        if self.ik is None:
            self.ik = LegIK(self.robot_type)
        if self.kin is None:
            self.kin = RobotKinematics(self.robot_type)
        if self.stand is None:
            self.stand = WalkEngine(self.robot_type).update(0.0, 0.0, 0.0).targets
        self.legs, self.height, spots = stand_stance(self.robot_type, self.kin, self.stand)
        # Stand sole spots in the ground frame (z = 0).
        self.spot = {s: np.append(xy, 0.0) for s, xy in spots.items()}
        self.kick_side = self.spec.foot
        self.support = "r" if self.kick_side == "l" else "l"
        self.reset()

    # --------------------------------------------------------------- set-up

    def reset(self, ball: tuple[float, float] | None = None, start: np.ndarray | None = None) -> None:
        """Start over at the next `step`, with the ball at `ball` (m, robot frame) or the
        spec's nominal position; checks the swing's reachability (see `unreachable`).
        `start` (the held targets, `KickSkill.reset`) is not used."""
        self.ball = np.array(self.spec.ball if ball is None else ball, dtype=float)
        self._t0: float | None = None
        self._t = 0.0
        self._done = False
        self.tilt = TiltEstimator(from_first=True)  # as the kick was tuned
        self._build(self.ball)
        self.unreachable = self._checked()
        if self.unreachable and self.strict:
            u = self.unreachable[0]
            raise UnreachableKick(
                f"{self.spec.name}: ball at ({self.ball[0]:.3f}, {self.ball[1]:.3f}) m: the "
                f"{'left' if self.kick_side == 'l' else 'right'} sole cannot reach "
                f"({u.target[0]:.3f}, {u.target[1]:.3f}, {u.target[2]:.3f}) m at s={u.s:.2f} "
                f"({len(self.unreachable)} of {CHECK_SAMPLES + 1} samples)")

    def _build(self, ball: np.ndarray) -> None:
        p = self.params
        spot = self.spot[self.kick_side]
        b = np.array([ball[0], ball[1], 0.0])
        ts = [0.0] + [w.t for w in p.waypoints] + [1.0]
        pts = [spot] + [b + np.array(w.pos) for w in p.waypoints] + [spot + np.array([0.0, 0.0, p.end_z])]
        rpys = [np.zeros(3)] + [np.array(w.rpy) for w in p.waypoints] + [np.zeros(3)]
        t = np.array(ts)
        if np.any(np.diff(t) <= 0.0):
            raise ValueError(f"{self.spec.name}: waypoint times must increase strictly inside (0, 1): {ts}")
        self.knots = t
        self.points = np.array(pts)
        self.tangents = hermite_tangents(t, self.points)
        self.rpys = np.array(rpys)

    def foot_at(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """Kicking sole position (m, ground frame) and rpy (rad) at normalized swing time `s`."""
        pos = hermite(self.knots, self.points, self.tangents, s)
        s = min(max(s, 0.0), 1.0)
        rpy = np.array([np.interp(s, self.knots, self.rpys[:, i]) for i in range(3)])
        return pos, rpy

    def _torso(self, shift: float) -> np.ndarray:
        """Torso position (m, ground frame) at shift fraction `shift` in [0, 1]."""
        return np.array([0.0, 0.0, self.height]) + shift * np.array(self.params.shift)

    def _checked(self) -> list[Unreachable]:
        """`check` at the current ball, remembered for the same kick, stance and ball (every
        player of a type builds the same kicks at the spec's ball)."""
        if self.ik.geom is not leg_geometry(self.robot_type):  # a geometry of the caller's own
            return self.check(self.ball)
        key = (self.robot_type, self.kick_side, self.params, tuple(self.ball.tolist()), self.height,
               tuple(self.spot["l"].tolist()), tuple(self.spot["r"].tolist()))
        bad = _CHECKS.get(key)
        if bad is None:
            bad = tuple(self.check(self.ball))
            if len(_CHECKS) < CHECKS_KEPT:
                _CHECKS[key] = bad
        return list(bad)

    def check(self, ball: tuple[float, float] | np.ndarray | None = None) -> list[Unreachable]:
        """Samples of the swing (with the ball at `ball`, robot frame) the kicking leg
        cannot reach with the torso shifted; empty when the whole kick is reachable."""
        saved = (self.knots, self.points, self.tangents, self.rpys)
        if ball is not None:
            self._build(np.asarray(ball, dtype=float))
        torso = self._torso(1.0)
        bad = []
        for s in np.linspace(0.0, 1.0, CHECK_SAMPLES + 1):
            pos, rpy = self.foot_at(float(s))
            _, ok = self.ik.solve(self.kick_side, pos - torso, rpy)
            if not ok:
                bad.append(Unreachable(float(s), (float(pos[0]), float(pos[1]), float(pos[2]))))
        _, ok = self.ik.solve(self.support, self.spot[self.support] - torso, np.zeros(3))
        if not ok:
            bad.append(Unreachable(-1.0, tuple(map(float, self.spot[self.support]))))
        self.knots, self.points, self.tangents, self.rpys = saved
        return bad

    @property
    def reachable(self) -> bool:
        """True when the last `reset`'s check found the whole kick reachable."""
        return not self.unreachable

    # --------------------------------------------------------------- playing

    def pose_at(self, t: float) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], np.ndarray, str]:
        """Sole poses (m, rad; ground frame) per side, the torso position (ground frame) and
        the phase name at time `t` (s) since the kick's start."""
        p = self.params
        feet = {s: (self.spot[s].copy(), np.zeros(3)) for s in "lr"}
        t1 = p.shift_time
        t2 = t1 + p.swing_time
        t3 = t2 + p.land_time
        t4 = t3 + p.unshift_time
        if t < t1:
            return feet, self._torso(ease(t / max(t1, 1e-9))), "shift"
        if t < t2:
            feet[self.kick_side] = self.foot_at((t - t1) / p.swing_time)
            return feet, self._torso(1.0), "swing"
        if t < t3:
            pos = self.spot[self.kick_side] + [0.0, 0.0, p.end_z * (1.0 - ease((t - t2) / p.land_time))]
            feet[self.kick_side] = (pos, np.zeros(3))
            return feet, self._torso(1.0), "land"
        if t < t4:
            return feet, self._torso(1.0 - ease((t - t3) / p.unshift_time)), "unshift"
        return feet, self._torso(0.0), "settle"

    def targets_at(self, t: float, pitch: float = 0.0, roll: float = 0.0) -> np.ndarray:
        """Joint targets (rad, league order; NaN = hold) at time `t` (s) since the start;
        `pitch`/`roll` are the torso's estimated tilt (rad) for the balance terms."""
        feet, torso, _ = self.pose_at(t)
        q = self.stand.copy()
        bal = np.array([self.params.balance_roll * roll, self.params.balance_pitch * pitch, 0.0])
        for side, (pos, rpy) in feet.items():
            q6, _ = self.ik.solve(side, pos - torso, rpy + (bal if side == self.support else 0.0))
            q[self.legs[side]] = q6
        return q

    def step(self, percept: Percept) -> np.ndarray:
        """Joint targets (rad, league order; NaN = hold) for this cycle."""
        if self._t0 is None:
            self._t0 = percept.time
        self.tilt.update(percept.gyro, percept.accel, CYCLE)
        self._t = percept.time - self._t0
        if self._t >= self.params.duration:
            self._done = True
        return self.targets_at(self._t, self.tilt.pitch, self.tilt.roll)

    @property
    def done(self) -> bool:
        """True once the kick is over and the robot stands again."""
        return self._done

    @property
    def phase(self) -> str:
        """The current phase's name."""
        return self.pose_at(self._t)[2]


# ------------------------------------------------------------------ loading

def _kick_params(values: Mapping[str, float], kind: str) -> IkKickParams:
    wps = []
    for i in range(1, MAX_WAYPOINTS + 1):
        keys = [f"wp{i}_{c}" for c in ("t", "x", "y", "z")]
        present = [k in values for k in keys]
        if not any(present):
            continue
        if not all(present):
            missing = ", ".join(KINDS[kind] + k for k, ok in zip(keys, present) if not ok)
            raise ValueError(f"IK kick {kind}: waypoint {i} lacks {missing}")
        wps.append(Waypoint(values[f"wp{i}_t"], (values[f"wp{i}_x"], values[f"wp{i}_y"], values[f"wp{i}_z"]),
                            tuple(values.get(f"wp{i}_{a}", 0.0) for a in ("roll", "pitch", "yaw"))))
    if not wps:
        raise ValueError(f"IK kick {kind}: no waypoints")
    need = ("ball_x", "ball_y", "tol_x", "tol_y", "tol_theta", "direction", "distance")
    missing = [KINDS[kind] + n for n in need if n not in values]
    if missing:
        raise ValueError(f"IK kick {kind}: parameters not set: {', '.join(missing)}")
    kw = {n: values[n] for n in ("shift_time", "swing_time", "end_z", "land_time", "unshift_time",
                                 "settle_time", "balance_pitch", "balance_roll") if n in values}
    if any(n in values for n in ("shift_x", "shift_y", "shift_z")):
        kw["shift"] = (values.get("shift_x", 0.0), values.get("shift_y", -0.05), values.get("shift_z", 0.0))
    return IkKickParams((values["ball_x"], values["ball_y"]), (values["tol_x"], values["tol_y"],
                        values["tol_theta"]), values["direction"], values["distance"], tuple(wps), **kw)


def load_ik_params(paths: Iterable[PathLike]) -> dict[str, IkKickParams]:
    """Left-foot parameters per kind from parameter files (later files override).

    Unprefixed names apply to every kick; ``forward_``, ``45_in_``, ... override
    them for one kick. Errors name the file and line (`skills.params.ParamError`).
    """
    raw = load_param_sets(list(paths), SCHEMA, ["", *KINDS.values()])
    return {kind: _kick_params({**raw[""], **raw[prefix]}, kind) for kind, prefix in KINDS.items()}


def default_param_files(robot_type: int) -> list[str]:
    """The shipped IK kick parameter files for a robot type, general first."""
    return with_type_file(PARAMS_FILE, robot_type)


def ik_kicks(robot_type: int, param_paths: Iterable[PathLike] = (),
             strict: bool = False) -> dict[str, IkKick]:
    """Every IK kick of a robot type by spec name (``ik_forward_left`` ...), from the
    shipped ``skills/data/ikkick.params``, the type's ``ikkick_type<T>.params`` if
    there is one, then `param_paths` (each overriding the ones before)."""
    base = load_ik_params([*default_param_files(robot_type), *param_paths])
    ik, kin = LegIK(robot_type), RobotKinematics(robot_type)
    stand = WalkEngine(robot_type).update(0.0, 0.0, 0.0).targets
    out: dict[str, IkKick] = {}
    for kind, p in base.items():
        for foot, side in (("l", "left"), ("r", "right")):
            q = p if foot == "l" else p.mirrored()
            spec = KickSpec(f"ik_{kind}_{side}", foot, q.ball, q.tolerance, q.direction, q.distance,
                            q.duration)
            out[spec.name] = IkKick(robot_type, spec, q, strict=strict, ik=ik, kin=kin, stand=stand)
    return out


__all__ = ["IkKick", "IkKickParams", "UnreachableKick", "Unreachable", "Waypoint", "ease", "hermite",
           "default_param_files", "hermite_tangents", "ik_kicks", "load_ik_params", "stand_stance"]

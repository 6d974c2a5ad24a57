"""Moving the stance a few centimetres and degrees precisely, one foot at a time.

The walk stops wherever its last step put the feet: a few centimetres and about
5 deg from where the approach wanted them, at random, however slowly it creeps.
`Align` moves a standing robot by a small (dx, dy, dturn) with two single steps
played slowly enough to stay statically balanced, the way the IK kicks stand on
one leg (`skills.kicks.ik`). For each foot in turn:

1. shift: the torso moves over the other (support) foot, to where an IK kick
   puts it (`shift` m beyond the stand spot's middle, facing as the support foot);
2. swing: the free sole lifts `lift`, moves to its new spot and turn with a
   cosine ease, and comes down (zero speed at both ends);
3. land: both feet down, the torso stays over the support foot `land_time`;
4. unshift: the torso moves back between the feet: halfway to the goal after
   the first step, onto it after the second.

Turning, the foot that turns inward moves first (a Nao's hip turns a sole only
inward); otherwise the one whose move widens the stance, so the feet never cross.
Both feet end on the stand spots of the moved pose, so the walk's stand (and any
kick) takes over where `Align` ends.

Frames: the *ground frame* is the robot frame at the start (the torso projected
on the ground, x forward, y left, z up from the ground; m, rad). The torso is
held upright at the stand height, as in the IK kicks; a sole's pose is its
centre and yaw in the ground frame. The move assumes the robot starts in the
walk's stand pose (feet on their stand spots).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from models.messages import Percept
from skills.ik import LegIK
from skills.kicks.ik import ease, stand_stance
from skills.kinematics import RobotKinematics
from skills.params import PathLike, load_params
from skills.walk import WalkEngine

DATA = Path(__file__).parent / "data"
TURN_FIRST = math.radians(2.0)  # rad: turns larger than this set which foot moves first

# Names in parameter files (prefix "align_") and their file units.
ALIGN_SCHEMA = {"shift_time": "s", "swing_time": "s", "land_time": "s", "unshift_time": "s",
                "settle_time": "s", "lift": "mm", "shift": "mm", "max_move": "mm", "max_turn": "deg"}


@dataclass(frozen=True)
class AlignParams:
    """Timing and geometry of the two steps (SI: s, m, rad)."""

    shift_time: float = 0.56  # s: torso over the support foot
    swing_time: float = 0.8  # s: the free foot to its new spot
    land_time: float = 0.16  # s: both feet down before the torso moves back
    unshift_time: float = 0.4  # s: torso back between the feet
    settle_time: float = 0.16  # s: the stand held at the end
    lift: float = 0.011  # m: sole height at the middle of a swing
    shift: float = 0.05  # m: torso beyond the middle of the stand spots, toward the support foot
    max_move: float = 0.06  # m: largest move along x or y `Align` takes on
    max_turn: float = math.radians(20.0)  # rad: largest turn `Align` takes on

    @classmethod
    def load(cls, paths: tuple[PathLike, ...] = ()) -> AlignParams:
        """Shipped values (skills/data/align.params), then `paths` (later override)."""
        return replace(cls(), **load_params([DATA / "align.params", *paths], ALIGN_SCHEMA, "align_"))

    def fits(self, move: tuple[float, float, float]) -> bool:
        """Whether `move` (dx m, dy m, dturn rad; ground frame) is small enough to take on."""
        return max(abs(move[0]), abs(move[1])) <= self.max_move and abs(move[2]) <= self.max_turn

    @property
    def step_time(self) -> float:
        return self.shift_time + self.swing_time + self.land_time + self.unshift_time

    @property
    def duration(self) -> float:
        return 2.0 * self.step_time + self.settle_time


def _rot(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s], [s, c]])


class Align:
    """Two slow single steps that move the stance by a small (dx, dy, dturn)."""

    def __init__(self, robot_type: int, params: AlignParams | None = None, ik: LegIK | None = None,
                 kin: RobotKinematics | None = None, stand: np.ndarray | None = None) -> None:
        self.params = params or AlignParams.load()
        self.ik = ik or LegIK(robot_type)
        kin = kin or RobotKinematics(robot_type)
        self.stand = WalkEngine(robot_type).update(0.0, 0.0, 0.0).targets if stand is None else stand
        # leg joint indices, torso height above the ground (m), stand sole spots (torso frame)
        self.legs, self.height, self.spot = stand_stance(robot_type, kin, self.stand)
        # The torso relative to the support sole in single support: `shift` toward it
        # from the stand, as the IK kicks stand.
        self.over = {s: np.array([0.0, math.copysign(self.params.shift, self.spot[s][1])]) - self.spot[s]
                     for s in "lr"}
        self.reset((0.0, 0.0, 0.0))

    def fits(self, move: tuple[float, float, float]) -> bool:
        """Whether `move` (dx m, dy m, dturn rad; ground frame) is small enough to take on."""
        return self.params.fits(move)

    def reset(self, move: tuple[float, float, float]) -> None:
        """Plan the move of the torso by `move` (dx, dy in m, dturn in rad; ground frame)."""
        dx, dy, dth = (float(v) for v in move)
        self.move = (dx, dy, dth)
        goal_xy = np.array([dx, dy])
        self.start = {s: (self.spot[s].copy(), 0.0) for s in "lr"}
        self.goal = {s: (goal_xy + _rot(dth) @ self.spot[s], dth) for s in "lr"}
        # A Nao's sole turns only inward from its hip (left toes rightward, right toes
        # leftward), so turning, the foot on the side turned away from turns first;
        # otherwise the foot that moves outward leads (the stance widens first).
        if abs(dth) > TURN_FIRST:
            first = "r" if dth > 0.0 else "l"
        else:
            out = {s: (self.goal[s][0][1] - self.spot[s][1]) * (1.0 if s == "l" else -1.0) for s in "lr"}
            first = "l" if out["l"] >= out["r"] else "r"
        self.order = (first, "r" if first == "l" else "l")
        self.halfway = (0.5 * goal_xy, 0.5 * dth)
        self.t0: float | None = None
        self.t = 0.0
        self.done = False

    def pose_at(self, t: float) -> tuple[dict[str, tuple[np.ndarray, float, float]], np.ndarray, float]:
        """Sole (xy, z, yaw) per side and the torso's (xy, yaw) at `t` s (ground frame)."""
        p = self.params
        feet = {s: (xy.copy(), 0.0, yaw) for s, (xy, yaw) in self.start.items()}
        torso_xy, torso_yaw = np.zeros(2), 0.0
        ends = [(np.zeros(2), 0.0), self.halfway, (np.array(self.move[:2]), self.move[2])]
        for k, side in enumerate(self.order):
            support = self.order[1 - k]
            sxy, _, syaw = feet[support]
            over = sxy + _rot(syaw) @ self.over[support]  # torso over the support sole
            base_xy, base_yaw = ends[k]
            end_xy, end_yaw = ends[k + 1]
            u = t - k * p.step_time
            if u < 0.0:
                break
            torso_xy, torso_yaw = base_xy, base_yaw
            if u < p.shift_time:
                e = ease(u / p.shift_time)
                return feet, base_xy + e * (over - base_xy), base_yaw + e * (syaw - base_yaw)
            u -= p.shift_time
            if u < p.swing_time:
                e = ease(u / p.swing_time)
                (axy, ayaw), (bxy, byaw) = self.start[side], self.goal[side]
                lift = p.lift * 0.5 * (1.0 - math.cos(2.0 * math.pi * u / p.swing_time))
                feet[side] = (axy + e * (bxy - axy), lift, ayaw + e * (byaw - ayaw))
                return feet, over, syaw
            feet[side] = (self.goal[side][0].copy(), 0.0, self.goal[side][1])
            u -= p.swing_time
            if u < p.land_time:  # both feet down, the torso still over the support foot
                return feet, over, syaw
            u -= p.land_time
            if u < p.unshift_time:
                e = ease(u / p.unshift_time)
                return feet, over + e * (end_xy - over), syaw + e * (end_yaw - syaw)
            torso_xy, torso_yaw = end_xy, end_yaw
        return feet, torso_xy, torso_yaw

    def targets_at(self, t: float) -> np.ndarray:
        """Joint targets (rad, league order; NaN = hold) at `t` s since the start."""
        feet, torso_xy, torso_yaw = self.pose_at(t)
        q = self.stand.copy()
        back = _rot(-torso_yaw)
        for side, (xy, z, yaw) in feet.items():
            rel = back @ (xy - torso_xy)
            q6, _ = self.ik.solve(side, np.array([rel[0], rel[1], z - self.height]),
                                  np.array([0.0, 0.0, yaw - torso_yaw]))
            q[self.legs[side]] = q6
        return q

    def torso(self) -> tuple[float, float, float]:
        """The torso's planned pose now (x, y, yaw; ground frame)."""
        _, xy, yaw = self.pose_at(self.t)
        return float(xy[0]), float(xy[1]), float(yaw)

    def step(self, percept: Percept) -> np.ndarray:
        """Joint targets (rad, league order; NaN = hold) for this cycle."""
        if self.t0 is None:
            self.t0 = percept.time
        self.t = percept.time - self.t0
        if self.t >= self.params.duration:
            self.done = True
        return self.targets_at(self.t)


__all__ = ["ALIGN_SCHEMA", "Align", "AlignParams"]

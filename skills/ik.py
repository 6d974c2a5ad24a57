"""Closed-form inverse kinematics of the Nao legs (and a pointing IK for the arms).

Targets are in the TORSO frame (m, rad). A leg target is the pose of the SOLE
center (the `lfoot_sole`/`rfoot_sole` site, the same frame
`RobotKinematics.foot_poses` returns), or of the ankle joint center with
`target="ankle"` (the foot frame's orientation either way). `rpy` is (roll
about x, pitch about y, yaw about z) of the foot: R = Rz(yaw) Ry(pitch) Rx(roll).

The leg is hip yaw-pitch (lj1, about a 45-degree axis in the y-z plane), hip
roll (lj2, +x), hip pitch (lj3, -y), knee (lj4, -y), ankle pitch (lj5, -y) and
ankle roll (lj6, +x); the three hip axes meet at the hip, the two ankle axes at
the ankle. The hip-knee and knee-ankle vectors need not be vertical (this
model's knee sits 5 mm forward); they are used exactly. The solution:

1. the hip-ankle distance gives the knee (bent negative, the only branch
   inside the joint limits);
2. the hip seen from the ankle in the foot frame gives ankle roll and pitch
   (of the two roll branches, the one inside the roll limits);
3. what is left, R1(lj1) Rx(lj2) Ry(-lj3), is a Y-X-Y Euler decomposition once
   turned by the yaw-pitch axis' tilt: Rot(a, t) = Rx(tilt) Ry(t) Rx(-tilt)
   (of the two hip roll branches, the one inside the roll limits).

Inside the limits the solution is unique. Out of reach, the hip-ankle distance
is clamped to [reach_min, reach_max] (keeping its direction in the foot frame
and the foot's orientation), then every angle is clipped to its limits; the
result is a nearby posture within the limits and `reachable` is False. A
target is reachable when neither clamp moved anything by more than LIMIT_TOL.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from models.geometry import wrap
from skills import _kernels as kernels
from skills.kinematics import ArmGeometry, LegGeometry, LegsGeometry, leg_geometry

LIMIT_TOL = 1e-9  # rad; clamping by more than this marks the target unreachable


def _excess(a: float, lo: float, up: float) -> float:
    """How far angle `a` lies outside [lo, up] (0 inside)."""
    return max(lo - a, a - up, 0.0)


def solve_leg(g: LegGeometry, foot_pos, foot_rpy, target: str = "sole") -> tuple[np.ndarray, bool]:
    """Joint angles lj1..lj6 (rad) putting leg `g`'s sole (or ankle) at a torso-frame pose.

    Returns (q6, reachable). q6 is always within the joint limits. Compiled
    (`skills._kernels.solve_leg`), bit for bit the Python reference in
    tests/skills/ik_reference.py, in about a fifth of its time.
    """
    r, p, y = foot_rpy.tolist() if isinstance(foot_rpy, np.ndarray) else map(float, foot_rpy)
    px, py, pz = foot_pos.tolist() if isinstance(foot_pos, np.ndarray) else map(float, foot_pos)
    if target != "sole" and target != "ankle":
        raise ValueError(f"target must be 'sole' or 'ankle', not {target!r}")
    q = np.empty(6)
    reachable = kernels.solve_leg(g.kconsts, r, p, y, px, py, pz, target == "sole", q)
    return q, bool(reachable)


def leg_ik(geom: LegsGeometry, side: str, foot_pos, foot_rpy,
           target: str = "sole") -> tuple[np.ndarray, bool]:
    """Closed-form IK of one leg: (lj1..lj6 in rad, reachable) for a torso-frame foot pose.

    side is "l"/"left" or "r"/"right"; foot_pos (m) and foot_rpy (rad) give the
    sole center (target="sole") or ankle center (target="ankle") and the foot's
    orientation in the torso frame.
    """
    return solve_leg(geom.leg(side), foot_pos, foot_rpy, target)


def arm_point_ik(g: ArmGeometry, point) -> tuple[np.ndarray, bool]:
    """Shoulder pitch and roll (aj1, aj2 in rad) aiming the straight arm at a torso-frame point (m).

    The elbow joints are assumed at zero. Returns (q2, reachable); reachable is
    False when the point is closer than the arm tip can aim at or the limits clamp.
    """
    tx, ty, tz = (float(point[i]) - g.shoulder[i] for i in range(3))
    n = math.sqrt(tx * tx + ty * ty + tz * tz)
    hx, hz = g.hand[0], g.hand[2]
    la = math.hypot(hx, hz)
    reachable = n > 1e-9
    if not reachable:
        tx, ty, tz, n = 1.0, 0.0, 0.0, 1.0
    tx, ty, tz = tx / n, ty / n, tz / n
    ax, bz = hx / la, hz / la  # unit hand direction at zero angles: (ax, 0, bz)
    # Rz(q2) then Ry(-q1): the y component ax sin(q2) must equal ty.
    s2 = ty / ax
    if abs(s2) > 1.0:
        reachable = False
        s2 = math.copysign(1.0, s2)
    # Two roll branches, q2 and pi - q2 (the roll range passes 90 degrees); in the x-z
    # plane Ry(-q1) then raises the angle atan2(z, x) by q1. Take the first in limits.
    best, best_excess = None, math.inf
    for q2 in (math.asin(s2), wrap(math.copysign(math.pi, s2) - math.asin(s2))):
        q1 = wrap(math.atan2(tz, tx) - math.atan2(bz, ax * math.cos(q2)))
        excess = _excess(q1, g.lower[0], g.upper[0]) + _excess(q2, g.lower[1], g.upper[1])
        if excess < best_excess:
            best, best_excess = (q1, q2), excess
    q = np.array(best)
    qc = np.minimum(np.maximum(q, g.lower), g.upper)
    if np.any(np.abs(qc - q) > LIMIT_TOL):
        reachable = False
    return qc, reachable


@dataclass
class LegIK:
    """Per-type cache of the leg geometry with helpers for both legs (torso frame, m, rad)."""

    robot_type: int

    def __post_init__(self):
        self.geom: LegsGeometry = leg_geometry(self.robot_type)

    def solve(self, side: str, foot_pos, foot_rpy, target: str = "sole") -> tuple[np.ndarray, bool]:
        """One leg: (lj1..lj6, reachable)."""
        return solve_leg(self.geom.leg(side), foot_pos, foot_rpy, target)

    def solve_both(self, left_pos, left_rpy, right_pos, right_rpy,
                   target: str = "sole") -> tuple[np.ndarray, np.ndarray, bool]:
        """Both legs: (left lj1..lj6, right lj1..lj6, both reachable)."""
        ql, okl = solve_leg(self.geom.left, left_pos, left_rpy, target)
        qr, okr = solve_leg(self.geom.right, right_pos, right_rpy, target)
        return ql, qr, okl and okr

    def point_arm(self, side: str, point) -> tuple[np.ndarray, bool]:
        """Shoulder (aj1, aj2) aiming one straight arm at a torso-frame point."""
        return arm_point_ik(self.geom.arm(side), point)

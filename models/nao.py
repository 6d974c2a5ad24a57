"""The Nao-like robot of the RoboCup 3D league, for robot types 0-4.

Everything comes from one parameter table (`LINKS`, `TYPES`) with the numbers of
`shared/NAO.md`, read from SimSpark's `nao_hetero.rsg`, `naoleg.rsg`, `naoarm.rsg`
and `naoneckhead.rsg`. SimSpark writes vectors with x = right, y = forward,
z = up; the table keeps the league's numbers as they are and `to_project`
converts them, once, into the project's robot frame (x forward, y left, z up).

Joint angles keep the league's sign conventions (a positive hip pitch swings the
thigh forward, the knee bends negative), so UT Austin Villa style parameter and
skill files apply unchanged. Angles in the table are degrees (as the league
writes them) and are converted to radians when a `JointSpec` is made.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

# --------------------------------------------------------------------------- frames


def to_project(v: tuple[float, float, float]) -> tuple[float, float, float]:
    """SimSpark vector (x right, y forward, z up) -> project (x forward, y left, z up)."""
    sx, sy, sz = v
    return (sy, -sx, sz)


def size_to_project(s: tuple[float, float, float]) -> tuple[float, float, float]:
    """SimSpark box extents (along x, y, z) -> extents along the project's axes."""
    sx, sy, sz = s
    return (sy, sx, sz)


# ------------------------------------------------------------------- robot types

MAX_JOINT_SPEED = 6.1395  # rad/s (351.77 deg/s), every joint of every type ...
TYPE2_ANKLE_PITCH_SPEED = 8.80667  # rad/s, ... except type 2's ankles
TYPE2_ANKLE_ROLL_SPEED = 3.47234  # rad/s
MAX_MOTOR_TORQUE = 10.0  # N m, SimSpark's motor force limit
TOE_LENGTH = 0.035518  # m, type 4's toe


@dataclass(frozen=True)
class RobotType:
    """The per-type differences of NAO.md's heterogeneous table (meters, SimSpark axes)."""

    index: int
    hip1_x: float  # |x| of hip1 relative to the torso
    thigh_z: float  # thigh center relative to hip2, z
    ankle_z: float  # ankle relative to shank center, z
    elbow_y: float  # elbow relative to upper arm center, y
    toe: bool = False


TYPES: dict[int, RobotType] = {
    0: RobotType(0, 0.055, -0.04, -0.055, 0.07),
    1: RobotType(1, 0.055, -0.05832, -0.07332, 0.10664),
    2: RobotType(2, 0.055, -0.04, -0.055, 0.07),
    3: RobotType(3, 0.072954, -0.067868, -0.082868, 0.125737),
    4: RobotType(4, 0.055, -0.04, -0.055, 0.07, toe=True),
}


def robot_type(t: int) -> RobotType:
    """The type `t`, or a ValueError that names the valid types."""
    if t not in TYPES:
        raise ValueError(f"unknown robot type {t!r}; valid types are 0, 1, 2, 3, 4")
    return TYPES[t]


# ------------------------------------------------------------------ the link table


@dataclass(frozen=True)
class Link:
    """One rigid body of the robot, in SimSpark's axes (meters, kg, degrees).

    `pos` is the body's center relative to its parent's center; the joint that
    moves it (if any) sits at `anchor` relative to this body's center and turns
    about `axis` within `range_deg`.
    """

    name: str
    parent: str
    pos: tuple[float, float, float]
    mass: float
    shape: str  # "box", "sphere" or "capsule"
    size: tuple[float, ...]  # box extents, (radius,) or (radius, length)
    joint: str | None = None
    axis: tuple[float, float, float] = (1.0, 0.0, 0.0)
    range_deg: tuple[float, float] = (0.0, 0.0)
    anchor: tuple[float, float, float] = (0.0, 0.0, 0.0)
    collides: bool = True


def _side_links(rt: RobotType, side: str) -> list[Link]:
    """Arm and leg links of one side ('l' or 'r'); s is -1 left, +1 right (SimSpark x)."""
    s = -1.0 if side == "l" else 1.0
    left = side == "l"
    p = side
    links = [
        # Arm (naoarm.rsg). Zero angles point the arm forward.
        Link(f"{p}shoulder", "torso", (s * 0.098, 0.0, 0.075), 0.07, "sphere", (0.01,),
             f"{p}aj1", (1, 0, 0), (-120, 120), collides=False),
        Link(f"{p}upperarm", f"{p}shoulder", (s * 0.01, 0.02, 0.0), 0.15, "box",
             (0.07, 0.08, 0.06), f"{p}aj2", (0, 0, 1),
             (-1, 95) if left else (-95, 1), (-s * 0.01, -0.02, 0.0)),
        Link(f"{p}elbow", f"{p}upperarm", (-s * 0.01, rt.elbow_y, 0.009), 0.035, "sphere",
             (0.01,), f"{p}aj3", (0, 1, 0), (-120, 120), collides=False),
        Link(f"{p}lowerarm", f"{p}elbow", (0.0, 0.05, 0.0), 0.2, "box", (0.05, 0.11, 0.05),
             f"{p}aj4", (0, 0, 1), (-90, 1) if left else (-1, 90), (0.0, -0.05, 0.0)),
        # Leg (naoleg.rsg).
        Link(f"{p}hip1", "torso", (s * rt.hip1_x, -0.01, -0.115), 0.09, "sphere", (0.01,),
             f"{p}lj1", (-0.7071, 0, 0.7071) if left else (-0.7071, 0, -0.7071), (-90, 1),
             collides=False),
        Link(f"{p}hip2", f"{p}hip1", (0.0, 0.0, 0.0), 0.125, "sphere", (0.01,),
             f"{p}lj2", (0, 1, 0), (-25, 45) if left else (-45, 25), collides=False),
        Link(f"{p}thigh", f"{p}hip2", (0.0, 0.01, rt.thigh_z), 0.275, "box",
             (0.07, 0.07, 0.14), f"{p}lj3", (1, 0, 0), (-25, 100), (0.0, -0.01, -rt.thigh_z)),
        Link(f"{p}shank", f"{p}thigh", (0.0, 0.005, -0.125), 0.225, "box",
             (0.08, 0.07, 0.11), f"{p}lj4", (1, 0, 0), (-130, 1), (0.0, -0.01, 0.045)),
        Link(f"{p}ankle", f"{p}shank", (0.0, -0.01, rt.ankle_z), 0.125, "sphere", (0.01,),
             f"{p}lj5", (1, 0, 0), (-45, 75), collides=False),
    ]
    if not rt.toe:
        links.append(
            Link(f"{p}foot", f"{p}ankle", (0.0, 0.03, -0.04), 0.2, "box", (0.08, 0.16, 0.02),
                 f"{p}lj6", (0, 1, 0), (-45, 25) if left else (-25, 45), (0.0, -0.03, 0.04)))
    else:
        # Type 4: the front TOE_LENGTH of the foot is a toe on its own pitch joint.
        heel_len = 0.16 - TOE_LENGTH
        toe_mass = 0.2 * TOE_LENGTH / 0.16
        dy = -TOE_LENGTH / 2  # the shorter foot's center moves back; the heel stays put
        links += [
            Link(f"{p}foot", f"{p}ankle", (0.0, 0.03 + dy, -0.04), 0.2 - toe_mass, "box",
                 (0.08, heel_len, 0.02), f"{p}lj6", (0, 1, 0),
                 (-45, 25) if left else (-25, 45), (0.0, -0.03 - dy, 0.04)),
            Link(f"{p}toe", f"{p}foot", (0.0, heel_len / 2 + TOE_LENGTH / 2, 0.0), toe_mass,
                 "box", (0.08, TOE_LENGTH, 0.02), f"{p}lj7", (1, 0, 0), (-1, 70),
                 (0.0, -TOE_LENGTH / 2, 0.0)),
        ]
    return links


def links(t: int) -> list[Link]:
    """Every link of robot type `t`, parents before children."""
    rt = robot_type(t)
    head = [
        Link("torso", "", (0.0, 0.0, 0.0), 1.2171, "box", (0.1, 0.1, 0.18)),
        Link("neck", "torso", (0.0, 0.0, 0.09), 0.05, "capsule", (0.015, 0.08), "hj1",
             (0, 0, 1), (-120, 120), collides=False),
        Link("head", "neck", (0.0, 0.0, 0.065), 0.35, "sphere", (0.065,), "hj2", (1, 0, 0),
             (-45, 45), (0.0, 0.0, -0.005)),
    ]
    return head + _side_links(rt, "l") + _side_links(rt, "r")


# --------------------------------------------------------------------- joint table


@dataclass(frozen=True)
class JointSpec:
    """One hinge of the robot, in the project's robot frame and SI units."""

    name: str  # perceptor name, e.g. "llj4"
    effector: str  # effector name, e.g. "lle4"
    body: str  # the link it moves
    axis: tuple[float, float, float]  # in the parent link's frame (x fwd, y left, z up)
    lower: float  # rad
    upper: float  # rad
    max_speed: float  # rad/s


# Perceptor order of the league: head, left arm, right arm, left leg, right leg.
_ORDER = ["hj1", "hj2"] + [f"{s}aj{i}" for s in "lr" for i in range(1, 5)] + [
    f"{s}lj{i}" for s in "lr" for i in range(1, 7)
]


def joints(t: int) -> list[JointSpec]:
    """The hinge joints of robot type `t` in the league's order (22, or 24 for type 4)."""
    return list(_joints(t))


@functools.cache
def _joints(t: int) -> tuple[JointSpec, ...]:
    rt = robot_type(t)
    by_name = {ln.joint: ln for ln in links(t) if ln.joint}
    names = list(_ORDER) + (["llj7", "rlj7"] if rt.toe else [])
    specs = []
    for name in names:
        ln = by_name[name]
        speed = MAX_JOINT_SPEED
        if t == 2 and name[1:] == "lj5":
            speed = TYPE2_ANKLE_PITCH_SPEED
        elif t == 2 and name[1:] == "lj6":
            speed = TYPE2_ANKLE_ROLL_SPEED
        ax = np.asarray(to_project(ln.axis), dtype=float)
        ax = ax / np.linalg.norm(ax)
        specs.append(JointSpec(
            name=name,
            effector=name.replace("j", "e", 1),
            body=ln.name,
            axis=tuple(float(a) for a in ax),
            lower=math.radians(ln.range_deg[0]),
            upper=math.radians(ln.range_deg[1]),
            max_speed=speed,
        ))
    return tuple(specs)


def joint_names(t: int) -> list[str]:
    """Perceptor names of type `t`'s joints in the league's order."""
    return [j.name for j in joints(t)]


def total_mass(t: int) -> float:
    """Mass of robot type `t` in kg."""
    return sum(ln.mass for ln in links(t))


def standing_height(t: int) -> float:
    """Torso-center height (m) with every joint at zero and the soles on the ground."""
    rt = robot_type(t)
    return 0.115 - rt.thigh_z + 0.125 - rt.ankle_z + 0.04 + 0.01

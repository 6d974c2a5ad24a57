"""The soccer field, goals, ball and the landmarks agents see.

Field frame: meters, origin at the center spot, x toward the right team's goal
(the left team attacks +x), y to the left of a left-team player facing +x,
z up. Names of flags and posts follow SimSpark: F1L is the left team's corner
flag at +y, G2R the right team's goal post at -y.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

FIELD_LENGTH = 30.0  # m, along x
FIELD_WIDTH = 20.0  # m, along y
HALF_LENGTH = FIELD_LENGTH / 2
HALF_WIDTH = FIELD_WIDTH / 2
GOAL_WIDTH = 2.1  # m between the posts' inner faces
GOAL_DEPTH = 0.6  # m
GOAL_HEIGHT = 0.8  # m, under the crossbar
GOAL_POST_RADIUS = 0.05  # m
PENALTY_DEPTH = 1.8  # m
PENALTY_WIDTH = 3.9  # m (rcssserver3d 2020; the agents' code bases use 6.0)
CENTER_CIRCLE_RADIUS = 2.0  # m
BALL_RADIUS = 0.042  # m
BALL_MASS = 0.026  # kg
BALL_LINEAR_DRAG = 0.01  # N s/m: force -0.01 v on the ball's center (NAO.md, SimSpark's drag)
BALL_ROLLING_FRICTION = 0.001  # m; brings a slow ball to rest
# How the ball on the ground slows down, fitted on the simulated ball (rolls of 1-6 m/s):
# dv/dt = -BALL_ROLL_DRAG v - BALL_ROLL_DECEL v/|v| (the drag and the rolling friction).
BALL_ROLL_DRAG = 0.31  # 1/s
BALL_ROLL_DECEL = 0.045  # m/s^2
# Ball contacts (time constant s, damping ratio): restitution about 0.5. The league's
# ball bounces with 0.8 (NAO.md); a damping ratio under 0.2 at the 5 ms step makes a
# dropped ball gain energy in MuJoCo's soft contacts, so 0.2 is as lively as it stays stable.
BALL_SOLREF = (0.02, 0.2)

# Landmarks: name -> (x, y, z) in the field frame. Posts are marked at their tops.
FLAGS = {
    "F1L": (-HALF_LENGTH, HALF_WIDTH, 0.0),
    "F2L": (-HALF_LENGTH, -HALF_WIDTH, 0.0),
    "F1R": (HALF_LENGTH, HALF_WIDTH, 0.0),
    "F2R": (HALF_LENGTH, -HALF_WIDTH, 0.0),
}
POSTS = {
    "G1L": (-HALF_LENGTH, GOAL_WIDTH / 2, GOAL_HEIGHT),
    "G2L": (-HALF_LENGTH, -GOAL_WIDTH / 2, GOAL_HEIGHT),
    "G1R": (HALF_LENGTH, GOAL_WIDTH / 2, GOAL_HEIGHT),
    "G2R": (HALF_LENGTH, -GOAL_WIDTH / 2, GOAL_HEIGHT),
}
LANDMARKS = {**FLAGS, **POSTS}
LANDMARK_NAMES = tuple(LANDMARKS)
LANDMARK_POSITIONS = np.array([LANDMARKS[n] for n in LANDMARK_NAMES])


def rolling_distance(speed: float, drag: float = BALL_ROLL_DRAG,
                     deceleration: float = BALL_ROLL_DECEL) -> float:
    """Distance (m) a ball rolling at `speed` (m/s) travels before it rests, under
    dv/dt = -drag v - deceleration: v/drag - deceleration/drag^2 ln(1 + drag v / deceleration)."""
    if drag <= 0:
        return speed * speed / (2.0 * deceleration)
    return speed / drag - deceleration / drag ** 2 * math.log1p(drag * speed / deceleration)


def field_lines(circle_segments: int = 10) -> np.ndarray:
    """The field's lines as (n, 2, 3) segment end points in the field frame (m)."""
    L, W, pd, pw = HALF_LENGTH, HALF_WIDTH, PENALTY_DEPTH, PENALTY_WIDTH / 2
    segs = [
        ((-L, W), (L, W)), ((-L, -W), (L, -W)),  # side lines
        ((-L, -W), (-L, W)), ((L, -W), (L, W)),  # end lines
        ((0, -W), (0, W)),  # halfway line
    ]
    for sx in (-1, 1):  # penalty areas
        x0, x1 = sx * L, sx * (L - pd)
        segs += [((x1, -pw), (x1, pw)), ((x0, pw), (x1, pw)), ((x0, -pw), (x1, -pw))]
    a = np.linspace(0, 2 * math.pi, circle_segments + 1)
    r = CENTER_CIRCLE_RADIUS
    for i in range(circle_segments):
        segs.append(((r * math.cos(a[i]), r * math.sin(a[i])),
                     (r * math.cos(a[i + 1]), r * math.sin(a[i + 1]))))
    out = np.zeros((len(segs), 2, 3))
    out[:, :, :2] = np.array(segs, dtype=float)
    return out


FIELD_LINES = field_lines()


def _f(*v: float) -> str:
    return " ".join(f"{x:.6g}" for x in v)


def field_xml(world: ET.Element, floor_bits: tuple[int, int], goal_bits: tuple[int, int]) -> None:
    """Add the ground, line markings, flags and both goals to an MJCF worldbody.

    floor_bits and goal_bits are (contype, conaffinity) for the ground plane and
    the goal frames; lines and flags are visual only.
    """
    ET.SubElement(world, "geom", name="floor", type="plane",
                  size=_f(HALF_LENGTH + 3, HALF_WIDTH + 3, 0.1), rgba="0.2 0.55 0.2 1",
                  contype=str(floor_bits[0]), conaffinity=str(floor_bits[1]), friction="1 0.005 0.0001")
    for i, (p, q) in enumerate(FIELD_LINES):
        mid, d = (p + q) / 2, q - p
        length = float(np.hypot(d[0], d[1]))
        yaw = math.atan2(d[1], d[0])
        ET.SubElement(world, "geom", name=f"line{i}", type="box", pos=_f(mid[0], mid[1], 0.001),
                      size=_f(length / 2 + 0.025, 0.025, 0.001),
                      quat=_f(math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)),
                      rgba="1 1 1 1", contype="0", conaffinity="0")
    for name, (x, y, _) in FLAGS.items():
        ET.SubElement(world, "geom", name=name, type="cylinder", pos=_f(x, y, 0.25),
                      size="0.02 0.25", rgba="1 1 0 1", contype="0", conaffinity="0")
    ct, ca = (str(b) for b in goal_bits)
    r, w2, h, dpt = GOAL_POST_RADIUS, GOAL_WIDTH / 2, GOAL_HEIGHT, GOAL_DEPTH
    for sx, side in ((-1, "L"), (1, "R")):
        x0 = sx * HALF_LENGTH
        xb = sx * (HALF_LENGTH + dpt)
        rgba = "1 1 1 1"
        for sy, num in ((1, "1"), (-1, "2")):
            ET.SubElement(world, "geom", name=f"G{num}{side}", type="cylinder",
                          pos=_f(x0 + sx * r, sy * (w2 + r), h / 2), size=_f(r, h / 2),
                          rgba=rgba, contype=ct, conaffinity=ca)
            ET.SubElement(world, "geom", name=f"goal{side}_wall{num}", type="box",
                          pos=_f((x0 + xb) / 2 + sx * r, sy * (w2 + r), h / 2),
                          size=_f(dpt / 2, 0.01, h / 2), rgba="0.9 0.9 0.9 0.4",
                          contype=ct, conaffinity=ca)
        ET.SubElement(world, "geom", name=f"goal{side}_bar", type="cylinder",
                      pos=_f(x0 + sx * r, 0, h + r), size=_f(r, w2 + 2 * r),
                      quat=_f(math.cos(math.pi / 4), math.sin(math.pi / 4), 0, 0),
                      rgba=rgba, contype=ct, conaffinity=ca)
        ET.SubElement(world, "geom", name=f"goal{side}_back", type="box",
                      pos=_f(xb + sx * 0.01, 0, h / 2), size=_f(0.01, w2 + 2 * r, h / 2),
                      rgba="0.9 0.9 0.9 0.4", contype=ct, conaffinity=ca)
        ET.SubElement(world, "geom", name=f"goal{side}_roof", type="box",
                      pos=_f((x0 + xb) / 2 + sx * r, 0, h + 0.01), size=_f(dpt / 2, w2 + r, 0.01),
                      rgba="0.9 0.9 0.9 0.3", contype=ct, conaffinity=ca)


def ball_xml(world: ET.Element, contype: int, conaffinity: int) -> None:
    """Add the ball (a free body at the center spot) to an MJCF worldbody.

    The ball's six degrees of freedom are three world-aligned slide joints (ball_x,
    ball_y, ball_z) and a ball joint (ball), the same qpos and qvel layout as a free
    joint, so that the slides can carry the league's linear drag as joint damping
    (a free joint's damping would also brake the spin, and a rolling ball with it).
    """
    body = ET.SubElement(world, "body", name="ball", pos=_f(0, 0, BALL_RADIUS))
    for name, axis, ref in (("ball_x", "1 0 0", 0.0), ("ball_y", "0 1 0", 0.0),
                            ("ball_z", "0 0 1", BALL_RADIUS)):  # ref: qpos is the world position
        ET.SubElement(body, "joint", name=name, type="slide", axis=axis, ref=_f(ref),
                      damping=_f(BALL_LINEAR_DRAG), limited="false")
    ET.SubElement(body, "joint", name="ball", type="ball", limited="false")
    ET.SubElement(body, "geom", name="ball", type="sphere", size=_f(BALL_RADIUS),
                  mass=_f(BALL_MASS), rgba="1 0.5 0 1", condim="6",
                  friction=_f(0.8, 0.005, BALL_ROLLING_FRICTION),
                  solref=_f(*BALL_SOLREF), priority="1",
                  contype=str(contype), conaffinity=str(conaffinity))

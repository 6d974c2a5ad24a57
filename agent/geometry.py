"""Small geometry helpers shared by perception, localization and the world model.

Frames (all right-handed, meters and radians):

* *camera*: the head camera (x along the line of sight, y left, z up); vision
  arrives in polar form (distance, horizontal, vertical) in this frame.
* *torso*: the robot's torso body frame (x forward, y left, z up).
* *level*: the torso frame rotated by the torso's roll and pitch so that z is
  vertical; it shares the torso's origin and yaw. 2D observations for the
  localizer live here.
* *team*: the field frame as seen by one team: origin at the center spot, own
  goal at -x. For side 'L' it is the field frame of `models.field`; for side
  'R' it is that frame turned by 180 deg about z.
"""

from __future__ import annotations

import math

import numpy as np

from models import field
from models.geometry import wrap
from models.rules import Side
from skills.frames import rot_x, rot_y, rot_z  # noqa: F401  (re-exported for agent modules)

# The head chain (models/nao.py, project axes): neck yaw joint at torso +0.09 z,
# head pitch joint at neck +0.065 - 0.005 z, camera at the head center (+0.005 z
# from the pitch axis).
NECK_Z = 0.09  # m, hj1 axis origin above the torso center
PITCH_PIVOT_Z = 0.06  # m, hj2 axis above the neck origin
CAMERA_ABOVE_PIVOT = 0.005  # m, head center above the hj2 axis


def from_polar(pol: np.ndarray) -> np.ndarray:
    """(..., 3) polar (distance m, horizontal rad, vertical rad) -> cartesian (m)."""
    d, h, v = pol[..., 0], pol[..., 1], pol[..., 2]
    c = d * np.cos(v)
    return np.stack([c * np.cos(h), c * np.sin(h), d * np.sin(v)], axis=-1)


def to_polar(xyz: np.ndarray) -> np.ndarray:
    """(..., 3) cartesian (m) -> polar (distance, horizontal, vertical)."""
    x, y, z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    return np.stack([np.sqrt(x * x + y * y + z * z), np.arctan2(y, x),
                     np.arctan2(z, np.hypot(x, y))], axis=-1)


def camera_in_torso(neck_yaw: float, head_pitch: float) -> tuple[np.ndarray, np.ndarray]:
    """Pose of the camera in the torso frame for head joint angles hj1, hj2 (rad).

    Returns (R, p): camera axes as columns of R and the camera origin p (m), so a
    camera-frame vector v is R @ v + p in the torso frame. hj2 turns about -y,
    so a positive head pitch looks up.
    """
    r_yaw = rot_z(neck_yaw)
    r_pitch = rot_y(-head_pitch)
    r = r_yaw @ r_pitch
    p = np.array([0.0, 0.0, NECK_Z]) + r_yaw @ (
        np.array([0.0, 0.0, PITCH_PIVOT_Z]) + r_pitch @ np.array([0.0, 0.0, CAMERA_ABOVE_PIVOT]))
    return r, p


def team_sign(side: str) -> float:
    """+1 for side 'L', -1 for 'R': field frame (x, y) = sign * team frame (x, y)."""
    return 1.0 if side == Side.LEFT else -1.0


def field_to_team(xy: np.ndarray, side: str) -> np.ndarray:
    """Points (..., 2 or 3) from the field frame into a team's frame (z unchanged)."""
    out = np.array(xy, dtype=float, copy=True)
    out[..., :2] *= team_sign(side)
    return out


def team_to_field(xy: np.ndarray, side: str) -> np.ndarray:
    """Points (..., 2 or 3) from a team's frame into the field frame (same map as its inverse)."""
    return field_to_team(xy, side)


def heading_field_to_team(theta: float, side: str) -> float:
    """A heading (rad) in the field frame as a heading in the team frame."""
    return float(wrap(theta + (0.0 if side == Side.LEFT else math.pi)))


def landmarks_in_team(side: str) -> dict[str, np.ndarray]:
    """Every flag and post by SimSpark name at its (x, y, z) in the team frame (m)."""
    return {n: field_to_team(np.array(p, dtype=float), side) for n, p in field.LANDMARKS.items()}


def lines_in_team(side: str) -> np.ndarray:
    """The field lines (n, 2, 3) in the team frame (m); the field is symmetric, so
    only the order of the end points changes with the side."""
    return field_to_team(field.FIELD_LINES, side)

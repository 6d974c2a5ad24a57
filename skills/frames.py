"""Small rotation helpers (radians, right-handed frames).

`rpy` is (roll about x, pitch about y, yaw about z) applied in that order about
the fixed axes, i.e. R = Rz(yaw) @ Ry(pitch) @ Rx(roll).
"""

from __future__ import annotations

import math

import numpy as np


def rot_x(a: float) -> np.ndarray:
    """Rotation matrix about x by `a` rad."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """Rotation matrix about y by `a` rad."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    """Rotation matrix about z by `a` rad."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy_to_matrix(rpy) -> np.ndarray:
    """(roll, pitch, yaw) in rad -> 3x3 rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    r, p, y = (float(v) for v in rpy)
    cr, sr = math.cos(r), math.sin(r)
    cp, sp = math.cos(p), math.sin(p)
    cy, sy = math.cos(y), math.sin(y)
    return np.array([
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ])


def matrix_to_rpy(R: np.ndarray) -> np.ndarray:
    """3x3 rotation -> (roll, pitch, yaw) in rad, pitch in [-pi/2, pi/2]."""
    pitch = math.atan2(-R[2, 0], math.hypot(R[0, 0], R[1, 0]))
    if math.hypot(R[0, 0], R[1, 0]) < 1e-12:  # gimbal lock: put everything into roll
        return np.array([math.atan2(-R[1, 2], R[1, 1]), pitch, 0.0])
    return np.array([math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0])])


def pose(R: np.ndarray, p) -> np.ndarray:
    """4x4 homogeneous transform from a rotation and a translation (m)."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = p
    return T


def rotation_angle(R1: np.ndarray, R2: np.ndarray) -> float:
    """Angle (rad) of the rotation between two orientations."""
    c = (np.trace(R1.T @ R2) - 1.0) / 2.0
    return math.acos(min(1.0, max(-1.0, c)))

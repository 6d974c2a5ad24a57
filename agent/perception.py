"""Vision percepts turned from polar head-camera readings into the level torso frame.

The camera sits on a head that pans (hj1) and tilts (hj2) on the torso, which
itself leans. Every vision frame is therefore moved, with the head joint angles
read in the same percept and the torso tilt from `skills.imu`, into the *level*
frame (torso origin and yaw, z vertical; see `agent.geometry`). From there the
localizer turns 2D positions into the team frame with the pose estimate.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from agent import _kernels
from agent.geometry import CAMERA_ABOVE_PIVOT, NECK_Z, PITCH_PIVOT_Z
from models.messages import Vision


@dataclass(frozen=True)
class Observation:
    """One vision frame in the level frame (m, relative to the torso center).

    camera_rotation / camera_position give the camera's pose in the level frame
    (a camera-frame vector v is camera_rotation @ v + camera_position), for
    checking what should have been in view.
    """

    time: float  # s, server time of the percept
    landmark_names: tuple[str, ...]
    landmarks: np.ndarray  # (k, 3)
    ball: np.ndarray | None  # (3,)
    lines: np.ndarray  # (n, 2, 3) end points
    player_ours: np.ndarray  # (p,) bool
    player_unum: np.ndarray  # (p,) int
    player_part: np.ndarray  # (p,) index into models.messages.SEEN_PARTS
    players: np.ndarray  # (p, 3)
    camera_rotation: np.ndarray  # (3, 3)
    camera_position: np.ndarray  # (3,)

    @property
    def seen_anything_fixed(self) -> bool:
        """True when a landmark or a field line is in view (what the localizer can use)."""
        return len(self.landmark_names) > 0 or len(self.lines) > 0


_NO_BALL = np.empty((0, 3))
_UPRIGHT = np.eye(3)
_FROM_TILT = np.empty((0, 0))  # observe_frame: the level rotation from (roll, pitch)


def camera_in_level(neck_yaw: float, head_pitch: float, level: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Camera pose (R, p) in the level frame for head angles (rad) and the torso's
    torso-to-level rotation `level` (3x3): `camera_in_torso` turned by `level`."""
    return _kernels.camera_in_level(float(neck_yaw), float(head_pitch), np.asarray(level, dtype=float),
                                    NECK_Z, PITCH_PIVOT_Z, CAMERA_ABOVE_PIVOT)


def observe(vision: Vision, time: float, neck_yaw: float, head_pitch: float,
            level: np.ndarray | None = None, tilt: tuple[float, float] | None = None) -> Observation:
    """Move every object of a vision percept into the level frame.

    neck_yaw, head_pitch: hj1, hj2 (rad) of the same percept; level: the torso's
    torso-to-level rotation (identity for an upright torso), or tilt: the torso's
    (roll, pitch) (rad) it is made of (`skills.imu.TiltEstimator.level`).
    """
    if level is None:
        level = _UPRIGHT if tilt is None else _FROM_TILT
    roll, pitch = (0.0, 0.0) if tilt is None else tilt
    n_lm, n_ln, n_pl = len(vision.landmarks), len(vision.lines), len(vision.players)
    ball = _NO_BALL if vision.ball is None else np.asarray(vision.ball, dtype=float).reshape(1, 3)
    # One compiled conversion for every object of the frame (and the camera pose), then split.
    block = _kernels.observe_frame(_rows(vision.landmarks), _rows(vision.lines), _rows(vision.players), ball,
                                   float(neck_yaw), float(head_pitch), np.asarray(level, dtype=float),
                                   roll, pitch, NECK_Z, PITCH_PIVOT_Z, CAMERA_ABOVE_PIVOT)
    a, b = 4 + n_lm, 4 + n_lm + 2 * n_ln
    return Observation(
        time=time, landmark_names=vision.landmark_names, landmarks=block[4:a],
        ball=block[-1] if vision.ball is not None else None, lines=block[a:b].reshape(n_ln, 2, 3),
        player_ours=np.asarray(vision.player_ours, dtype=bool),
        player_unum=np.asarray(vision.player_unum, dtype=int),
        player_part=np.asarray(vision.player_part, dtype=int),
        players=block[b:b + n_pl], camera_rotation=block[:3], camera_position=block[3])


def _rows(a: np.ndarray) -> np.ndarray:
    """Polar readings as float (k, 3) rows."""
    return (a if a.dtype == np.float64 else a.astype(float)).reshape(-1, 3)

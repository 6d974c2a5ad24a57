"""The league's restricted vision model (SimSpark's RestrictedVisionPerceptor).

Every third cycle each robot sees, from its head camera, every object inside a
120 x 120 deg cone, without occlusion: flags, goal posts, the ball, the visible
parts of field lines (both end points, clipped to the cone), and other robots'
head, lower arms and feet. Positions are relative to the camera, with a fixed
per-robot calibration offset (uniform +-5 mm per axis, camera frame) and
Gaussian noise on distance (0.0965 % of it), horizontal (0.148 deg) and
vertical (0.1225 deg) angle.
"""

from __future__ import annotations

import math

import numpy as np

from models import field
from models.messages import Vision
from models.rules import (
    VIEW_CONE,
    VISION_CALIBRATION_ERROR,
    VISION_SIGMA_DIST,
    VISION_SIGMA_HORIZONTAL,
    VISION_SIGMA_VERTICAL,
)
from server.world import World

HALF_CONE = VIEW_CONE / 2
_T = math.tan(HALF_CONE)
# Inward normals of the four planes bounding the view pyramid (camera frame).
_PLANES = np.array([[_T, -1.0, 0.0], [_T, 1.0, 0.0], [_T, 0.0, -1.0], [_T, 0.0, 1.0]])


def to_polar(rel: np.ndarray) -> np.ndarray:
    """(..., 3) camera-frame vectors -> (..., 3) (distance, horizontal, vertical)."""
    x, y, z = rel[..., 0], rel[..., 1], rel[..., 2]
    return np.stack([np.sqrt(x * x + y * y + z * z), np.arctan2(y, x),
                     np.arctan2(z, np.hypot(x, y))], axis=-1)


def from_polar(pol: np.ndarray) -> np.ndarray:
    """Inverse of `to_polar`: (..., 3) polar -> camera-frame vectors."""
    d, h, v = pol[..., 0], pol[..., 1], pol[..., 2]
    c = np.cos(v)
    return np.stack([d * c * np.cos(h), d * c * np.sin(h), d * np.sin(v)], axis=-1)


def in_cone(pol: np.ndarray) -> np.ndarray:
    """Mask of polar points inside the view cone."""
    return (np.abs(pol[..., 1]) <= HALF_CONE) & (np.abs(pol[..., 2]) <= HALF_CONE)


def clip_segments(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Clip (m, 3) camera-frame segments a-b to the view pyramid.

    Returns the clipped end points and a mask of segments with a visible part.
    """
    fa = a @ _PLANES.T
    fb = b @ _PLANES.T
    with np.errstate(divide="ignore", invalid="ignore"):
        t = fa / (fa - fb)
    enter = (fa < 0) & (fb >= 0)
    leave = (fa >= 0) & (fb < 0)
    t0 = np.where(enter, t, 0.0).max(axis=1)
    t1 = np.where(leave, t, 1.0).min(axis=1)
    visible = ~((fa < 0) & (fb < 0)).any(axis=1) & (t0 < t1)
    d = b - a
    return a + t0[:, None] * d, a + t1[:, None] * d, visible


class VisionSensor:
    """Vision for every player of a world, with fixed calibration errors."""

    def __init__(self, world: World, rng: np.random.Generator) -> None:
        self.world = world
        self.rng = rng
        n = len(world.players)
        self.calibration = rng.uniform(-VISION_CALIBRATION_ERROR, VISION_CALIBRATION_ERROR, (n, 3))
        self.sigma = np.array([VISION_SIGMA_DIST / 100.0, VISION_SIGMA_HORIZONTAL,
                               VISION_SIGMA_VERTICAL])
        self._lines = field.FIELD_LINES

    def _noisy(self, pol: np.ndarray) -> np.ndarray:
        noise = self.rng.standard_normal(pol.shape) * self.sigma
        out = pol + noise
        out[..., 0] = pol[..., 0] * (1.0 + noise[..., 0])
        return out

    def see_all(self, observers: list[int] | None = None) -> dict[int, Vision]:
        """Vision percepts of the given players (all by default), computed together."""
        w = self.world
        d = w.data
        n = len(w.players)
        obs = np.arange(n) if observers is None else np.asarray(observers, dtype=int)
        parts = d.xpos[w.part_ids]  # (n, 5, 3)
        objects = np.vstack([field.LANDMARK_POSITIONS, d.xpos[w.ball_body][None, :],
                             parts.reshape(-1, 3)])  # (K, 3) world frame
        cam = d.site_xpos[w.camera_ids[obs]]  # (m, 3)
        rot = d.site_xmat[w.camera_ids[obs]].reshape(-1, 3, 3)  # camera axes as columns
        calib = self.calibration[obs][:, None, :]
        # Camera-frame coordinates of every object for every observer: (m, K, 3).
        rel = np.einsum("mkj,mji->mki", objects[None, :, :] - cam[:, None, :], rot) + calib
        pol = to_polar(rel)
        seen = in_cone(pol)
        nl = len(field.LANDMARK_NAMES)
        for r, i in enumerate(obs):  # a robot does not see its own parts
            seen[r, nl + 1 + 5 * i: nl + 1 + 5 * (i + 1)] = False
        rows, cols = np.nonzero(seen)
        noisy = self._noisy(pol[rows, cols])
        # Lines: (m, L, 2, 3) end points in camera frames, clipped to the cone.
        ends = np.einsum("lej,mji->mlei", self._lines, rot) - np.einsum(
            "mj,mji->mi", cam, rot)[:, None, None, :] + calib[:, :, None, :]
        a, b, vis = clip_segments(ends[:, :, 0].reshape(-1, 3), ends[:, :, 1].reshape(-1, 3))
        vis = vis.reshape(len(obs), -1)
        line_pol = self._noisy(to_polar(np.stack([a, b], axis=1))).reshape(len(obs), -1, 2, 3)
        out: dict[int, Vision] = {}
        bounds = np.searchsorted(rows, np.arange(len(obs) + 1))
        names = field.LANDMARK_NAMES
        for r, i in enumerate(obs):
            c = cols[bounds[r]:bounds[r + 1]]
            p = noisy[bounds[r]:bounds[r + 1]]
            lm = c < nl
            is_ball = c == nl
            pl = c > nl
            who, part = np.divmod(c[pl] - nl - 1, 5)
            out[int(i)] = Vision(
                landmark_names=tuple(names[k] for k in c[lm]), landmarks=p[lm],
                ball=p[is_ball][0] if is_ball.any() else None, lines=line_pol[r][vis[r]],
                player_ours=w.side_of[who] == w.side_of[i], player_unum=w.unum_of[who],
                player_part=part, players=p[pl])
        return out

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


def in_cone_xyz(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Mask of camera-frame points (x, y, z) inside the view cone: `in_cone` of their
    polar coordinates, decided without computing the angles."""
    return (np.abs(y) <= _T * x) & (z * z <= (_T * _T) * (x * x + y * y))


def clip_segments(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Clip (m, 3) camera-frame segments a-b to the view pyramid.

    Returns the clipped end points and a mask of segments with a visible part.
    """
    fa = a @ _PLANES.T
    fb = b @ _PLANES.T
    out_a = fa < 0
    out_b = fb < 0
    enter = out_a & ~out_b
    leave = out_b & ~out_a
    # Where a segment crosses a plane, fa and fb differ in sign, so fa - fb != 0.
    t = fa / np.where(enter | leave, fa - fb, 1.0)
    t0 = np.where(enter, t, 0.0).max(axis=1)
    t1 = np.where(leave, t, 1.0).min(axis=1)
    visible = ~(out_a & out_b).any(axis=1) & (t0 < t1)
    d = b - a
    return a + t0[:, None] * d, a + t1[:, None] * d, visible


class VisionSensor:
    """Vision for every player of a world, with fixed calibration errors.

    One call of `see_all` computes every observer's view with a handful of numpy
    operations over (observers x objects) arrays; each `Vision` then holds views
    (slices) of those arrays, one disjoint block per observer.
    """

    def __init__(self, world: World, rng: np.random.Generator) -> None:
        self.world = world
        self.rng = rng
        n = len(world.players)
        self.calibration = rng.uniform(-VISION_CALIBRATION_ERROR, VISION_CALIBRATION_ERROR, (n, 3))
        self.sigma = np.array([VISION_SIGMA_DIST / 100.0, VISION_SIGMA_HORIZONTAL,
                               VISION_SIGMA_VERTICAL])
        self._lines = field.FIELD_LINES
        self._names = list(field.LANDMARK_NAMES)
        nl = len(self._names)
        nparts = world.part_ids.shape[1]
        self._nl = nl
        # Every object's world coordinates, one row per axis, in column order:
        # landmarks, ball, then each player's SEEN_PARTS. Landmarks never move; the
        # rest is refreshed per call. And the field lines' end points (a0, b0, a1, ...).
        self._nobj = nl + 1 + nparts * n
        self._objects = np.empty((3, self._nobj))
        self._objects[:, :nl] = field.LANDMARK_POSITIONS.T
        self._line_ends = np.ascontiguousarray(self._lines.reshape(-1, 3).T)
        self._part_ids = world.part_ids.reshape(-1)
        # Per object column: for other players' parts, the player's side (True: left),
        # uniform number and part index (zeros for landmarks and the ball).
        owner = np.repeat(np.arange(n), nparts)
        pc = slice(nl + 1, self._nobj)
        self._col_side = np.zeros(self._nobj, dtype=bool)
        self._col_side[pc] = world.side_of[owner] == "L"
        self._col_unum = np.zeros(self._nobj, dtype=world.unum_of.dtype)
        self._col_unum[pc] = world.unum_of[owner]
        self._col_part = np.zeros(self._nobj, dtype=np.intp)
        self._col_part[pc] = np.tile(np.arange(nparts), n)
        self._side_left = world.side_of == "L"
        # own[i, k]: object column k is one of player i's own parts (never seen).
        own = np.zeros((n, self._nobj), dtype=bool)
        own[owner, nl + 1 + np.arange(nparts * n)] = True
        self._not_own = ~own
        self._everyone = np.arange(n)

    def _noisy(self, pol: np.ndarray) -> np.ndarray:
        noise = self.rng.standard_normal(pol.shape) * self.sigma
        out = pol + noise
        out[..., 0] = pol[..., 0] * (1.0 + noise[..., 0])
        return out

    def see_all(self, observers: list[int] | None = None) -> dict[int, Vision]:
        """Vision percepts of the given players (all by default), computed together."""
        w = self.world
        d = w.data
        obs = self._everyone if observers is None else np.asarray(observers, dtype=int)
        m = len(obs)
        if m == 0:
            return {}
        nl = self._nl
        objects = self._objects
        objects[:, nl] = d.xpos[w.ball_body]
        objects[:, nl + 1:] = d.xpos[self._part_ids].T
        cam_ids = w.camera_ids[obs]
        cam = d.site_xpos[cam_ids]  # (m, 3)
        rot = d.site_xmat[cam_ids].reshape(-1, 3, 3)  # camera axes as columns
        calib = self.calibration[obs]
        # Camera-frame coordinates of every object for every observer, (p - cam) R +
        # calibration, one (m, K) array per axis. The products and sums come in the
        # order numpy's einsum takes them (as this code once did with einsum, 20x
        # slower), so a seed still gives the same percepts to the last bit.
        q = [[rot[:, j, i, None] for i in range(3)] for j in range(3)]
        dx, dy, dz = (objects[j][None, :] - cam[:, j, None] for j in range(3))
        x, y, z = (dx * q[0][i] + dy * q[1][i] + dz * q[2][i] + calib[:, i, None] for i in range(3))
        seen = in_cone_xyz(x, y, z)
        seen &= self._not_own[obs]  # a robot does not see its own parts
        rows, cols = np.nonzero(seen)  # row-major: per observer, columns ascending
        # Lines: end points in camera frames (p R - cam R + calibration), clipped to the cone.
        e0, e1, e2 = self._line_ends
        ends = np.stack([
            e0 * q[0][i] + e1 * q[1][i] + e2 * q[2][i]
            - (cam[:, 0] * q[0][i][:, 0] + cam[:, 1] * q[1][i][:, 0] + cam[:, 2] * q[2][i][:, 0])[:, None]
            + calib[:, i, None] for i in range(3)], axis=-1).reshape(-1, 2, 3)  # (m * L, 2, 3)
        a, b, vis = clip_segments(ends[:, 0], ends[:, 1])
        n_seen = len(rows)
        # Noise for the objects in view, then for every line's end points, in one draw.
        seen_xyz = np.stack([x[rows, cols], y[rows, cols], z[rows, cols]], axis=-1)
        noisy = self._noisy(to_polar(np.concatenate([seen_xyz, np.stack([a, b], axis=1).reshape(-1, 3)])))
        line_pol = noisy[n_seen:].reshape(-1, 2, 3)[vis]  # (visible, 2, 3)
        noisy = noisy[:n_seen]
        # Per observer, its block of `rows` is [landmarks][ball?][players] (column order).
        count = seen.sum(axis=1)
        start = np.zeros(m + 1, dtype=np.intp)
        np.cumsum(count, out=start[1:])
        n_lm = seen[:, :nl].sum(axis=1)
        has_ball = seen[:, nl]
        line_start = np.zeros(m + 1, dtype=np.intp)
        np.cumsum(vis.reshape(m, len(self._lines)).sum(axis=1), out=line_start[1:])
        ours = self._col_side[cols] == self._side_left[obs][rows]
        unum = self._col_unum[cols]
        part = self._col_part[cols]
        names = self._names
        col_list = cols.tolist()
        out: dict[int, Vision] = {}
        for i, s, e, k, hb, l0, l1 in zip(
                obs.tolist(), start[:-1].tolist(), start[1:].tolist(), n_lm.tolist(),
                has_ball.tolist(), line_start[:-1].tolist(), line_start[1:].tolist()):
            b0 = s + k
            p0 = b0 + hb
            out[i] = Vision(
                landmark_names=tuple([names[c] for c in col_list[s:b0]]), landmarks=noisy[s:b0],
                ball=noisy[b0] if hb else None, lines=line_pol[l0:l1],
                player_ours=ours[p0:e], player_unum=unum[p0:e], player_part=part[p0:e],
                players=noisy[p0:e])
        return out

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
    Side,
)
from server._kernels import camera_views
from server.world import World

HALF_CONE = VIEW_CONE / 2
_T = math.tan(HALF_CONE)
NOISE_POOL = 1 << 17  # standard normal draws per refill of the noise pool


def to_polar(rel: np.ndarray) -> np.ndarray:
    """(..., 3) camera-frame vectors -> (..., 3) (distance, horizontal, vertical)."""
    x, y, z = rel[..., 0], rel[..., 1], rel[..., 2]
    return np.stack([np.sqrt(x * x + y * y + z * z), np.arctan2(y, x),
                     np.arctan2(z, np.hypot(x, y))], axis=-1)


def in_cone(pol: np.ndarray) -> np.ndarray:
    """Mask of polar points inside the view cone."""
    return (np.abs(pol[..., 1]) <= HALF_CONE) & (np.abs(pol[..., 2]) <= HALF_CONE)


class VisionSensor:
    """Vision for every player of a world, with fixed calibration errors.

    One call of `see_all` computes every observer's view at once, geometry and
    noise in one compiled loop (`server._kernels.camera_views`), the noise taken in
    order from a pool of standard normal draws of the seeded `rng`; each
    `Vision` then holds views (slices) of those arrays, one disjoint block per
    observer.
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
        # Every point's world coordinates, one row each: the objects in column order
        # (landmarks, ball, then each player's SEEN_PARTS), then the field lines' end
        # points (a0, b0, a1, ...). Landmarks and lines never move; the rest is
        # refreshed per call.
        self._nobj = nl + 1 + nparts * n
        self._points = np.empty((self._nobj + 2 * len(self._lines), 3))
        self._points[:nl] = field.LANDMARK_POSITIONS
        self._points[self._nobj:] = self._lines.reshape(-1, 3)
        self._part_ids = world.part_ids.reshape(-1)
        # Per object column: for other players' parts, the player's side (True: left),
        # uniform number and part index (zeros for landmarks and the ball).
        owner = np.repeat(np.arange(n), nparts)
        pc = slice(nl + 1, self._nobj)
        self._col_side = np.zeros(self._nobj, dtype=bool)
        self._col_side[pc] = world.side_of[owner] == Side.LEFT
        self._col_unum = np.zeros(self._nobj, dtype=world.unum_of.dtype)
        self._col_unum[pc] = world.unum_of[owner]
        self._col_part = np.zeros(self._nobj, dtype=np.intp)
        self._col_part[pc] = np.tile(np.arange(nparts), n)
        self._side_left = world.side_of == Side.LEFT
        # own[i, k]: object column k is one of player i's own parts (never seen).
        own = np.zeros((n, self._nobj), dtype=bool)
        own[owner, nl + 1 + np.arange(nparts * n)] = True
        self._not_own = ~own
        self._everyone = np.arange(n)
        self._pool = np.empty(0)  # standard normal draws for the noise, used in order
        self._used = 0
        self._most = 3 * (self._nobj + 2 * len(self._lines))  # draws one observer may need

    def _noise_from(self, need: int) -> int:
        """Where the next `need` draws start in the noise pool, refilled from `rng`
        (in blocks of NOISE_POOL: one big draw costs less than many small ones)."""
        if self._used + need > len(self._pool):
            self._pool = self.rng.standard_normal(max(NOISE_POOL, need))
            self._used = 0
        return self._used

    def see_all(self, observers: list[int] | None = None) -> dict[int, Vision]:
        """Vision percepts of the given players (all by default), computed together."""
        w = self.world
        d = w.data
        obs = self._everyone if observers is None else np.asarray(observers, dtype=int)
        m = len(obs)
        if m == 0:
            return {}
        nl = self._nl
        points = self._points
        points[nl] = d.xpos[w.ball_body]
        points[nl + 1:self._nobj] = d.xpos[self._part_ids]
        cam_ids = w.camera_ids[obs]
        start = self._noise_from(m * self._most)
        cols, noisy, ours, obj_end, line_pol, line_end, used = camera_views(
            points, self._nobj, self._not_own[obs], d.site_xpos[cam_ids],
            d.site_xmat[cam_ids].reshape(-1, 3, 3), self.calibration[obs], _T,
            self._pool, start, self.sigma, self._side_left[obs], self._col_side)
        self._used += used
        # Per observer, its block of objects is [landmarks][ball?][players] (column order).
        unum = self._col_unum[cols]
        part = self._col_part[cols]
        names = self._names
        col_list = cols.tolist()
        out: dict[int, Vision] = {}
        s = l0 = 0
        for i, e, l1 in zip(obs.tolist(), obj_end.tolist(), line_end.tolist()):
            b0 = s
            while b0 < e and col_list[b0] < nl:
                b0 += 1
            hb = b0 < e and col_list[b0] == nl
            p0 = b0 + hb
            out[i] = Vision(
                landmark_names=tuple([names[c] for c in col_list[s:b0]]), landmarks=noisy[s:b0],
                ball=noisy[b0] if hb else None, lines=line_pol[l0:l1],
                player_ours=ours[p0:e], player_unum=unum[p0:e], player_part=part[p0:e],
                players=noisy[p0:e])
            s, l0 = e, l1
        return out

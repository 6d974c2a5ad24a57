"""Monte Carlo localization: a particle filter over the robot's (x, y, heading).

Frames: particles live in the *team* frame (m, rad; own goal at -x);
observations come in the *level* torso frame (see `agent.geometry`), reduced
to 2D. Section 8.2.2 of MacAlpine's dissertation: 500 particles; on every
vision frame (1) odometry moves the particles (`predict`, fed every cycle by
the walk), (2) landmark and field line observations weight them (Gaussians
over distance and bearing error, in log space; the longest K observed lines
each scored against its most similar known line by end-point distance, angle
and length ratio), (3) resampling, only when something was seen, with 5 % of
the particles drawn anew for a kidnapped robot, then a small random walk. The
pose estimate is the weighted mean of the weighted set (before resampling) with
a circular mean for the heading, moved on by odometry until the next frame.

Deviations, each to make the filter fast or quick to recover:

* Line matching scores the observed line's midpoint distance from the known
  line plus how far its end points reach past the known segment's ends (both
  measured along the known line), which keeps every term linear in the
  particle's features so that one matrix product serves all particles,
  observed and known lines (see `log_likelihood`).
* Half of the fresh 5 % are drawn uniformly over the field, the other half from
  the current landmark observations (sensor resetting: the pose a pair of seen
  landmarks implies, or with a single landmark a random heading and the
  position that puts it where it was seen). Recovery from a kidnap then takes a
  few vision frames rather than the tens of seconds pure uniform draws need on
  a 600 m^2 field.
* The random walk grows (up to 8x) while even the best particle fits the
  observations badly, so a cloud that collapsed next to the truth moves onto it.
* The walk's odometry arrives every cycle and moves the estimate at once, but the
  particles only when they are next read (in practice once per vision frame), by
  the steps composed since, with noise of 1/sqrt(steps) of the per-step fraction
  (the spread of that many equal steps with independent noise): one pass over the
  particles per frame instead of three.
* Resampling is systematic (the algorithm of filterpy's `systematic_resample`)
  but compiled (one pass over the cumulative weights) and driven by this
  filter's own seeded generator: filterpy's version loops in Python and draws
  from numpy's global random state.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from agent import _kernels as kernels
from agent.geometry import landmarks_in_team, lines_in_team
from models import field
from models.geometry import rotate, wrap

# UT Austin Villa's odometry factors (a, b, c) for x, y and turn, as shared/NAO.md
# reads them from PFLocalization.cc: fitted to their walk's odometry.
UT_ODOMETRY_FACTORS = (0.8, 0.3, 0.2)
# Ours, fitted to skills/walk.py: true torso displacement over the displacement the
# walk reports, 10 s of walking forward, sideways and turning, mean over types 0-4
# (forward 0.85-1.03 by type, sideways 0.91-1.00; the turn comes from the gyro: 1.00-1.04).
WALK_ODOMETRY_FACTORS = (0.94, 0.95, 1.0)


@dataclass
class LocalizationParams:
    """Tunable figures of the particle filter (SI units)."""

    n_particles: int = 500
    # Odometry: each step (dx, dy, dtheta) is scaled by these factors (the
    # paper's a, b, c, fitted to our walk) ...
    odometry_scale: tuple[float, float, float] = WALK_ODOMETRY_FACTORS
    # ... and perturbed by Gaussian noise of this fraction of its size.
    odometry_noise: tuple[float, float, float] = (0.2, 0.2, 0.2)
    sigma_distance: float = 0.05  # m, landmark distance error, plus ...
    sigma_distance_rel: float = 0.01  # ... this fraction of the distance
    sigma_bearing: float = 0.02  # rad, landmark bearing error
    line_count: int = 3  # K longest observed lines used
    min_line_length: float = 0.3  # m, shorter observed lines are ignored
    sigma_line_distance: float = 0.15  # m, end point to known line
    sigma_line_angle: float = 0.08  # rad, acute angle between observed and known line
    sigma_line_ratio: float = 0.1  # excess of observed / known length over 1
    random_fraction: float = 0.05  # particles drawn anew at each resampling
    walk_xy: float = 0.015  # m, random-walk noise after resampling
    walk_theta: float = 0.008  # rad
    seed_sigma_theta: float = 0.02  # rad of noise on headings of particles seeded from landmarks
    walk_max_growth: float = 8.0  # largest factor on the random walk when the best particle fits badly
    field_margin: float = 0.5  # m beyond the lines where uniform particles may fall


class ParticleFilter:
    """500 (x, y, heading) particles in the team frame of `side` ('L' or 'R').

    Feed it `predict(dx, dy, dtheta)` with odometry (torso frame, m and rad)
    every cycle, and `update(...)` with each vision frame's level-frame
    observations; read `pose`. Particle headings are not wrapped after the random
    walk (only their sine and cosine are used); `pose` is.
    """

    def __init__(self, side: str = "L", seed: int = 0, params: LocalizationParams | None = None) -> None:
        self.params = params or LocalizationParams()
        self.rng = np.random.default_rng(seed)
        self._gen = kernels.bitgen_addresses(self.rng)  # see _draws
        self.side = side
        lm = landmarks_in_team(side)
        self._lm_names = {n: i for i, n in enumerate(lm)}
        self._lm_index: dict[tuple[str, ...], np.ndarray] = {}  # names seen -> indices (-1: unknown)
        self._lm_xy = np.array([v[:2] for v in lm.values()])
        lines = lines_in_team(side)[:, :, :2]
        a, b = lines[:, 0], lines[:, 1]
        d = b - a
        length = np.hypot(d[:, 0], d[:, 1])
        u = d / length[:, None]
        self._line_len = length
        angle = np.arctan2(u[:, 1], u[:, 0])
        n = np.stack([-u[:, 1], u[:, 0]], axis=1)
        mid = (a + b) / 2
        # Rows of _line_w map an observed line's features (fx, fy, C, S, 1) - its
        # midpoint in the team frame and cos / sin of twice its direction - to, per
        # known line: the midpoint's coordinate along it from its center and its
        # distance from it (both over sigma_line_distance), and the angle penalty
        # (1 - cos 2 da) / (2 sigma_line_angle^2) = sin^2 da / sigma^2 ~ (da / sigma)^2.
        inv = 1.0 / self.params.sigma_line_distance
        ka = 0.5 / self.params.sigma_line_angle ** 2
        m_lines = len(a)
        w = np.zeros((3 * m_lines, 5))
        w[:m_lines, 0:2] = u * inv
        w[:m_lines, 4] = -(mid * u).sum(axis=1) * inv
        w[m_lines:2 * m_lines, 0:2] = n * inv
        w[m_lines:2 * m_lines, 4] = -(a * n).sum(axis=1) * inv
        w[2 * m_lines:, 2] = -ka * np.cos(2 * angle)
        w[2 * m_lines:, 3] = -ka * np.sin(2 * angle)
        w[2 * m_lines:, 4] = ka
        self._line_w = w
        # Pieces of the center circle are short; an observed line longer than
        # _circle_piece is compared with the straight lines only.
        r_mid = np.hypot(mid[:, 0], mid[:, 1])
        straight = ~((r_mid < field.CENTER_CIRCLE_RADIUS + 1e-6) & (length < field.CENTER_CIRCLE_RADIUS))
        self._circle_piece = float(length[~straight].max() * 1.1) if (~straight).any() else math.inf
        rows = np.concatenate([np.nonzero(straight)[0] + j * m_lines for j in range(3)])
        self._line_w_straight = w[rows]
        self._line_len_straight = length[straight]
        m = self.params.field_margin
        self._bounds = np.array([field.HALF_LENGTH + m, field.HALF_WIDTH + m])
        self._high = np.array([self._bounds[0], self._bounds[1], math.pi])
        self._low = -self._high
        self._range = self._high - self._low
        n_p = self.params.n_particles
        self._particles = np.zeros((n_p, 3))
        # Odometry not yet applied to the particles: the scaled steps composed in the torso
        # frame of the first of them (m, m, rad), and how many (see predict).
        self._pending, self._pending_steps = (0.0, 0.0, 0.0), 0
        self._scratch_pose = np.zeros(3)  # the kernel moves a pose too: predict moved the estimate already
        self._spare = np.zeros((n_p, 3))  # the next resampling's output; then they swap
        self._c, self._s = np.empty(n_p), np.empty(n_p)  # particle heading cosines, sines
        self._ll, self._tmp = np.empty(n_p), np.empty(n_p)  # log-likelihoods, scratch
        self._no_lines = np.zeros((0, 2, 2))
        self._no_landmarks = np.zeros((0, 2))
        self.weights = np.full(n_p, 1.0 / n_p)
        self._pose = np.zeros(3)
        self._spread = float("inf")
        self.misfit = 0.0  # s.d. per measured quantity of the best particle at the last update
        self.last_update_seen = False
        self.reset_uniform()

    # ------------------------------------------------------------------ resets

    def _uniform(self, k: int) -> np.ndarray:
        out = np.empty((k, 3))
        out[:, :2] = self.rng.uniform(-self._bounds, self._bounds, (k, 2))
        out[:, 2] = self.rng.uniform(-math.pi, math.pi, k)
        return out

    def reset_uniform(self) -> None:
        """Forget everything: particles spread uniformly over the field and headings."""
        self._pending, self._pending_steps = (0.0, 0.0, 0.0), 0
        self._particles[:] = self._uniform(len(self._particles))
        self.weights.fill(1.0 / len(self.weights))
        self._pose = self._mean(self._particles, self.weights)
        self._spread = float("inf")

    def reset_around(self, x: float, y: float, theta: float, sigma_xy: float = 0.1,
                     sigma_theta: float = 0.1, fraction: float = 1.0) -> None:
        """Put `fraction` of the particles (the rest stay) in a Gaussian around a pose
        (team frame; m, rad), e.g. after a beam or a teammate's report. The estimate is
        that pose until the next update weighs the particles."""
        p = self.particles
        n = len(p)
        k = max(1, min(n, int(round(fraction * n))))
        idx = self.rng.choice(n, k, replace=False) if k < n else np.arange(n)
        noise = self.rng.standard_normal((k, 3)) * (sigma_xy, sigma_xy, sigma_theta)
        p[idx] = np.array([x, y, theta]) + noise
        p[idx, 2] = wrap(p[idx, 2])
        self.weights.fill(1.0 / n)
        self._pose = np.array([x, y, float(wrap(theta))])  # until the next update weighs them
        self._spread = sigma_xy

    def _draws(self) -> np.ndarray:
        """The addresses through which the kernels draw from self.rng's PCG64, found anew
        when its state has moved (a copied or unpickled filter has a new generator)."""
        if self._gen[0] != self.rng.bit_generator.ctypes.state_address:
            self._gen = kernels.bitgen_addresses(self.rng)
        return self._gen

    # ---------------------------------------------------------------- odometry

    def predict(self, dx: float, dy: float, dtheta: float) -> None:
        """Move the estimate by an odometry step (dx, dy in m in the torso frame at the
        step's start, dtheta in rad) scaled per `LocalizationParams`; the particles follow
        when next read (`particles`, `update`), by the steps composed since."""
        if dx == 0.0 and dy == 0.0 and dtheta == 0.0:
            return
        sx, sy, st = self.params.odometry_scale
        ex, ey, et = sx * dx, sy * dy, st * dtheta
        x, y, t = self._pose.tolist()
        rx, ry = rotate(ex, ey, t)
        self._pose = np.array([x + rx, y + ry, wrap(t + et)])
        px, py, pt = self._pending
        rx, ry = rotate(ex, ey, pt)
        self._pending = (px + rx, py + ry, pt + et)
        self._pending_steps += 1

    @property
    def particles(self) -> np.ndarray:
        """The (n, 3) particles (team frame; m, m, rad), moved by the odometry so far."""
        if self._pending_steps:
            self._apply_odometry()
        return self._particles

    def _apply_odometry(self) -> None:
        """Move the particles by the composed pending steps, perturbed by Gaussian noise of
        `odometry_noise` / sqrt(steps) of the composite: the spread k equal steps with
        independent noise of `odometry_noise` each would give (k = steps)."""
        nx, ny, nt = self.params.odometry_noise
        k = math.sqrt(self._pending_steps)
        ex, ey, et = self._pending
        # The noise: (n, 3) standard normal draws of self.rng, as rng.standard_normal((n, 3)).
        kernels.predict_particles(self._particles, self._scratch_pose, self._draws(), ex, ey, et,
                                  nx / k, ny / k, nt / k)
        self._pending, self._pending_steps = (0.0, 0.0, 0.0), 0

    # ------------------------------------------------------------ observations

    def _observed(self, particles: np.ndarray, landmark_names: tuple[str, ...] | list[str],
                  landmarks: np.ndarray, lines: np.ndarray, c: np.ndarray, s: np.ndarray, ll: np.ndarray,
                  tmp: np.ndarray) -> tuple[np.ndarray, np.ndarray, int, int]:
        """Fill ll with the log-likelihood of the observations for particles (n, 3), c and s
        with their heading cosines and sines (tmp: scratch, (n,)); return the landmark
        indices (-1 for unknown names), the landmarks as a float array and the numbers of
        landmarks and lines used."""
        pr = self.params
        named = isinstance(landmark_names, tuple)  # a list does not hash
        lm_idx = self._lm_index.get(landmark_names) if named else None
        if lm_idx is None:
            if len(self._lm_index) > 4096:  # a bound, far above the sets of landmarks seen in a game
                self._lm_index.clear()
            get = self._lm_names.get
            lm_idx = np.array([get(name, -1) for name in landmark_names], dtype=np.int64)
            if named:
                self._lm_index[landmark_names] = lm_idx
        landmarks = np.asarray(landmarks, dtype=float)
        lines = np.asarray(lines, dtype=float)
        if lines.ndim != 3:  # no lines, in any shape
            lines = self._no_lines
        if not len(lm_idx):
            landmarks = self._no_landmarks
        n_landmarks, n_lines = kernels.observation_log_likelihood(
            particles, c, s, self._lm_xy, lm_idx, landmarks, lines, pr.line_count, pr.min_line_length,
            self._circle_piece, self._line_w, self._line_len, self._line_w_straight, self._line_len_straight,
            pr.sigma_distance, pr.sigma_distance_rel, 1.0 / pr.sigma_bearing ** 2,
            1.0 / pr.sigma_line_distance, pr.sigma_line_ratio, ll, tmp)
        return lm_idx, landmarks, n_landmarks, n_lines

    def log_likelihood(self, particles: np.ndarray, landmark_names: tuple[str, ...] | list[str],
                       landmarks: np.ndarray, lines: np.ndarray) -> np.ndarray:
        """Log-likelihood (n,) of the observations for each particle (n, 3).

        landmarks: (k, 2+) level-frame positions (m) of the named landmarks;
        lines: (l, 2, 2+) level-frame end points (m) of observed field lines.

        Per particle and landmark: Gaussians over the distance error and the bearing
        error (the latter through its chord, 2 - 2 cos d ~ d^2); per observed line (the
        line_count longest), the best match over the known lines (see
        `kernels.line_log_likelihood`): the midpoint's distance from the known line, how
        far its end points reach past the known segment's ends, the acute angle between
        the lines and the excess of the length ratio over 1. Observed lines too long to
        be a piece of the center circle are matched against the straight lines only.
        """
        p = np.ascontiguousarray(particles, dtype=float)
        c, s, ll, tmp = np.empty(len(p)), np.empty(len(p)), np.empty(len(p)), np.empty(len(p))
        self._observed(p, landmark_names, landmarks, lines, c, s, ll, tmp)
        return ll

    def update(self, landmark_names: tuple[str, ...] | list[str], landmarks: np.ndarray,
               lines: np.ndarray) -> bool:
        """Weight the particles by one vision frame's observations and resample.

        landmarks: (k, 2+) level-frame positions (m) of the named landmarks; lines:
        (l, 2, 2+) level-frame end points (m) of observed field lines. Returns False
        (and changes nothing) when neither a landmark nor a usable line was seen.
        """
        p, c, s = self.particles, self._c, self._s  # particles: odometry applied
        lm_idx, landmarks, n_landmarks, n_lines = self._observed(p, landmark_names, landmarks, lines, c, s,
                                                                 self._ll, self._tmp)
        self.last_update_seen = n_landmarks > 0 or n_lines > 0
        if not self.last_update_seen:
            return False
        # Weights, estimate and spread; then systematic resampling of all but the fresh 5 %,
        # a random walk that grows when even the best particle fits badly (the cloud has
        # collapsed next to the truth rather than on it) and fresh particles, half of them
        # seeded from the landmarks seen. misfit: the best particle's s.d. per measured quantity.
        pr = self.params
        out = self._spare
        self.misfit, self._spread = kernels.weigh_and_resample(
            p, self._ll, c, s, self.weights, self._pose, self._tmp, 2 * n_landmarks + 3 * n_lines,
            self._draws(), int(round(pr.random_fraction * len(p))), pr.walk_xy, pr.walk_theta,
            pr.walk_max_growth, self._low, self._range, self._lm_xy, lm_idx, landmarks, pr.seed_sigma_theta,
            out)
        self._spare, self._particles = p, out
        return True

    # ---------------------------------------------------------------- estimate

    @staticmethod
    def _mean(p: np.ndarray, w: np.ndarray) -> np.ndarray:
        """Weighted mean (x, y) and circular mean heading of particles p with weights w."""
        return np.array([w @ p[:, 0], w @ p[:, 1], math.atan2(w @ np.sin(p[:, 2]), w @ np.cos(p[:, 2]))])

    @property
    def pose(self) -> np.ndarray:
        """Estimated (x, y, heading) in the team frame (m, m, rad): the weighted mean
        of the last weighted particle set, moved on by odometry since."""
        return self._pose.copy()

    @property
    def spread(self) -> float:
        """Weighted standard deviation (m) of the particles' positions around the estimate,
        as of the last weighting (the fresh 5 % of a resampling are left out)."""
        return self._spread

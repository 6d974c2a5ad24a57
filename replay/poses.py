"""A match log ready to replay: its MuJoCo model, frame lookup and player poses.

Frames are the log's 20 ms cycles. Times given by a user are game time (s),
the clock on the frames and in the log's events; frames in which the clock
stands (before a kickoff, after a goal) share one game time. Poses are in the
field frame of `models.field` (m, rad; x toward the right team's goal).
"""

from __future__ import annotations

import os

import mujoco
import numpy as np

from models.rules import PLAY_MODES
from server.log import LogError, MatchLog, read_log

FREE_QPOS = 7  # x y z qw qx qy qz
FALLEN_UP_Z = 0.5  # a torso whose up axis has a z component below this is fallen


class Replay:
    """A match log with its compiled model, ready to set any frame's poses.

    `data` holds the pose of the frame last given to `set_frame`; nothing here
    ever steps physics.
    """

    def __init__(self, log: MatchLog) -> None:
        if len(log) == 0:
            raise LogError("the match log has no frames")
        try:
            self.model = mujoco.MjModel.from_xml_string(log.xml)
        except ValueError as exc:
            raise LogError(f"the scene in the match log does not compile ({exc})") from None
        m = self.model
        if log.qpos.ndim != 2 or log.qpos.shape[1] != m.nq:
            raise LogError(f"the match log's qpos has shape {log.qpos.shape}, its scene needs (T, {m.nq})")
        if len(log.play_mode) and int(np.max(log.play_mode)) >= len(PLAY_MODES):
            raise LogError(f"the match log has an unknown play mode {int(np.max(log.play_mode))}")
        if log.targets.shape[1:] != (len(log.players), 2):
            raise LogError(f"the match log's targets have shape {log.targets.shape}, "
                           f"expected (T, {len(log.players)}, 2)")
        self.log = log
        self.data = mujoco.MjData(m)
        self.players = list(log.players)
        try:
            roots = [m.joint(f"{p}/root").id for p in self.players]
            self.torso_bodies = np.array([m.jnt_bodyid[j] for j in roots])
            self.ball_body = m.body("ball").id
            ball_qpos = int(m.jnt_qposadr[m.joint("ball_x").id])
        except KeyError as exc:
            raise LogError(f"the match log's scene lacks a body or joint its players need ({exc})") from None
        self.root_qpos = np.array([m.jnt_qposadr[j] for j in roots], dtype=np.int64)
        self.ball_qpos = ball_qpos
        self.sides = np.array([p[0] for p in self.players])
        self.unums = np.array([int(p[1:]) for p in self.players])
        self.frame = -1

    # ------------------------------------------------------------------ frames

    def __len__(self) -> int:
        return len(self.log)

    @property
    def duration(self) -> float:
        """Server time covered by the log (s)."""
        return float(self.log.time[-1] - self.log.time[0])

    def frame_at(self, seconds: float) -> int:
        """The first frame whose game time is at least `seconds` (the last frame if none)."""
        g = self.log.game_time
        i = int(np.searchsorted(g, seconds - 1e-6, side="left"))
        return min(i, len(g) - 1)

    def last_frame_at(self, seconds: float) -> int:
        """The last frame whose game time is at most `seconds` (the first frame if none)."""
        g = self.log.game_time
        i = int(np.searchsorted(g, seconds + 1e-6, side="right")) - 1
        return max(i, 0)

    def frames(self, start: float | None, end: float | None, fps: float) -> np.ndarray:
        """Frame indices that show game time `start`..`end` (s; None: the log's ends)
        played at `fps` output frames per second of server time."""
        i0 = 0 if start is None else self.frame_at(start)
        i1 = len(self) - 1 if end is None else self.last_frame_at(end)
        if i1 < i0:
            raise ValueError(f"no frames between game time {start} s and {end} s")
        t = self.log.time
        wanted = np.arange(t[i0], t[i1] + 1e-9, 1.0 / fps)
        idx = np.searchsorted(t, wanted - 1e-9, side="left")
        return np.clip(idx, i0, i1)

    def set_frame(self, i: int) -> mujoco.MjData:
        """Put every body at its pose in frame i (forward kinematics only) and return `data`."""
        d = self.data
        d.qpos[:] = self.log.qpos[i]
        mujoco.mj_kinematics(self.model, d)
        self.frame = i
        return d

    # ------------------------------------------------------------------- poses

    def _root(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n, 7) free-joint qpos of every player's torso."""
        cols = self.root_qpos[:, None] + np.arange(FREE_QPOS)
        return self.log.qpos[frames][..., cols]

    def positions(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n, 3) torso centers (m, field frame)."""
        return self._root(frames)[..., :3].astype(float)

    def headings(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n) yaw of each torso's x axis in the field frame (rad)."""
        q = self._root(frames)[..., 3:7].astype(float)
        w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
        return np.arctan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z))

    def up_z(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n) z component of each torso's up axis: 1 upright, 0 lying, -1 upside down."""
        q = self._root(frames)[..., 3:7].astype(float)
        x, y = q[..., 1], q[..., 2]
        n2 = np.sum(q * q, axis=-1)
        return 1 - 2 * (x * x + y * y) / np.where(n2 > 0, n2, 1.0)

    def fallen(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n) whether each player is down (torso up axis z below 0.5)."""
        return self.up_z(frames) < FALLEN_UP_Z

    def ball(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., 3) ball center (m, field frame)."""
        return self.log.qpos[frames][..., self.ball_qpos:self.ball_qpos + 3].astype(float)

    def targets(self, frames: np.ndarray | int) -> np.ndarray:
        """(..., n, 2) role targets (m, field frame), NaN where a player gave none."""
        return self.log.targets[frames].astype(float)

    def status(self, i: int) -> tuple[str, str, str]:
        """Overlay texts of frame i: (game clock, score, play mode)."""
        g = float(self.log.game_time[i])
        sl, sr = (int(v) for v in self.log.score[i])
        clock = f"{int(g // 60):02d}:{g % 60:04.1f}"
        return clock, f"L {sl} : {sr} R", self.log.mode_name(i)


def load(path: str | os.PathLike) -> Replay:
    """Read a match log and make it a `Replay` (LogError when it is corrupt or truncated)."""
    return Replay(read_log(path))

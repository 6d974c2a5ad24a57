"""Match logs: every body's pose at 50 Hz, compressed, for replay and rendering.

A log stores the scene's MJCF and, per cycle, the whole `qpos`, from which
forward kinematics gives every body's pose; plus play mode,
score, game time and optional per-player annotations (a role target (x, y) in
the field frame, NaN when absent). Logs are written atomically.

On disk `qpos` is quantized in steps of QPOS_STEP (1e-5 m or rad: 5 um at most)
and stored as int32 differences from the previous frame, which compress about
four times better than float32 (version 2).
"""

from __future__ import annotations

import json
import os
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from models.rules import PLAY_MODES
from server.files import atomic_path

LOG_VERSION = 2
QPOS_STEP = 1e-5  # m or rad per quantum of the stored qpos
REQUIRED = ("version", "xml", "players", "time", "game_time", "qpos_delta", "play_mode", "score",
            "targets", "events")


def encode_qpos(qpos: np.ndarray) -> np.ndarray:
    """(T, nq) positions -> int32 quantized frame-to-frame differences."""
    q = np.round(np.asarray(qpos, dtype=np.float64) / QPOS_STEP).astype(np.int64)
    delta = np.diff(q, axis=0, prepend=np.zeros((1, q.shape[1]), dtype=np.int64))
    return delta.astype(np.int32)


def decode_qpos(delta: np.ndarray) -> np.ndarray:
    """Inverse of `encode_qpos` (float32, within QPOS_STEP / 2 of the original)."""
    return (np.cumsum(delta.astype(np.int64), axis=0) * QPOS_STEP).astype(np.float32)


class LogError(ValueError):
    """A match log that cannot be read."""


@dataclass
class MatchLog:
    """The contents of a match log (arrays indexed by frame)."""

    xml: str
    players: list[str]  # "L1", "R7", ...
    time: np.ndarray  # (T,) server time, s
    game_time: np.ndarray  # (T,) s
    qpos: np.ndarray  # (T, nq) float32
    play_mode: np.ndarray  # (T,) index into models.rules.PLAY_MODES
    score: np.ndarray  # (T, 2) left, right
    targets: np.ndarray  # (T, n_players, 2) float32, NaN where absent
    events: list[dict]

    def __len__(self) -> int:
        return len(self.time)

    def mode_name(self, frame: int) -> str:
        return PLAY_MODES[int(self.play_mode[frame])].value


class LogRecorder:
    """Collects one frame a cycle."""

    def __init__(self, xml: str, players: list[str]) -> None:
        self.xml = xml
        self.players = players
        self._frames: dict[str, list] = {k: [] for k in
                                         ("time", "game_time", "qpos", "play_mode", "score", "targets")}

    def record(self, time: float, game_time: float, qpos: np.ndarray, mode_index: int,
               score: tuple[int, int], targets: np.ndarray) -> None:
        f = self._frames
        f["time"].append(time)
        f["game_time"].append(game_time)
        f["qpos"].append(qpos.astype(np.float32))
        f["play_mode"].append(mode_index)
        f["score"].append(score)
        f["targets"].append(targets.astype(np.float32))

    def finish(self, events: list[dict]) -> MatchLog:
        f = self._frames
        n = len(self.players)
        return MatchLog(
            xml=self.xml, players=list(self.players),
            time=np.asarray(f["time"], dtype=np.float64),
            game_time=np.asarray(f["game_time"], dtype=np.float32),
            qpos=np.asarray(f["qpos"], dtype=np.float32),
            play_mode=np.asarray(f["play_mode"], dtype=np.uint8),
            score=np.asarray(f["score"], dtype=np.uint8).reshape(-1, 2),
            targets=np.asarray(f["targets"], dtype=np.float32).reshape(-1, n, 2),
            events=events,
        )


def write_log(log: MatchLog, path: str | os.PathLike) -> None:
    """Write `log` to `path` (.npz, compressed) atomically."""
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        np.savez_compressed(
            fh, version=np.array(LOG_VERSION), xml=np.array(log.xml),
            players=np.array(log.players), time=log.time, game_time=log.game_time,
            qpos_delta=encode_qpos(log.qpos), play_mode=log.play_mode, score=log.score,
            targets=log.targets, events=np.array(json.dumps(log.events)))


def read_log(path: str | os.PathLike) -> MatchLog:
    """Read a match log, or raise LogError saying what is wrong with it."""
    path = Path(path)
    if not path.exists():
        raise LogError(f"{path}: no such match log")
    try:
        with np.load(path, allow_pickle=False) as z:
            missing = [k for k in REQUIRED if k not in z.files]
            if missing:
                raise LogError(f"{path}: not a match log (missing {', '.join(missing)})")
            arrays = {k: z[k] for k in REQUIRED}
    except LogError:
        raise
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        raise LogError(f"{path}: corrupt or truncated match log ({exc})") from None
    if int(arrays["version"]) != LOG_VERSION:
        raise LogError(f"{path}: log version {int(arrays['version'])}, expected {LOG_VERSION}")
    t = len(arrays["time"])
    for k in ("game_time", "qpos_delta", "play_mode", "score", "targets"):
        if len(arrays[k]) != t:
            raise LogError(f"{path}: {k} has {len(arrays[k])} frames, time has {t}")
    return MatchLog(
        xml=str(arrays["xml"]), players=[str(p) for p in arrays["players"]],
        time=arrays["time"], game_time=arrays["game_time"], qpos=decode_qpos(arrays["qpos_delta"]),
        play_mode=arrays["play_mode"], score=arrays["score"], targets=arrays["targets"],
        events=json.loads(str(arrays["events"])),
    )

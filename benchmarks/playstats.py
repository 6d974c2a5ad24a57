"""Where and how the ball is played: figures of match logs (`soccer match --log`).

Over the frames in play (PlayOn), ground truth from the log (field frame, m):

* contested: a player of each team within CONTESTED m of the ball; free: no player
  of either team that near;
* wide: the ball within WIDE m of a touchline; central: within CENTRAL m of the
  field's long axis;
* near a goal: the ball within NEAR_GOAL m of either goal line;
* still: the ball slower than STILL m/s (from frame to frame);
* crowd: players of each team within CROWD m of the ball, the mean over the two teams;
* contested spells: runs of contested frames, their median length (s).

Each log gives one line; with several logs a last line gives each figure's mean and
standard error over them (a match is one sample: read a difference between two teams'
logs against those errors).

What it showed (seed 1, one match each, December 6, 2026): villa against villa, the ball
spent 20% of the play within 2 m of a touchline and 4% within 3 m of a goal line, contested
13%; villa:Straight against itself (no dribble cone) 2.6%, 10% and 19%; villa:ConeIn against
itself (the cone only toward the middle) 2.9%, 9% and 16%. All three ended 0:0, and against
villa both variants lost ground (territory -1.5 m a game, benchmarks/results): the cone's
pushes toward the touchline win the race for the ball.

    python -m benchmarks.playstats LOG.npz [LOG.npz ...]
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from benchmarks.machine import machine
from models import field as fld
from models.rules import CYCLE, PLAY_MODES, PlayMode
from replay.poses import Replay
from server.log import LogError, read_log

CONTESTED = 0.6  # m
WIDE = 2.0  # m from a touchline
CENTRAL = 2.0  # m from the long axis
NEAR_GOAL = 3.0  # m from a goal line
STILL = 0.05  # m/s
CROWD = 2.0  # m

FIGURES = ("contested", "free", "wide", "central", "near_goal", "still", "crowd", "spell_s")


def play_stats(r: Replay) -> dict[str, float]:
    """The figures of one match log (shares of the frames in play; crowd in players,
    spell_s in s)."""
    play_on = PLAY_MODES.index(PlayMode.PLAY_ON)
    frames = np.flatnonzero(r.log.play_mode == play_on)
    if len(frames) < 2:
        raise LogError("the match log has no play (no PlayOn frames)")
    ball = r.ball(frames)[:, :2]
    dist = np.linalg.norm(r.positions(frames)[..., :2] - ball[:, None, :], axis=-1)
    left = r.sides == "L"
    near_l, near_r = dist[:, left].min(axis=1), dist[:, ~left].min(axis=1)
    contested = (near_l < CONTESTED) & (near_r < CONTESTED)
    step = np.r_[np.nan, np.linalg.norm(np.diff(ball, axis=0), axis=1)]
    speed = np.where(np.r_[False, np.diff(frames) == 1], step / CYCLE, np.nan)  # m/s, within a spell of play
    edges = np.diff(np.r_[0, contested.astype(int), 0])
    spells = (np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)) * CYCLE
    return {
        "contested": float(contested.mean()),
        "free": float(((near_l >= CONTESTED) & (near_r >= CONTESTED)).mean()),
        "wide": float((np.abs(ball[:, 1]) > fld.HALF_WIDTH - WIDE).mean()),
        "central": float((np.abs(ball[:, 1]) < CENTRAL).mean()),
        "near_goal": float((np.abs(ball[:, 0]) > fld.HALF_LENGTH - NEAR_GOAL).mean()),
        "still": float(np.mean(speed[np.isfinite(speed)] < STILL)),
        "crowd": float((dist < CROWD).sum(axis=1).mean() / 2),
        "spell_s": float(np.median(spells)) if len(spells) else 0.0,
    }


def summary(rows: list[dict[str, float]]) -> dict[str, dict[str, float]]:
    """Mean and standard error (over logs) of each figure."""
    out = {}
    for k in FIGURES:
        v = np.array([r[k] for r in rows], dtype=float)
        se = float(v.std(ddof=1) / np.sqrt(len(v))) if len(v) > 1 else float("nan")
        out[k] = {"mean": round(float(v.mean()), 3), "se": round(se, 3)}
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("logs", nargs="+", help="match logs (.npz) written by soccer match --log")
    args = ap.parse_args(argv)
    rows = []
    for path in args.logs:
        try:
            r = Replay(read_log(path))
            row = play_stats(r)
        except (OSError, LogError) as e:
            print(f"{path}: {e}", file=sys.stderr)
            return 2
        rows.append(row)
        figures = {k: round(v, 3) for k, v in row.items()}
        print(json.dumps({"log": path, "players": len(r.players), **figures}))
    if len(rows) > 1:
        print(json.dumps({"logs": len(rows), "mean_se": summary(rows), "machine": machine()}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

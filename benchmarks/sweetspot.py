"""Where a keyframe kick wants the ball: standing kicks over a grid of ball offsets.

A keyframe kick plays the same joint keyframes wherever the ball lies, so its
parameter set names the ball's offset from the robot (`ball_x`, `ball_y`) that
the approach must bring it to, within the set's tolerance box. This benchmark
measures how the kick fares around that offset: for each robot type and
keyframe set, `--tries` standing kicks per foot (`optimization.kick.kick_trial`,
the robot placed within `SPREAD`, 2 mm and 0.5 deg sd) with the ball moved by (dx, dy)
on a square grid of `--step` mm out to `--half` mm. dy is in the left foot's
frame (+ is farther out for the left foot); right-foot kicks are mirrored into
it, so both feet share one grid, as they share one parameter set.

Each cell: success rate (the ball at least 1 m along the kick's direction, no
fall), mean distance along it (m) and falls. Where the ball really lies when a
walking approach starts the kick scatters about the set's offset: measured on
walking keyframe kicks of types 1, 2 and 4 (200 kicks), the true offset less the
set's was +2 to +7 mm in x (sd 5.5-6.7) and 0 in y (sd 6.5-8.4): the approach
stops on its belief, which sees the ball a few mm near. The "walking rate" of a
center is the grid's success rate weighted by that scatter (`--bias`, `--sd`,
mm: a Gaussian in x and y about the center plus the bias, over the cells). The
row gives the walking rate at the shipped offset and at the best center (on a
5 mm lattice, its scatter within 1.5 sd of the grid's edge; ties: the mean
distance, then the nearer center; the shipped offset unless the best gains at
least `MIN_GAIN`, 0.03: a cell's rate is a mean of 16 kicks), and that center as
the file's `ball_x`/`ball_y` (mm). Ground truth only (a benchmark, not the agent).

Prints the machine, then one JSON line per type and set (`--table` also prints
each grid as text to stderr).

    python -m benchmarks.sweetspot [--types 3] [--sets kick_3m kick_4m] [--tries 8] [--step 10]
                                   [--half 30] [--bias 5 0] [--sd 6 7.5] [--seed 0] [--workers 2]
                                   [--table]
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
import json
import math
import sys
from multiprocessing import Pool

import numpy as np
from tqdm import tqdm

from benchmarks.machine import machine
from optimization.executor import one_thread
from optimization.kick import kick_trial
from skills.kicks.keyframe import keyframe_kicks

SPREAD = (0.002, 0.5)  # m, deg: placement noise (the grid's cells are 10 mm apart)
BIAS = (0.005, 0.0)  # m: true ball offset less the set's when a walking approach kicks (mean) ...
SD = (0.006, 0.0075)  # m: ... and its standard deviations (x, y; see the module docstring)
MIN_GAIN = 0.03  # least gain in walking rate for which a center replaces the shipped offset


def keyframe_sets(robot_type: int) -> list[str]:
    """The type's keyframe kick sets (``kick``, ``kick_3m`` ...), from its shipped kicks."""
    return sorted({name.rsplit("_", 1)[0] for name in keyframe_kicks(robot_type)})


def offset_trial(job: tuple[int, str, str, float, float, int, int]) -> dict:
    """One standing kick of set `set_name` with `foot` ("left"/"right") and the ball moved
    by (dx, dy) m (dy in the left foot's frame); its outcome."""
    robot_type, set_name, foot, dx, dy, seed, i = job
    kick = copy.copy(keyframe_kicks(robot_type)[f"{set_name}_{foot}"])
    bx, by = kick.spec.ball
    sign = 1.0 if foot == "left" else -1.0
    kick.spec = dataclasses.replace(kick.spec, ball=(bx + dx, by + sign * dy))
    rng = np.random.default_rng([seed, robot_type, i, round(dx * 1e4) + 10_000, round(dy * 1e4) + 10_000,
                                 sum(map(ord, set_name + foot))])
    r = kick_trial(robot_type, kick, "standing", rng, seed * 1000 + i, spread=SPREAD)
    return {"dx": dx, "dy": dy, "ok": bool(r["success"]), "toward": r["toward"], "fell": bool(r["fell"])}


def walking_rate(grid: np.ndarray, offsets: np.ndarray, center: tuple[float, float],
                 bias: tuple[float, float], sd: tuple[float, float]) -> float:
    """Mean of `grid` (a figure per cell, rows dx, columns dy, at `offsets` m) weighted by
    a Gaussian about `center` + `bias` with standard deviations `sd` (m, x and y)."""
    wx = np.exp(-0.5 * ((offsets - center[0] - bias[0]) / sd[0]) ** 2)
    wy = np.exp(-0.5 * ((offsets - center[1] - bias[1]) / sd[1]) ** 2)
    w = np.outer(wx, wy)
    return float((w * grid).sum() / w.sum())


Pair = tuple[float, float]


def best_center(ok: np.ndarray, toward: np.ndarray, offsets: np.ndarray, bias: Pair = BIAS,
                sd: Pair = SD, min_gain: float = MIN_GAIN) -> tuple[Pair, Pair, Pair]:
    """The center (m, from the shipped offset) of the best walking rate over grids `ok`
    (success rates) and `toward` (mean distances, m): on a 5 mm lattice, its scatter 1.5 sd
    inside the grid; ties go to the longer mean distance, then the nearer center. The
    shipped offset stays unless the best beats its rate by `min_gain` (the grid is
    noisy). Also the (rate, distance) at the shipped offset and at the center."""
    half = float(np.max(np.abs(offsets)))
    lattice = np.round(np.arange(-half, half + 1e-9, 0.005), 6)
    cx = [float(c) for c in lattice if abs(c + bias[0]) + 1.5 * sd[0] <= half + 1e-9] or [0.0]
    cy = [float(c) for c in lattice if abs(c + bias[1]) + 1.5 * sd[1] <= half + 1e-9] or [0.0]

    def score(c: tuple[float, float]) -> tuple[float, float]:
        return walking_rate(ok, offsets, c, bias, sd), walking_rate(toward, offsets, c, bias, sd)

    scores = {(x, y): score((x, y)) for x in cx for y in cy}
    best = max(scores, key=lambda c: (round(scores[c][0], 3), scores[c][1], -abs(c[0]) - abs(c[1])))
    shipped = score((0.0, 0.0))
    if scores[best][0] < shipped[0] + min_gain:
        return (0.0, 0.0), shipped, shipped
    return best, shipped, scores[best]


def sweep(robot_type: int, set_name: str, tries: int, step: float, half: float, seed: int,
          pool: Pool | None = None, progress: tqdm | None = None,
          bias: Pair = BIAS, sd: Pair = SD) -> dict:
    """The grid of one type and set (one JSON row; offsets in m, figures per cell), with the
    walking rates of `walking_rate` (bias, sd: m)."""
    offsets = np.round(np.arange(-half, half + 1e-9, step), 6)
    jobs = [(robot_type, set_name, foot, float(dx), float(dy), seed, i)
            for dx in offsets for dy in offsets for foot in ("left", "right") for i in range(tries)]
    results = []
    for r in (pool.imap(offset_trial, jobs, chunksize=2) if pool else map(offset_trial, jobs)):
        results.append(r)
        if progress is not None:
            progress.update()
    n = len(offsets)
    ok, toward, falls = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n), dtype=int)
    index = {float(v): k for k, v in enumerate(offsets)}
    for r in results:
        a, b = index[r["dx"]], index[r["dy"]]
        ok[a, b] += r["ok"] / (2 * tries)
        toward[a, b] += r["toward"] / (2 * tries)
        falls[a, b] += r["fell"]
    spec = keyframe_kicks(robot_type)[f"{set_name}_left"].spec
    best, shipped, at_best = best_center(ok, toward, offsets, bias, sd)
    return {
        "robot_type": robot_type, "set": set_name, "tries_per_cell": 2 * tries,
        "offsets_mm": [round(1000 * v, 1) for v in offsets],
        "success": np.round(ok, 3).tolist(), "toward_m": np.round(toward, 2).tolist(),
        "falls": falls.tolist(),
        "bias_mm": [round(1000 * v, 1) for v in bias], "sd_mm": [round(1000 * v, 1) for v in sd],
        "ball_mm": [round(1000 * v, 1) for v in spec.ball],
        "walking_rate_shipped": round(shipped[0], 3), "walking_toward_shipped_m": round(shipped[1], 2),
        "walking_rate_best": round(at_best[0], 3), "walking_toward_best_m": round(at_best[1], 2),
        "best_ball_mm": [round(1000 * (spec.ball[0] + best[0]), 1),
                         round(1000 * (spec.ball[1] + best[1]), 1)],
    }


def table(row: dict) -> str:
    """A row's success grid as text (rows dx, columns dy, mm)."""
    offs = row["offsets_mm"]
    lines = [f"type {row['robot_type']} {row['set']}: success (falls) by ball offset; rows dx, "
             f"columns dy (mm, + = out for the left foot); shipped ball {row['ball_mm']} mm, "
             f"walking rate {row['walking_rate_shipped']} -> best {row['walking_rate_best']} at "
             f"{row['best_ball_mm']}",
             "        " + "".join(f"{v:>10.0f}" for v in offs)]
    for a, dx in enumerate(offs):
        cells = "".join(f"{row['success'][a][b]:>6.2f} ({row['falls'][a][b]})" for b in range(len(offs)))
        lines.append(f"{dx:>8.0f}{cells}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", type=int, nargs="+", default=[0], choices=range(5), metavar="T")
    ap.add_argument("--sets", nargs="+", default=None, help="keyframe sets (default: every one of the type)")
    ap.add_argument("--tries", type=int, default=8, help="kicks per cell and foot")
    ap.add_argument("--step", type=float, default=10.0, help="grid step (mm)")
    ap.add_argument("--half", type=float, default=30.0, help="grid half-width (mm)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--bias", type=float, nargs=2, default=[1000 * v for v in BIAS], metavar=("X", "Y"),
                    help="mm: mean of the true ball offset less the set's in walking kicks")
    ap.add_argument("--sd", type=float, nargs=2, default=[1000 * v for v in SD], metavar=("X", "Y"),
                    help="mm: its standard deviations")
    ap.add_argument("--table", action="store_true", help="also print each grid as text to stderr")
    args = ap.parse_args(argv)
    if args.tries < 1:
        ap.error(f"--tries must be at least 1, not {args.tries}")
    if args.step <= 0 or args.half < 0 or not math.isclose(args.half / args.step,
                                                            round(args.half / args.step)):
        ap.error(f"--half ({args.half}) must be a whole number of positive --step ({args.step})")
    if min(args.sd) <= 0:
        ap.error(f"--sd must be positive, not {args.sd}")
    if args.workers < 1:
        ap.error(f"--workers must be at least 1, not {args.workers}")
    plan = []
    for t in args.types:
        known = keyframe_sets(t)
        for s in args.sets or known:
            if s not in known:
                ap.error(f"unknown keyframe set {s!r} for type {t}; one of {', '.join(known)}")
            plan.append((t, s))
    print(json.dumps({"machine": machine()}), flush=True)
    cells = (2 * round(args.half / args.step) + 1) ** 2
    total = len(plan) * cells * 2 * args.tries
    pool = Pool(args.workers, initializer=one_thread) if args.workers > 1 else None
    try:
        with tqdm(total=total, unit="kick", file=sys.stderr, disable=None) as bar:
            for t, s in plan:
                bias = (args.bias[0] / 1000, args.bias[1] / 1000)
                sd = (args.sd[0] / 1000, args.sd[1] / 1000)
                row = sweep(t, s, args.tries, args.step / 1000, args.half / 1000, args.seed, pool, bar,
                            bias, sd)
                print(json.dumps(row), flush=True)
                if args.table:
                    bar.write(table(row), file=sys.stderr)
    finally:
        if pool is not None:
            pool.close()
            pool.join()
    return 0


if __name__ == "__main__":
    sys.exit(main())

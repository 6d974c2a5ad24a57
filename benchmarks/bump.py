"""Bumps: two robots walk into each other at full go-to-target speed; who falls.

Most of a match's falls come from contact (`benchmarks.falls`): in villa-villa duels
the fallen player's torso leaned away from the opponent, backward when they met head
on and sideways when they walked side by side after a rolling ball. This benchmark
stages both meetings with the walk alone (no agent, no vision), real contact only:

* head-on: A faces B 1.6-3 m apart, offset sideways by up to 0.25 m; both walk
  straight ahead;
* side by side: A and B start 0.5-0.9 m apart abreast (either ahead by up to 0.2 m),
  each turned 15-35 deg toward the other's path, and walk straight ahead.

Each seeded trial draws a robot type from `--types` (both robots the same) and one of
the two meetings (even seeds head-on), stands both 0.5 s, then walks them for
`--seconds`. A robot whose torso's up axis drops below 0.5 has fallen. A walks with the
shipped walk sets and then `--params`, B with the shipped sets and then `--against`;
the line gives each side's falls a trial and the paired difference A - B with its
standard error (over trials), by meeting and overall. A against A comes out near 0.

What it showed (600 trials, seed 0, December 6, 2026): the shipped walk against itself,
A 0.655 and B 0.633 falls a trial (A - B +0.022 +- 0.030; head-on 0.78, side by side
0.52): two robots that meet walking straight on mostly fall. With balance steps
(`skills.walk`: balance_step_x 1.0, balance_step_y 0.5 m/rad beyond 0.08 rad, fade 1) A
fell 0.595 times a trial against B's 0.667, -0.072 +- 0.029 (head-on -0.047 +- 0.033,
side by side -0.097 +- 0.047); with the landed foot's offset dropped within a cycle
(balance_fade 0.05) -0.023 +- 0.029, and gains 1.0/1.0 beyond 0.02 rad with that fade
-0.045 +- 0.028. Larger gains and smaller deadbands made the walk itself fall
(`benchmarks.walk`'s course: 1.5/0.6 beyond 0.03 rad, type 0 fell in 4 of 10 runs).
Tried by hand, not kept: A stopping its forward push while its torso leaned back beyond
0.04 or 0.06 rad fell as often head-on (0.72 and 0.75 against B's 0.73 and 0.76).

Single walk parameters against the shipped walk (400 trials, seed 0, `--workers 1`, every
type; the shipped value in brackets): softer joints fell less, joint_kp 11 -0.198 +- 0.036
(A 0.51 against B 0.71; head-on -0.225), 8 -0.165, 15 -0.117, and stiffer more, 30 +0.072
+- 0.033 [21.2; type 3 18]; a lower step fell less, step_height 30 mm -0.150 +- 0.037, 25
-0.135, 20 -0.142, and 55 +0.037 [40; type 3 52.6]; arms in (arm_roll 0) -0.068 +- 0.035,
out (0.4) +0.018 [0.15]; walk_height 175 mm -0.028 [185.5; types 1 and 3 216 and 233].
The two did not add up: joint_kp 11 with step_height 30 -0.175, 14 with 30 -0.138. In
games the bumps did not carry over: villa:Soft (joint_kp 11) fell 25.9 times a game
against villa's 21.4 and lost -0.21 +- 0.10 over 24 full games, and villa:LowStep
(step_height 30) fell 19.9 against 22.8 and won nothing, +0.03 +- 0.05 over 80
(`benchmarks/results/soft-vs-villa/`, `lowstep-vs-villa/`).

    python -m benchmarks.bump [--params FILE ...] [--against FILE ...] [--trials 200]
                              [--seed 0] [--types 0,1,2,3,4] [--seconds 7] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from benchmarks.args import robot_types
from benchmarks.machine import machine
from models.messages import Action
from models.rules import CYCLE
from models.scene import Lineup
from optimization.robot import place_standing, walk_motion
from server.trainer import Trainer
from skills.params import ParamError
from skills.walk import default_param_files, load_walk_sets

STAND = 0.5  # s both robots stand before walking
MEETINGS = ("head-on", "side by side")


def starts(meeting: str, rng: np.random.Generator) -> list[tuple[float, float, float]]:
    """A's and B's start poses (x, y, heading; m, rad, world frame) for a meeting."""
    if meeting == "head-on":
        gap, offset = rng.uniform(0.8, 1.5), rng.uniform(-0.25, 0.25)
        return [(-gap, 0.0, 0.0), (gap, offset, math.pi)]
    turn, gap, lead = math.radians(rng.uniform(15.0, 35.0)), rng.uniform(0.5, 0.9), rng.uniform(-0.2, 0.2)
    poses = [(-1.0, -gap / 2, turn), (-1.0 + lead, gap / 2, -turn)]
    if rng.random() < 0.5:  # A on the left as often as on the right
        poses = [(x, -y, -h) for x, y, h in poses]
    return poses


def bump(seed: int, params: list[str], against: list[str], types: list[int], seconds: float) -> dict:
    """One trial: {"seed", "type", "meeting", "fell": [A, B], "time": [s of walking
    before each fell, or None], "closest": the torsos' least distance (m)}."""
    rng = np.random.default_rng(seed)
    t = int(types[int(rng.integers(len(types)))])
    meeting = MEETINGS[seed % 2]
    tr = Trainer(Lineup((t,), (t,)), seed=seed, vision=False)
    tr.world.place_ball((10.0, 8.0))  # out of the way
    motions = [walk_motion(t, files) for files in (params, against)]
    for i, (x, y, h) in enumerate(starts(meeting, rng)):
        place_standing(tr, i, motions[i], x, y, h, rng)
    fell: list[float | None] = [None, None]
    closest = math.inf
    stand = round(STAND / CYCLE)
    for k in range(stand + round(seconds / CYCLE)):
        percepts = tr.percepts()
        go = 1.0 if k >= stand else 0.0
        tr.step({i: Action(motions[i].walk_step(percepts[i], go, 0.0, 0.0))
                 for i in range(2) if fell[i] is None})
        up, pos = tr.world.torso_up(), tr.world.torso_positions()
        closest = min(closest, float(np.hypot(*(pos[0, :2] - pos[1, :2]))))
        for i in range(2):
            if fell[i] is None and up[i] < 0.5:
                fell[i] = round((k + 1 - stand) * CYCLE, 2)
    return {"seed": seed, "type": t, "meeting": meeting, "fell": [f is not None for f in fell], "time": fell,
            "closest": round(closest, 3)}


def summary(trials: list[dict]) -> dict:
    """Falls a trial for A and B and the paired difference A - B with its standard error."""
    def line(rows: list[dict]) -> dict:
        a = np.array([r["fell"][0] for r in rows], dtype=float)
        b = np.array([r["fell"][1] for r in rows], dtype=float)
        d = a - b
        se = float(d.std(ddof=1) / math.sqrt(len(d))) if len(d) > 1 else float("nan")
        return {"trials": len(rows), "falls_a": round(float(a.mean()), 3),
                "falls_b": round(float(b.mean()), 3), "a_minus_b": round(float(d.mean()), 3),
                "se": round(se, 3)}
    out = {"all": line(trials)}
    for m in MEETINGS:
        rows = [r for r in trials if r["meeting"] == m]
        if rows:
            out[m] = line(rows)
    return out


def _check(ap: argparse.ArgumentParser, option: str, files: list[str], types: list[int]) -> None:
    """A usage error naming the file, line and value when a walk file does not load."""
    for t in types:
        try:
            load_walk_sets([*default_param_files(t), *files])
        except (ParamError, OSError) as e:
            ap.error(f"{option}: {e}")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for option, side in (("--params", "A"), ("--against", "B")):
        ap.add_argument(option, nargs="+", default=[], metavar="FILE",
                        help=f"{side}'s walk files after the shipped ones")
    ap.add_argument("--trials", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--types", default="0,1,2,3,4")
    ap.add_argument("--seconds", type=float, default=7.0, help="s of walking after the 0.5 s stand")
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    types = robot_types(ap, args.types)
    if args.trials < 2:
        ap.error(f"--trials: at least 2, got {args.trials}")
    if args.seconds <= 0 or args.workers < 1:
        ap.error("--seconds must be positive and --workers at least 1")
    _check(ap, "--params", args.params, types)
    _check(ap, "--against", args.against, types)
    seeds = range(args.seed, args.seed + args.trials)
    n = len(seeds)
    jobs = (seeds, [args.params] * n, [args.against] * n, [types] * n, [args.seconds] * n)
    if args.workers == 1:
        trials = list(map(bump, *jobs))
    else:
        with ProcessPoolExecutor(args.workers) as pool:
            trials = list(pool.map(bump, *jobs, chunksize=4))
    print(json.dumps({"params": args.params, "against": args.against, "seed": args.seed, **summary(trials),
                      "machine": machine()}))


if __name__ == "__main__":
    main(sys.argv[1:])

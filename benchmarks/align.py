"""Precision of the stance moves (skills/align.py): one JSON line per robot type.

Each try: a robot stands in the walk's stand, `Align` moves it by a seeded
random (dx, dy, dturn) within +-`--move` m and +-`--turn` deg, then it stands
0.5 s again; ground truth compares the torso's displacement (in the start's
robot frame) with the request. Figures: mean and largest absolute error per
axis (mm, mm, deg) over the tries that did not fall, falls (during the move or the
stand after it; tries whose walk fell before the move are counted apart), and the
move's time.

How the robot comes to stand (`--start`): "walk" (the default, as in the ball
approach) walks ahead 1-2 s with the approach-to-kick set, stops at a change of
support and stands 0.5-0.8 s, by when the stand rocks on its feet at about
6.5 Hz; "stand" only stands 0.5 s from a still start, before the rocking sets in.

    python -m benchmarks.align [--types 0 1 2 3 4] [--tries 8] [--start walk|stand] [--move 0.05]
                               [--turn 18] [--seed 7]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from benchmarks.machine import machine
from benchmarks.walk import new_robot
from models.messages import Action
from server.trainer import Trainer
from skills.align import Align
from skills.motion import Motion

START_SET = "approach_to_kick"  # the walk set of the "walk" start


def come_to_stand(tr: Trainer, mo: Motion, start: str, rng: np.random.Generator) -> bool:
    """Bring a new robot to a stand as `start` says ("walk" or "stand"); False if it fell."""
    w = tr.world
    if start == "walk":
        walk = mo.walk
        until = w.time + rng.uniform(1.0, 2.0)
        while w.time < until or not walk.step_begins():
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.4, 0.0, 0.0, START_SET))})
        walk.reset()  # stop at the change of support, as the approach does
        until = w.time + rng.uniform(0.5, 0.8)
        while w.time < until or not (mo.last is not None and mo.last.standing):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0, START_SET))})
    else:
        for _ in range(25):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
    return w.torso_up()[0] > 0.5


def align_errors(robot_type: int, tries: int, move: float, turn: float, seed: int,
                 start: str = "walk") -> dict:
    rng = np.random.default_rng([seed, robot_type])
    align = Align(robot_type)
    errors, falls, start_falls = [], 0, 0
    for _ in range(tries):
        request = (rng.uniform(-move, move), rng.uniform(-move, move), math.radians(rng.uniform(-turn, turn)))
        tr, mo = new_robot(robot_type)
        w = tr.world
        if not come_to_stand(tr, mo, start, rng):  # fell walking: not the align's fall
            start_falls += 1
            continue
        x0, y0, h0 = w.player_pose(0)
        mo.walk.reset()
        align.reset(request)
        fell = False
        while not align.done:
            pc = tr.percepts()[0]
            tr.step({0: Action(mo.command(align.step(pc), pc))})
            fell = fell or bool(w.torso_up()[0] < 0.5)
        for _ in range(25):  # stand 0.5 s: a fall there counts too
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
            fell = fell or bool(w.torso_up()[0] < 0.5)
        falls += fell
        if fell:
            continue
        x1, y1, h1 = w.player_pose(0)
        c, s = math.cos(h0), math.sin(h0)
        dx, dy = c * (x1 - x0) + s * (y1 - y0), -s * (x1 - x0) + c * (y1 - y0)
        dh = math.remainder(h1 - h0, 2.0 * math.pi)
        errors.append((1e3 * abs(dx - request[0]), 1e3 * abs(dy - request[1]),
                       math.degrees(abs(dh - request[2]))))
    e = np.array(errors) if errors else np.full((1, 3), np.nan)
    return {"benchmark": "align", "robot_type": robot_type, "start": start, "tries": tries, "falls": falls,
            "fell_before": start_falls,
            "error_mean_mm_mm_deg": [round(float(v), 1) for v in e.mean(axis=0)],
            "error_max_mm_mm_deg": [round(float(v), 1) for v in e.max(axis=0)],
            "seconds_per_move": round(align.params.duration, 2)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", type=int, nargs="+", default=[0, 1, 2, 3, 4], choices=range(5), metavar="T")
    ap.add_argument("--tries", type=int, default=8)
    ap.add_argument("--move", type=float, default=0.05, help="largest request along x and y (m)")
    ap.add_argument("--turn", type=float, default=18.0, help="largest turn request (deg)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--start", choices=("walk", "stand"), default="walk",
                    help="stand after walking (as in the ball approach) or from a still start")
    args = ap.parse_args()
    if args.tries < 1:
        ap.error(f"--tries must be at least 1, not {args.tries}")
    print(json.dumps({"machine": machine()}), flush=True)
    for t in args.types:
        row = align_errors(t, args.tries, args.move, args.turn, args.seed, args.start)
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()

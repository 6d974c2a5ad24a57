"""Precision of the stance moves (skills/align.py): one JSON line per robot type.

Each try: a robot stands 0.5 s in the walk's stand, `Align` moves it by a seeded
random (dx, dy, dturn) within +-`--move` m and +-`--turn` deg, then it stands
0.5 s again; ground truth compares the torso's displacement (in the start's
robot frame) with the request. Figures: mean and largest absolute error per
axis (mm, mm, deg) over the tries that did not fall, falls, and the move's time.

    python -m benchmarks.align [--types 0 1 2 3 4] [--tries 8] [--move 0.05] [--turn 18] [--seed 7]
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

from benchmarks.machine import machine
from benchmarks.walk import new_robot
from models.messages import Action
from skills.align import Align


def align_errors(robot_type: int, tries: int, move: float, turn: float, seed: int) -> dict:
    rng = np.random.default_rng([seed, robot_type])
    align = Align(robot_type)
    errors, falls = [], 0
    for _ in range(tries):
        request = (rng.uniform(-move, move), rng.uniform(-move, move), math.radians(rng.uniform(-turn, turn)))
        tr, mo = new_robot(robot_type)
        w = tr.world
        for _ in range(25):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        x0, y0, h0 = w.player_pose(0)
        mo.walk.reset()
        align.reset(request)
        fell = False
        while not align.done:
            pc = tr.percepts()[0]
            tr.step({0: Action(mo.command(align.step(pc), pc))})
            fell = fell or bool(w.torso_up()[0] < 0.5)
        for _ in range(25):
            tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
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
    return {"benchmark": "align", "robot_type": robot_type, "tries": tries, "falls": falls,
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
    args = ap.parse_args()
    if args.tries < 1:
        ap.error(f"--tries must be at least 1, not {args.tries}")
    print(json.dumps({"machine": machine()}), flush=True)
    for t in args.types:
        print(json.dumps(align_errors(t, args.tries, args.move, args.turn, args.seed)), flush=True)


if __name__ == "__main__":
    main()

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

from benchmarks.machine import machine
from optimization.trials import align_errors


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

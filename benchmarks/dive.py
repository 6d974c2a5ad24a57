"""Dive benchmark: per robot type and dive, time to the ground, lateral reach and the getup.

A robot of each type stands still (the walk's stand, seeded heading and joint
noise), then plays each dive of `skills.dive.DIVES` from its percepts until the
dive reports done (standing again). Ground truth measures: the time until the
torso is below half the standing height, the farthest any collision geom gets
to the dive's side (for the central split, the total spread), the torso's
sideways travel, whether the robot stands again within 10 s and how long the
getup took. One JSON line per type and dive, after the machine.

    python -m benchmarks.dive [--types 0,1,2,3,4] [--tries 10]
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from benchmarks.machine import machine
from optimization.trials import run_dive
from skills.dive import DIVES


def dive_stats(robot_type: int, name: str, tries: int) -> dict:
    """Aggregate of `tries` seeded dives (one JSON row)."""
    rs = [run_dive(robot_type, name, s) for s in range(tries)]
    side = -1 if name.endswith("RIGHT") else 1
    g = [r.ground for r in rs if r.ground is not None]
    ok = [r for r in rs if r.upright_at_end]
    reach = ([r.reach_left - r.reach_right for r in rs] if name == "DIVE_CENTER"
             else [r.reach_left if side > 0 else -r.reach_right for r in rs])
    return {
        "type": robot_type, "dive": name, "tries": tries, "down": len(g),
        "ground_s": round(float(np.mean(g)), 2) if g else None,
        "ground_max_s": round(float(np.max(g)), 2) if g else None,
        "reach_m": round(float(np.mean(reach)), 2), "reach_min_m": round(float(np.min(reach)), 2),
        "torso_lateral_m": round(float(np.mean([side * r.torso_lateral for r in rs])), 2),
        "up_again": len(ok),
        "getup_s": (round(float(np.mean([r.times["settle"] - r.times["relax"] for r in ok])), 2)
                    if ok else None),
        "done_s": round(float(np.mean([r.up_after for r in ok])), 2) if ok else None,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0,1,2,3,4")
    ap.add_argument("--tries", type=int, default=10)
    args = ap.parse_args(argv)
    try:
        types = [int(v) for v in args.types.split(",")]
    except ValueError:
        ap.error(f"--types must be comma-separated robot types 0-4, not {args.types!r}")
    if any(t not in range(5) for t in types) or args.tries < 1:
        ap.error("--types must be within 0-4 and --tries at least 1")
    print(json.dumps({"machine": machine()}), flush=True)
    for t in types:
        for name in DIVES:
            print(json.dumps(dive_stats(t, name, args.tries)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

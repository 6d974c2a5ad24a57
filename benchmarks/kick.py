"""Kick benchmark: success, distance, direction error and time to contact, per kick and type.

For each kick and robot type, `--tries` kicks in each mode, seeded, as
`optimization.kick.kick_trial` runs them: "standing" (the robot stands at the
kick's pose behind the ball and kicks along its own direction) and "walking"
(it starts 1 to 2 m from the ball at a random bearing and approaches to kick
toward a target in a random direction), driven by `agent.kicker.Kicker` from
percepts alone. Success: the ball moved at least 1 m toward the target and the
robot did not fall. Distance: the ball's travel to its stop; direction error:
its travel direction against the target's, over the tries in which the kick
was played (a ball the approach ran into and pushed off is not the kick's
direction: those tries count in `approach_bumps`, the ball moved more than
`BUMP` before any kick began): its mean absolute value, and its signed mean
("bias", + to the left of the target) and standard deviation, which tell a
kick that aims off from one that scatters; time to contact: from the start
of the trial to the kicking robot's first touch. Each success rate comes with
its 95% interval (`benchmarks.stats.rate_ci`), and each row counts its tries by
outcome: success, timeout (no kick within the approach's 25 s), approach_fall,
kick_fall (in or after the kick) and short.

Prints the machine, then one JSON line per kick, robot type and mode.

    python -m benchmarks.kick [--types 0] [--kicks kick_left ik_forward_left] [--tries 20]
                              [--modes standing walking] [--seed 0]
                              [--params FILE ...] [--approach-params FILE ...]
                              [--walk-params FILE ...]

`--params` loads keyframe kick parameter files after the shipped ones (e.g. the
`best.txt` or `mean.txt` of a `long_kick` or `kick_distance` job), and
`--approach-params` ball-approach files (an `approach` job's), as
`benchmarks.walk --params` does for the walk: a result is benchmarked without
swapping the shipped files. Each row names the files it ran with.
"""

from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np
from tqdm import tqdm

from benchmarks.machine import machine
from benchmarks.stats import rate_ci
from optimization.kick import kick_trial
from skills.approach import ApproachParams
from skills.kicks import KickSkill, all_kicks
from skills.walk import default_param_files, load_walk_sets

OUTCOMES = ("success", "timeout", "approach_fall", "kick_fall", "short")
BUMP = 0.05  # m the ball may move (nudged, rocked) before the kick without counting as run into


def outcome(row: dict) -> str:
    """One trial's outcome (a `kick_trial` row): "success"; no kick started, "timeout" or
    "approach_fall" (the robot fell before it could kick); a kick started, "kick_fall"
    (it fell in or after the kick) or "short" (the ball went less than 1 m toward the target)."""
    if row["success"]:
        return "success"
    if not row["kicked"]:
        return "approach_fall" if row["fell"] else "timeout"
    return "kick_fall" if row["fell"] else "short"


def kick_stats(robot_type: int, kick: KickSkill, mode: str, tries: int, seed: int,
               progress: tqdm | None = None, approach: ApproachParams | None = None,
               walk_sets: dict | None = None) -> dict:
    """Aggregate of `tries` kicks (one JSON row); approach: the ball approach's parameters
    and walk_sets the walk's (default: the type's shipped ones)."""
    rng = np.random.default_rng([seed, robot_type, sum(map(ord, kick.spec.name)), len(mode)])
    rows = []
    wall = time.perf_counter()
    for i in range(tries):
        rows.append(kick_trial(robot_type, kick, mode, rng, seed * 1000 + i, approach=approach,
                               walk_sets=walk_sets))
        if progress is not None:
            progress.update()
    dist = np.array([r["distance"] for r in rows])
    dirs = np.array([r["direction"] for r in rows if r["kicked"] and r["direction"] is not None])
    errs = np.abs(dirs)
    contact = [r["contact_s"] for r in rows if r["contact_s"] is not None]
    ok = sum(r["success"] for r in rows)
    return {
        "kick": kick.spec.name, "robot_type": robot_type, "mode": mode, "tries": tries,
        "success_rate": round(ok / tries, 3), "success_ci95": rate_ci(ok, tries),
        "distance_mean_m": round(float(dist.mean()), 2), "distance_std_m": round(float(dist.std()), 2),
        "direction_error_mean_deg": round(float(errs.mean()), 1) if errs.size else None,
        "direction_bias_deg": round(float(dirs.mean()), 1) if dirs.size else None,
        "direction_sd_deg": round(float(dirs.std()), 1) if dirs.size else None,
        "falls": sum(r["fell"] for r in rows), "kicks_started": sum(r["kicked"] for r in rows),
        "approach_bumps": sum(r["bumped"] > BUMP for r in rows),
        "time_to_contact_mean_s": round(float(np.mean(contact)), 2) if contact else None,
        "outcomes": {k: sum(outcome(r) == k for r in rows) for k in OUTCOMES},
        "nominal_distance_m": kick.spec.distance,
        "wall_s": round(time.perf_counter() - wall, 1),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", type=int, nargs="+", default=[0], choices=range(5), metavar="T")
    ap.add_argument("--kicks", nargs="+", default=None, help="kick names (default: every shipped kick)")
    ap.add_argument("--modes", nargs="+", default=["standing", "walking"], choices=("standing", "walking"))
    ap.add_argument("--tries", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--params", nargs="+", default=[], metavar="FILE",
                    help="keyframe kick parameter files loaded after the shipped ones "
                         "(e.g. a CMA-ES best.txt)")
    ap.add_argument("--approach-params", nargs="+", default=[], metavar="FILE",
                    help="ball approach parameter files loaded after the shipped ones")
    ap.add_argument("--walk-params", nargs="+", default=[], metavar="FILE",
                    help="walk parameter files loaded after the shipped ones (as benchmarks.walk --params)")
    args = ap.parse_args(argv)
    if args.tries < 1:
        ap.error(f"--tries must be at least 1, not {args.tries}")
    jobs = []
    for t in args.types:
        try:  # a bad file fails here, with file:line
            kicks = all_kicks(t, keyframe_params=args.params)
            approach = ApproachParams.load(args.approach_params, robot_type=t)
            walk = load_walk_sets(default_param_files(t) + args.walk_params) if args.walk_params else None
        except (OSError, ValueError) as err:
            ap.error(str(err))
        names = args.kicks or list(kicks)
        unknown = [n for n in names if n not in kicks]
        if unknown:
            ap.error(f"unknown kick(s) {', '.join(unknown)}; known: {', '.join(kicks)}")
        jobs += [(t, kicks[n], m, approach, walk) for n in names for m in args.modes]
    files = {"params": args.params, "approach_params": args.approach_params, "walk_params": args.walk_params}
    print(json.dumps({"machine": machine()}), flush=True)
    with tqdm(total=len(jobs) * args.tries, desc="kicks", unit="kick", file=sys.stderr) as bar:
        for t, kick, mode, approach, walk in jobs:
            row = kick_stats(t, kick, mode, args.tries, args.seed, bar, approach, walk)
            print(json.dumps({**row, **files}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

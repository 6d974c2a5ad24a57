"""Dribbling: the team's walk through the ball, timed over 10 m (issue 47's dribble goal).

Per robot type, `--tries` seeded runs of `optimization.dribble_walk.dribble_run`
(one villa player, percepts only, asked for one `Dribble(target)` from `--start` m
behind the ball, the target 10 m away within +-`--spread` deg of the field's +x), so
the body's own dribble (`agent.body.Body._dribble`: line up behind the ball, walk
through it, line up again when it gets away) is what is measured. Ground truth decides:

* done: the ball's progress along the target line reached `--distance` m
  (default 10) within `--limit` s;
* speed (m/s): the distance over the time from the first touch to done;
* held: the ball stayed within 1 m of the robot's torso at every cycle from the
  first touch to done (issue 47: "keeps the ball within 1 m of the robot");
* off line (m): the ball's largest distance from the target line; falls.

A try that is done and held at at least 0.35 m/s meets issue 47's goal.

What it showed (10 tries a type, seed 0, December 2026), types 0-4: the ball
went the 10 m in 49 of 50 tries without a fall, at a median 0.31, 0.34, 0.29,
0.31 and 0.31 m/s (0.23-0.44 over all tries), but no try held it: each push
sends the ball a median 2.0-2.4 m ahead of the robot, which walks after it
(the go-to-target set at full speed through the ball), and it strays a median
0.7-1.5 m from the line. Goal met: 0 of 50.

Why the ball gets away: on this field a ball rolled off at 0.3, 0.5, 0.8 and 1.2 m/s
stops 0.6, 1.1, 1.8 and 2.8 m on, so a push must leave the foot below about 0.5 m/s
for a robot at 0.35 m/s to stay within 1 m; the walk's swing foot meets the ball
faster than that. Walking through the ball with the position-to-dribble set instead
(tried, 8 tries a type, not shipped): gap 1.5-1.9 m (types 0-4), off line 0.5-1.5 m,
0.28-0.33 m/s, one fall (type 2); still 0 held. The funnel (villa since December 6; 8 tries a type,
villa:NoFunnel -> villa): done 39 -> 40 of 40, median speed 0.28-0.37 -> 0.30-0.35 m/s,
gap 1.8-2.3 -> 1.5-2.1 m, off line 0.5-1.7 -> 0.6-1.5 m, falls 0 -> 3 (types 2 and 3);
still 0 held.

villa -> villa:Hold (the push walks toward 0.2 m past the ball instead of 0.8, slowing within
0.6 m, its step sizes following at 0.1 a cycle instead of 0.03; December 7, 2026, 10 tries a
type, seed 0), types 0-4: median gap 1.76, 2.15, 2.03, 1.61, 2.46 -> 1.20, 1.27, 2.09, 1.42,
1.08 m; median speed 0.289, 0.349, 0.313, 0.301, 0.341 -> 0.315, 0.327, 0.306, 0.277, 0.299
m/s; held 1 -> 2 of 50 (none at 0.35 m/s); falls 3 -> 2. A gentler push (0.2 m past, braking
within 0.8 m; 8 tries a type) held the ball in 16 of 40 tries (types 1, 3 and 4: 7, 4 and 5)
but dribbled at a median 0.19-0.29 m/s: at today's walk speed the goal's two halves pull apart.
In games villa:Hold tied villa, -0.08 +- 0.06 over 40 (benchmarks/results/hold-vs-villa/).
With a faster walk the two halves meet: `--variant FastHold` (FastWalk's go-to-target sets,
type 0 0.465 m/s, with the gentler push: 0.2 m past the ball, braking within 0.8 m), 10
tries, seed 0: type 0 held the ball in 5 and **met the goal in 3** (within 1 m at 0.35-0.42
m/s; 95% interval 11-60%), median speed 0.328 m/s, 2 falls; type 1 (0.407 m/s) held it once,
met it in none, 1 fall. FastWalk without the hold (8 tries): type 0 held it once, met it in
none.

villa with the fast sets for every type (villa since December 7, 2026; 10 tries a type, seed
0), types 0-4: median speed 0.353, 0.358, 0.315, 0.405, 0.318 m/s; median gap 1.54, 1.65,
1.48, 2.62, 2.03 m; held 2 of 50, the goal met in none; falls 4, 2, 0, 0, 7. Type 4's fast
set trips over the ball: 7 of 10 tries fell (3 of 10 with seed 1), none of 10 on its shipped
set (villa:SlowWalk).

`--variant FastDribble` (position-to-dribble sets learned from the fast stands on the
`dribble_walk` task, `skills/data/walk_fast_dribble_type*.txt`; December 7, 2026, 10 tries a
type, seed 0), villa -> FastDribble, types 0, 1, 2, 4: median speed 0.353, 0.358, 0.315,
0.318 -> 0.431, 0.373, 0.363, 0.406 m/s; median gap 1.54, 1.65, 1.48, 2.03 -> 1.62, 1.88,
1.52, 2.52 m; held in 2 of 40 tries, the goal met in both (types 0 and 2; villa: 2 of 50
over all five types, met in none); falls 4, 2, 0, 7 -> 0, 0, 0, 1. Type 3 keeps its
go-to-target values (0.405 m/s, gap 2.62 m, no falls, as villa). In games it tied villa
(+0.00 +- 0.08 over 40).

`--variant NAME` dribbles with a villa variant's body (`villa:Sprint`: the sprint
set toward a target within 15 deg on the shipped walk; never through the ball).

`--variant DribbleWalk` (position-to-dribble sets learned on this run's 20 s form, the
`dribble_walk` task, types 0-2 and 4; type 3's run found nothing better), 8 tries a type,
seed 0, base -> DribbleWalk: median gap 1.81 -> 1.64, 2.27 -> 1.96, 2.05 -> 2.42 and
2.26 -> 2.03 m (types 0, 1, 2, 4); median speed 0.32 -> 0.30, 0.37 -> 0.41, 0.28 -> 0.31,
0.33 -> 0.31 m/s; no falls; still 0 held. On the task's own measure (seconds of 20 with
the ball over 1 m away) the learned sets halve the time away for types 0 and 4.

    python -m benchmarks.dribble [--types 0,1,2,3,4] [--tries 10] [--seed 0] [--variant NAME]
"""

from __future__ import annotations

import argparse
import json
import math
import sys

import numpy as np

from agent.teamconfig import VILLA, UnknownVariant
from agent.teamconfig import variant as team_variant
from benchmarks.args import robot_types
from benchmarks.machine import machine
from benchmarks.stats import rate_ci
from optimization.dribble_walk import HOLD, dribble_run

GOAL_SPEED = 0.35  # m/s over the distance, issue 47


def trial(robot_type: int, rng: np.random.Generator, seed: int, distance: float = 10.0,
          start: float = 0.5, spread: float = 30.0, limit: float = 60.0, variant: str | None = None) -> dict:
    """One try: done, speed (m/s), held, the ball's largest gap to the torso and to the
    target line (m), falls, and the seconds to the first touch."""
    config = VILLA if variant is None else team_variant(variant)
    r = dribble_run(robot_type, rng, seed, distance, start, spread, limit, config)
    return {"done": r.done is not None, "speed": r.speed, "held": r.done is not None and r.gap <= HOLD,
            "gap": r.gap, "off_line": r.off_line, "falls": r.falls, "touch_s": r.touch,
            "progress": r.progress}


def dribble_stats(robot_type: int, tries: int, seed: int = 0, **kw) -> dict:
    """Aggregate of `tries` trials (one JSON row)."""
    rng = np.random.default_rng([seed, robot_type])
    rows = [trial(robot_type, rng, seed * 1000 + i, **kw) for i in range(tries)]
    done = [r for r in rows if r["done"]]
    speeds = np.array([r["speed"] for r in done])
    goal = sum(r["held"] and r["speed"] >= GOAL_SPEED for r in rows)
    return {
        "robot_type": robot_type, "tries": tries, "variant": kw.get("variant"),
        "done": len(done), "held": sum(r["held"] for r in rows),
        "speed_median": round(float(np.median(speeds)), 3) if len(done) else None,
        "speed_range": [round(float(speeds.min()), 3), round(float(speeds.max()), 3)] if len(done) else None,
        "goal_met": goal, "goal_ci95": [round(v, 3) for v in rate_ci(goal, tries)],
        "gap_median": round(float(np.median([r["gap"] for r in rows])), 2),
        "off_line_median": round(float(np.median([r["off_line"] for r in rows])), 2),
        "progress_median": round(float(np.median([r["progress"] for r in rows])), 2),
        "touch_median_s": round(float(np.median([r["touch_s"] if r["touch_s"] is not None else math.inf
                                                 for r in rows])), 2),
        "falls": sum(r["falls"] for r in rows),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.dribble", description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0,1,2,3,4", help="robot types, comma-separated (default all)")
    ap.add_argument("--tries", type=int, default=10, help="tries per type (default 10)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--distance", type=float, default=10.0, help="m the ball is to go (default 10)")
    ap.add_argument("--start", type=float, default=0.5, help="m behind the ball at the start (default 0.5)")
    ap.add_argument("--spread", type=float, default=30.0,
                    help="deg either side of +x for the target (default 30)")
    ap.add_argument("--limit", type=float, default=60.0, help="s a try may take (default 60)")
    ap.add_argument("--variant", default=None, help="the villa variant whose body dribbles (e.g. Sprint)")
    args = ap.parse_args(argv)
    types = robot_types(ap, args.types)
    if args.tries < 1 or not 0 < args.distance <= 12 or args.start < 0 or args.limit <= 0:
        got = f"{args.tries}, {args.distance}, {args.start}, {args.limit}"
        ap.error("--tries >= 1, 0 < --distance <= 12 (the ball starts 6 m from the field's center), "
                 f"--start >= 0 and --limit > 0 (got {got})")
    if args.variant is not None:
        try:
            team_variant(args.variant)
        except UnknownVariant as e:
            ap.error(str(e))
    print(json.dumps({"machine": machine()}), flush=True)
    for t in types:
        row = dribble_stats(t, args.tries, args.seed, distance=args.distance, start=args.start,
                            spread=args.spread, limit=args.limit, variant=args.variant)
        print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

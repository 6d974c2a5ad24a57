"""Duels: one field player a side for a free ball, team A's play against team B's.

In a match the ball is a race between the two on-ball players most of the time, so a
duel is a cheap first look at whether a change to how villa plays the ball wins it
(the proof is still `soccer batch`). Each of `--pairs` seeded pairs draws a ball in the
field's middle, a robot type from `--types` and two starts 1-2 m from the ball at random
bearings, facing it (`optimization.trials.duel`), and plays it twice: A (left) from the
first start and B (right) from the second, then the same turned half round the center
with the starts swapped, so that each team gets each start toward its own goal. Ground
truth per duel, after `--seconds` of play on:

* progress (m): how far the ball went toward B's goal; a pair's is the mean of its two;
* possession: A's share of the time the ball was last touched by either;
* first touch: how often A touched the ball first;
* falls a duel, each side.

The line gives the mean progress a pair with its standard error and 95% interval
(t over pairs), so A against A should come out near 0.

Against the batches (200 pairs, seed 0, December 6, 2026; 7 minutes each on 2 workers
beside a batch): villa:NoFunnel - villa **-0.43 +- 0.14 m** (possession 43%, first touch
40%), where the batch gave villa:Funnel +0.43 +- 0.12 goals a game over it; villa:NoCone
(neither the cone nor the funnel) - villa **-0.65 +- 0.16 m** (possession 41%, first touch
26%). A rolling ball played where the player would meet it (the ball filter's prediction;
tried, not kept) - villa +0.09 +- 0.14 m: nothing to batch. villa:QuickStart (the walk
at speed from the stand in a third of a second) - villa **+0.64 +- 0.13 m** (possession
60%), yet +0.03 +- 0.07 goals a game over 40 full games (4:3 in goals) and no more
possession there: a duel starts both players from a stand, which a match seldom does, so
it screens changes for a batch and does not replace one. GentleOrbit (commit 2ef4032)
won its duels too (+0.26 +- 0.13 m) and nothing in small-sided games; those (4 vs 4, 2 x
150 s, 40 games in 15 minutes) agree with full games on both Funnel and QuickStart, so
they are the better screen for a batch (README, `benchmarks/results/screen-4v4/`).

    python -m benchmarks.duel [--home villa:NAME] [--away villa] [--pairs 20] [--seed 0]
                              [--types 0,1,2,3,4] [--seconds 20] [--workers 1]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np
from scipy import stats

from agent.teamconfig import TeamConfig
from agent.variants import VillaFactory
from benchmarks.args import robot_types
from benchmarks.machine import machine
from cli.teams import UnknownTeam, factory
from optimization.trials import Duel, duel


def team(ap: argparse.ArgumentParser, spec: str) -> tuple[str, TeamConfig]:
    """(name, config) of "villa" or "villa:NAME" (`cli.teams`); a usage error naming the spec otherwise."""
    try:
        f = factory(spec)
    except UnknownTeam as e:
        ap.error(str(e))
    if not isinstance(f, VillaFactory):
        ap.error(f"duels are between villa variants (villa or villa:NAME), got {spec!r}")
    return f.name, f.config


def pair(a: TeamConfig, b: TeamConfig, types: tuple[int, ...], seed: int,
         seconds: float) -> tuple[Duel, Duel]:
    """Pair `seed`: the duel and its half-turned twin with the starts swapped, A left in both."""
    rng = np.random.default_rng(seed)
    ball = rng.uniform((-2.0, -2.0), (2.0, 2.0))
    starts = []
    for _ in range(2):
        bearing, distance = rng.uniform(-math.pi, math.pi), rng.uniform(1.0, 2.0)
        starts.append(ball + distance * np.array([math.cos(bearing), math.sin(bearing)]))
    robot_type = types[int(rng.integers(len(types)))]
    first = duel(a, b, robot_type, 2 * seed, tuple(ball), (tuple(starts[0]), tuple(starts[1])), seconds)
    turned = (tuple(-starts[1]), tuple(-starts[0]))
    second = duel(a, b, robot_type, 2 * seed + 1, tuple(-ball), turned, seconds)
    return first, second


def summary(pairs: list[tuple[Duel, Duel]]) -> dict:
    """The figures of the module docstring over the pairs' duels."""
    duels = [d for p in pairs for d in p]
    progress = np.array([(p[0].progress + p[1].progress) / 2 for p in pairs])
    n = len(progress)
    se = float(progress.std(ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    half = float(stats.t.ppf(0.975, n - 1) * se) if n > 1 else math.nan
    held = sum(d.possession["L"] for d in duels), sum(d.possession["R"] for d in duels)
    touched = [d.first for d in duels if d.first is not None]
    return {
        "pairs": n,
        "progress_m": round(float(progress.mean()), 3),
        "se": round(se, 3),
        "ci95": [round(float(progress.mean()) - half, 3), round(float(progress.mean()) + half, 3)],
        "possession_a": round(held[0] / max(sum(held), 1e-9), 3),
        "first_touch_a": round(touched.count("L") / max(len(touched), 1), 3),
        "falls_a": round(sum(d.falls["L"] for d in duels) / len(duels), 2),
        "falls_b": round(sum(d.falls["R"] for d in duels) / len(duels), 2),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", default="villa", help="team A: villa or villa:NAME (default villa)")
    ap.add_argument("--away", default="villa", help="team B: villa or villa:NAME (default villa)")
    ap.add_argument("--pairs", type=int, default=20, help="pairs of duels (default 20)")
    ap.add_argument("--seed", type=int, default=0, help="pair k draws from seed + k (default 0)")
    ap.add_argument("--types", default="0,1,2,3,4", help="robot types drawn from, comma-separated")
    ap.add_argument("--seconds", type=float, default=20.0, help="s of play a duel (default 20)")
    ap.add_argument("--workers", type=int, default=1, help="processes (default 1)")
    args = ap.parse_args(argv)
    types = tuple(robot_types(ap, args.types))
    if args.pairs < 2 or args.seconds <= 0 or args.workers < 1:
        ap.error(f"need --pairs >= 2, --seconds > 0 and --workers >= 1 (got {args.pairs}, {args.seconds}, "
                 f"{args.workers})")
    (name_a, a), (name_b, b) = team(ap, args.home), team(ap, args.away)
    seeds = range(args.seed, args.seed + args.pairs)
    with ProcessPoolExecutor(args.workers) as pool:
        pairs = list(pool.map(pair, *zip(*((a, b, types, s, args.seconds) for s in seeds))))
    print(json.dumps({"benchmark": "duel", "a": name_a, "b": name_b, "seed": args.seed,
                      "seconds": args.seconds, "types": list(types), **summary(pairs)}), flush=True)
    print(json.dumps({"machine": machine()}), file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

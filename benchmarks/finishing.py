"""Finishing: the team's play on a ball near their goal, against a standing goalie.

Seeded tries (`optimization.trials.finish`, try k with robot type k mod 5 unless
`--types` names one): a villa player (`--variant` of it, or the base team) stands a few
m from a ball near the right goal, facing it; the right team's posture goalie stands
where it was beamed, in front of its goal's middle; the referee sets play on and the
player does what the team does with the ball, from its percepts, until a goal, an out
or `--seconds`. Two spots (`--spot`):

* goal-kick: the ball where a goal kick puts it, 1 m in front of the goal's middle (a
  posture team never takes its goal kicks: the ball lies there until the drop ball), the
  player 1.5-3.5 m behind it;
* beside: the ball beside a post, 0.2-0.7 m from the end line and 1.3-2.5 m off the
  field's long axis, the player 2-3.5 m from the end line.

Figures per spot: goals, outs and tries still in play at the end; the median time to a
goal (s, over the tries that scored); falls. Ground truth throughout.

What it showed (12 tries a spot, seed 0, types 0-4 in turn, December 6, 2026),
villa:NoFinish -> villa:Finish, villa since (the dribble aiming past a blocker and
centering a ball beside the goal first): goal-kick 8 goals, 2 outs, 2 still in play after
30 s -> 12 goals (median 13.3 -> 13.1 s; falls 2 -> 1); beside 3 goals, 9 outs -> 8 goals,
1 out, 3 in play (median 9.9 -> 19.4 s: centering takes time; falls 0 -> 3).
villa:NoFinish pushed a ball beside the goal straight on, over the end line, and from the
goal kick's spot aimed 0.17 m past the goalie's middle, into its side. Aiming instead at
whichever corner the line still reaches from beside the goal: 6 goals, 6 outs (the dribble
does not hit a narrow mouth from a steep angle).

    python -m benchmarks.finishing [--spot goal-kick,beside] [--tries 12] [--seed 0]
                                   [--variant NAME] [--types 0,1,2,3,4] [--seconds 30]
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from agent.teamconfig import TeamConfig
from benchmarks.args import robot_types, villa_config
from benchmarks.machine import machine
from models import field as fld
from optimization.trials import Finish, finish

SPOTS = ("goal-kick", "beside")


def placement(spot: str, rng: np.random.Generator) -> tuple[tuple[float, float], tuple[float, float]]:
    """The ball's and the player's places (field frame, m) of one try at `spot`."""
    if spot == "goal-kick":
        return (fld.HALF_LENGTH - 1.0, 0.0), (fld.HALF_LENGTH - rng.uniform(2.5, 4.5), rng.uniform(-1.0, 1.0))
    side = float(rng.choice((-1.0, 1.0)))
    ball = (fld.HALF_LENGTH - rng.uniform(0.2, 0.7), side * rng.uniform(1.3, 2.5))
    return ball, (fld.HALF_LENGTH - rng.uniform(2.0, 3.5), side * rng.uniform(0.0, 3.0))


def finish_stats(spot: str, config: TeamConfig, tries: int, types: list[int], seed: int = 0,
                 seconds: float = 30.0) -> dict:
    """`tries` trials at `spot`, try k from seed + k with robot type types[k mod len], and
    their figures."""
    rows: list[Finish] = []
    for k in range(tries):
        ball, start = placement(spot, np.random.default_rng(seed + k))
        rows.append(finish(types[k % len(types)], config, seed + k, ball, start, seconds))
    goals = [r.time for r in rows if r.outcome == "goal"]
    return {
        "spot": spot, "tries": tries, "goals": len(goals),
        "outs": sum(r.outcome == "out" for r in rows),
        "in_play": sum(r.outcome is None for r in rows),
        "goal_median_s": round(float(np.median(goals)), 2) if goals else None,
        "falls": sum(r.falls for r in rows),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spot", default=",".join(SPOTS), help=f"spots, comma-separated: {', '.join(SPOTS)}")
    ap.add_argument("--tries", type=int, default=12, help="tries per spot (default 12)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--variant", default="", help="a villa variant (default: villa itself)")
    ap.add_argument("--types", default="0,1,2,3,4", help="robot types, taken in turn (default all)")
    ap.add_argument("--seconds", type=float, default=30.0, help="s of play a try at most (default 30)")
    args = ap.parse_args(argv)
    types = robot_types(ap, args.types)
    spots = [s.strip() for s in args.spot.split(",") if s.strip()]
    if not spots or any(s not in SPOTS for s in spots):
        ap.error(f"--spot: one or more of {', '.join(SPOTS)}, got {args.spot!r}")
    if args.tries < 1 or args.seconds <= 0:
        ap.error(f"need --tries >= 1 and --seconds > 0 (got {args.tries}, {args.seconds})")
    name, config = villa_config(ap, args.variant)
    for spot in spots:
        row = finish_stats(spot, config, args.tries, types, args.seed, args.seconds)
        print(json.dumps({"benchmark": "finishing", "team": name, **row}), flush=True)
    print(json.dumps({"machine": machine()}), file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Clearing: the team's play on a ball at its own goal line.

Seeded tries (`optimization.trials.clear`, try k with robot type k mod len(`--types`)),
villa's goalie where it was beamed and villa's player 2 (`--variant` of it, or the base
team); with `--attacker`, a villa player of the other team too. Three spots (`--spot`):

* line: the ball lies 0.2-0.6 m in front of the left goal line, within 1 m of the mouth's
  middle; player 2 stands 1.5-3 m out and up to 1.5 m to one side, facing the ball and so
  its own goal, as a player that ran back after the ball does; the attacker 1-2.5 m out on
  the other side, facing the ball too;
* roller: the ball rolls from 4-7 m out toward a point in the mouth where it would rest
  0.1-0.8 m out (a slow pass or shot that stops short of the line); player 2 starts 1.5-2.5 m
  to one side of it, the attacker 1.5-3 m behind it;
* attack: the ball 2.5-4.5 m out, within 1.5 m of the mouth's middle, the attacker (always
  there) 0.8-1.5 m behind it facing the goal, player 2 4-6 m out, 1-3 m to one side.

Play on until the ball, once within 2.5 m of the goal line, is that far out again
(cleared), a goal (into the own goal), an out, or `--seconds`. Figures: cleared, goals
against, outs and tries still in play at the end; the median time to clear (s, over the
tries that cleared); falls. Ground truth throughout.

What it showed (type 0, seeds from 0, December 7, 2026). A goal villa conceded in a
match (villa against villa:DeepKickoff, seed 5, 108 s): a slow kick stopped 0.4 m in
front of the goal and lay there for 8 s while the goalie and a defender, both facing their
own goal, walked round it to line up toward the other goal, until an attacker pushed it in.
Of the 17 goals in the 34 logged games of `benchmarks/results/walkupkickoff-vs-villa/`, 4
came after the ball had lain within 1 m of the goal line, in front of the mouth, for 6-11 s;
11 after 7-24 s of play within 3 m of it, 4 after 30 s or more there, 2 within 5 s.
- line, no attacker, 20 tries: 13 cleared (median 11.0 s), 5 outs, 2 in play, 18 falls.
- line, attacker, 100 tries: 32 cleared (median 11.9 s), **37 goals against**, 23 outs, 8
  in play, 101 falls. Pushing the ball out to the side instead (a dribble 60 deg off the
  field's long axis, away from the mouth's middle, the goalie too, so that nobody lines up
  inside the goal): 32 cleared (17.2 s), 40 goals, 17 outs, 124 falls; not kept. The field
  player voted onBall leaving the ball to the goalie when it takes the goalie for the on-ball
  player (both played it): seeds 0-59, 23 goals against villa's 22 there; without the
  attacker (20 tries) 17 cleared (16.7 s), 0 outs, 10 falls against 13 (11.0 s), 5, 18; not kept.
- roller, attacker, 60 tries: 38 cleared (12.1 s), 3 goals against, 2 outs, 17 in play.
  The goalie standing in the ball's path on its line instead of walking out to play it:
  39, 4, 2, 15; not kept. The slow roller that became a goal in the match is rare here.
- attack, 60 tries: 13 cleared, 17 goals against, 22 outs, 8 in play, 33 falls. The goalie
  keeping its place between the ball and the goal while an opponent is nearer the ball,
  instead of walking out to play it (two goals of a batch's logs went past a goalie that had
  stepped out): 12, 20, 21, 7, 43 falls; not kept.
- attack, our goalie's robot type (`--goalie-type`; villa's is 0), 60 tries each: goals
  against 17 (type 0), 17 (1), 23 (2), 19 (3), 11 (4). Types 0 and 4 over 200 more tries
  (`--seed 60 --tries 200`): 65 and 49, cleared 60 and 69, outs 51 and 55, falls 121 and 107;
  all 260 paired by seed: 82 against 60 goals (31.5 and 23.1%), 51 tries where only the type
  0 goalie conceded and 29 where only type 4 did (McNemar z 2.5). villa:Goalie4. The dives
  are the same for both types (`benchmarks.dive --types 0,4 --tries 5`). At the line with an
  attacker (seeds 0-99): a type 4 goalie 43 cleared, 28 goals against, 23 outs (type 0: 32,
  37, 23; 22 tries where only type 0 conceded, 13 where only type 4 did).
- attack, villa:GoalieHead (the goalie's head always on the ball, as the dissertation's goalie;
  villa's scans beyond 1 m), 60 tries (December 8, 2026): 16 cleared, 16 goals against, 20 outs,
  8 in play, 48 falls; villa the same day 16, 17, 19, 8, 35. Not kept.

    python -m benchmarks.clearing [--spot line|roller|attack] [--tries 12] [--seed 0] [--variant NAME]
                                  [--attacker] [--types 0,1,2,3,4] [--goalie-type 0] [--seconds 30]
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
from optimization.trials import Clear, clear

Place = tuple[float, float]
SPOTS = ("line", "roller", "attack")


def _speed_for(distance: float) -> float:
    """The speed (m/s) at which a ball rolls `distance` m before it rests (bisection)."""
    lo, hi = 0.0, 10.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if fld.rolling_distance(mid) < distance else (lo, mid)
    return 0.5 * (lo + hi)


def placement(spot: str, rng: np.random.Generator) -> tuple[Place, Place, Place, Place]:
    """The ball's place and velocity, the defender's and the attacker's places (field frame,
    m, m/s) of one try at `spot`."""
    if spot == "line":
        ball = (-fld.HALF_LENGTH + rng.uniform(0.2, 0.6), rng.uniform(-1.0, 1.0))
        side = float(rng.choice((-1.0, 1.0)))
        defender = (ball[0] + rng.uniform(1.5, 3.0), ball[1] + side * rng.uniform(0.0, 1.5))
        attacker = (ball[0] + rng.uniform(1.0, 2.5), ball[1] - side * rng.uniform(0.5, 1.5))
        return ball, (0.0, 0.0), defender, attacker
    if spot == "attack":  # an attacker dribbling at the goal, our defender far behind
        ball = (-fld.HALF_LENGTH + rng.uniform(2.5, 4.5), rng.uniform(-1.5, 1.5))
        attacker = (ball[0] + rng.uniform(0.8, 1.5), ball[1] + rng.uniform(-0.5, 0.5))
        defender = (ball[0] + rng.uniform(4.0, 6.0), float(rng.choice((-1.0, 1.0))) * rng.uniform(1.0, 3.0))
        return ball, (0.0, 0.0), defender, attacker
    # roller: from 4-7 m out toward a point in the mouth where it would rest 0.1-0.8 m out
    ball = (-fld.HALF_LENGTH + rng.uniform(4.0, 7.0), rng.uniform(-2.5, 2.5))
    rest = np.array([-fld.HALF_LENGTH + rng.uniform(0.1, 0.8), rng.uniform(-0.8, 0.8)])
    d = rest - np.array(ball)
    dist = float(np.hypot(*d))
    v = _speed_for(dist) * d / dist
    side = float(rng.choice((-1.0, 1.0)))
    defender = (ball[0] + rng.uniform(-1.0, 1.0), ball[1] + side * rng.uniform(1.5, 2.5))
    attacker = (ball[0] + rng.uniform(1.5, 3.0), ball[1] - side * rng.uniform(0.0, 1.0))
    return ball, (float(v[0]), float(v[1])), defender, attacker


def clear_stats(config: TeamConfig, tries: int, types: list[int], seed: int = 0, attacker: bool = False,
                seconds: float = 30.0, spot: str = "line", goalie_type: int = 0) -> dict:
    """`tries` trials at `spot`, try k from seed + k with robot type types[k mod len], and
    their figures."""
    rows: list[Clear] = []
    for k in range(tries):
        ball, velocity, start, other = placement(spot, np.random.default_rng(seed + k))
        rows.append(clear(types[k % len(types)], config, seed + k, ball, start,
                          other if attacker or spot == "attack" else None, seconds, velocity, goalie_type))
    times = [r.time for r in rows if r.outcome == "cleared"]
    return {
        "spot": spot, "goalie_type": goalie_type, "tries": tries, "attacker": attacker or spot == "attack",
        "cleared": len(times),
        "goals_against": sum(r.outcome == "goal" for r in rows),
        "outs": sum(r.outcome == "out" for r in rows),
        "in_play": sum(r.outcome is None for r in rows),
        "clear_median_s": round(float(np.median(times)), 2) if times else None,
        "falls": sum(r.falls for r in rows),
        "outcomes": [r.outcome for r in rows],
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spot", default="line", choices=SPOTS, help="line (default) or roller")
    ap.add_argument("--tries", type=int, default=12, help="tries (default 12)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--variant", default="", help="a villa variant (default: villa itself)")
    ap.add_argument("--attacker", action="store_true", help="a villa attacker of the other team")
    ap.add_argument("--types", default="0,1,2,3,4", help="robot types, taken in turn (default all)")
    ap.add_argument("--goalie-type", type=int, default=0, choices=range(5), help="our goalie's robot type")
    ap.add_argument("--seconds", type=float, default=30.0, help="s of play a try at most (default 30)")
    args = ap.parse_args(argv)
    types = robot_types(ap, args.types)
    if args.tries < 1 or args.seconds <= 0:
        ap.error(f"need --tries >= 1 and --seconds > 0 (got {args.tries}, {args.seconds})")
    name, config = villa_config(ap, args.variant)
    row = clear_stats(config, args.tries, types, args.seed, args.attacker, args.seconds, args.spot,
                      args.goalie_type)
    print(json.dumps({"benchmark": "clearing", "team": name, **row}), flush=True)
    print(json.dumps({"machine": machine()}), file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Kickoffs: where the ball is in the seconds after a team's own kickoff, paired by seed.

For each team of `--teams` (the first is the base) and each seed, an 11 vs 11 match
(`--size` a side) against `--away` is played from its first kickoff, which the team
takes (it plays left, attacking +x), for `--seconds` s of game time counted from the
kickoff's start. Ground truth throughout. Printed per team: the ball's mean x (m,
toward the opponents' goal) at each mark, and for every team after the first its
paired difference from the base with the standard error over seeds; when the kickoff
was taken (the play mode left KickOff, median s); goals for and against in the window.

What it showed (30 seeds from 0, villa against villa, December 7, 2026): villa's kickoff
is taken in 0.06 s: its taker, beamed 0.17 m behind the ball for an immediate pass to the
side, nudges it 1-1.5 m straight ahead with its approach's first step, and the ball is
back at the center line within a minute (x +1.2 m at 10 s, -1.0 at 90 s).
villa:DeepKickoff (the longest kick deep toward their goal, from 0.35 m behind the ball)
kicks at a median 8.0 s and keeps the ball deep: +5.1 +- 0.3 m more than villa at 10 s,
+9.7 +- 0.6 at 15 s, +8.1 +- 1.1 at 30 s, +9.5 +- 1.5 at 60 s, +8.5 +- 1.7 at 90 s; no goal
within 90 s either way (`benchmarks/results/deepkickoff-vs-villa/` for the full games).

    python -m benchmarks.kickoff [--teams villa,villa:DeepKickoff] [--away villa] [--tries 30]
                                 [--seed 0] [--seconds 90] [--size 11] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from benchmarks.machine import machine
from cli.teams import UnknownTeam, factory
from models.rules import CYCLE, PlayMode
from server.match import Match, lineup_for

MARKS = (5.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 90.0)  # s after the kickoff's start


def kickoff_try(team: str, away: str, seed: int, seconds: float, size: int) -> dict:
    """One match of `team` (left, kicking off) against `away`: the ball's x (world frame,
    m) at each mark within `seconds`, when the kickoff was taken (s, None if not) and the
    goals (for, against) within the window."""
    left, right = factory(team), factory(away)
    m = Match(left, right, lineup_for(left, right, size, size), half_time=max(300.0, seconds + 1.0),
              seed=seed, team_names=(team, away))
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    marks = [t for t in MARKS if t <= seconds + 1e-9]
    x, taken = {}, None
    for c in range(1, round(seconds / CYCLE) + 1):
        m.step()
        t = c * CYCLE
        if taken is None and m.referee.mode != PlayMode.KICK_OFF_LEFT:
            taken = round(t, 2)
        if marks and t >= marks[0] - 1e-9:
            x[marks.pop(0)] = float(m.world.ball_position()[0])
    return {"team": team, "seed": seed, "x": x, "taken": taken,
            "goals": (m.referee.score["L"], m.referee.score["R"])}


def summary(rows: list[dict], teams: list[str]) -> list[dict]:
    """Per team: mean ball x at each mark, the paired difference from teams[0] (mean, standard
    error over the seeds both played), the kickoff's median time and the goals."""
    by = {t: {r["seed"]: r for r in rows if r["team"] == t} for t in teams}
    base = by[teams[0]]
    out = []
    for t in teams:
        mine = by[t]
        seeds = sorted(set(mine) & set(base))
        marks = sorted(set.intersection(*(set(r["x"]) for r in mine.values()))) if mine else []
        row = {"team": t, "tries": len(mine),
               "x": {f"{k:g}": round(float(np.mean([r["x"][k] for r in mine.values()])), 2) for k in marks}}
        if t != teams[0] and len(seeds) > 1:
            diff = {}
            for k in marks:
                d = np.array([mine[s]["x"][k] - base[s]["x"][k] for s in seeds])
                se = float(d.std(ddof=1)) / math.sqrt(len(d))
                diff[f"{k:g}"] = [round(float(d.mean()), 2), round(se, 2)]
            row["minus_base"] = diff
        taken = [r["taken"] for r in mine.values() if r["taken"] is not None]
        row["taken_median_s"] = round(float(np.median(taken)), 2) if taken else None
        row["not_taken"] = sum(r["taken"] is None for r in mine.values())
        row["goals"] = [sum(r["goals"][0] for r in mine.values()), sum(r["goals"][1] for r in mine.values())]
        out.append(row)
    return out


def _run(job: tuple) -> dict:
    return kickoff_try(*job)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--teams", default="villa,villa:DeepKickoff",
                    help="teams taking the kickoff, comma-separated, the first the base "
                         "(default %(default)s)")
    ap.add_argument("--away", default="villa", help="the team they kick off against (default villa)")
    ap.add_argument("--tries", type=int, default=30, help="seeds a team (default 30)")
    ap.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    ap.add_argument("--seconds", type=float, default=90.0,
                    help="s of game time from the kickoff (default 90)")
    ap.add_argument("--size", type=int, default=11, help="players a side (default 11)")
    ap.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    args = ap.parse_args(argv)
    teams = [t.strip() for t in args.teams.split(",") if t.strip()]
    if not teams:
        ap.error(f"--teams: one or more teams, got {args.teams!r}")
    for t in (*teams, args.away):
        try:
            factory(t)
        except UnknownTeam as e:
            ap.error(str(e))
    if args.tries < 1 or args.seconds <= 0 or not 2 <= args.size <= 11 or args.workers < 1:
        ap.error(f"need --tries >= 1, --seconds > 0, --size 2-11 and --workers >= 1 (got {args.tries}, "
                 f"{args.seconds}, {args.size}, {args.workers})")
    jobs = [(t, args.away, args.seed + k, args.seconds, args.size) for k in range(args.tries) for t in teams]
    if args.workers == 1:
        rows = [_run(j) for j in jobs]
    else:
        with ProcessPoolExecutor(args.workers) as pool:
            rows = list(pool.map(_run, jobs))
    for row in summary(rows, teams):
        print(json.dumps({"benchmark": "kickoff", "away": args.away, "seed": args.seed, **row}), flush=True)
    print(json.dumps({"machine": machine()}), file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

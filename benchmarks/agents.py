"""Agent cost alone: a match's percepts replayed into fresh agents, timed per agent-cycle.

A match of `--home` against `--away` (11 vs 11, seed `--seed`) is played from the
kickoff for `--seconds` simulated seconds while every agent's percepts are
recorded, with the seed each agent was made with. The percepts are then fed again,
cycle by cycle and agent by agent as the match loop does, to new agents made with
the same seeds: each does exactly the work it did in the match, with no physics
between. Printed, per team: CPU time of `act` per agent-cycle (mean, median, p99;
vision frames included), the best of `--repeats` replays; and a hash of every
action, which a change meant to keep behavior must leave unchanged (issue 46's
"same seed, same match", without the physics' cost or noise).

    python -m benchmarks.agents [--home villa] [--away villa] [--seconds 20] [--seed 0] [--repeats 3]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import time

import numpy as np

from benchmarks.machine import machine
from cli.teams import UnknownTeam, factory
from models.rules import CYCLE, PlayMode
from server.match import Match, lineup_for


class _Recording:
    """An agent factory that remembers what it made each agent with."""

    def __init__(self, make) -> None:
        self.make, self.made = make, []

    def __call__(self, side, unum, robot_type, seed=0):
        self.made.append((side, unum, robot_type, seed))
        return self.make(side, unum, robot_type, seed)


def _hash_action(h, action) -> None:
    h.update(np.asarray(action.joint_velocities, dtype=float).tobytes())
    h.update(repr((action.say, action.beam)).encode())


def record(home: str, away: str, seconds: float, seed: int) -> tuple[list, list[list], int, str]:
    """(agent arguments, percepts per agent per cycle, the kickoff's cycle, the actions'
    hash): the beams and settling before the kickoff, then `seconds` of play."""
    chosen = {"L": factory(home), "R": factory(away)}
    teams = {s: _Recording(f) for s, f in chosen.items()}
    m = Match(teams["L"], teams["R"], lineup_for(chosen["L"], chosen["R"], 11, 11), half_time=300, seed=seed,
              team_names=(home, away))
    made = {(a[0], a[1]): a for t in teams.values() for a in t.made}
    args = [made[p.side, p.unum] for p in m.world.players]
    percepts: list[list] = [[] for _ in m.agents]
    act = m._act

    h = hashlib.sha256()

    def recorded(pcs):
        for i, p in enumerate(pcs):
            percepts[i].append(p)
        actions = act(pcs)
        for a in actions:
            _hash_action(h, a)
        return actions

    m._act = recorded
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # beam and settle: replayed, not timed
        m.step()
    kickoff = len(percepts[0])
    for _ in range(round(seconds / CYCLE)):
        m.step()
    return args, percepts, kickoff, h.hexdigest()[:16]


def replay(home: str, away: str, args: list, percepts: list[list], start: int) -> tuple[np.ndarray, str]:
    """CPU seconds of every agent-cycle from cycle `start` on (cycles, agents), and the hash of
    all the actions."""
    makers = {"L": factory(home), "R": factory(away)}
    agents = [makers[a[0]](*a) for a in args]
    n = len(percepts[0])
    cost = np.zeros((n, len(agents)))
    h = hashlib.sha256()
    clock = time.thread_time
    for k in range(n):
        for i, agent in enumerate(agents):
            t0 = clock()
            action = agent.act(percepts[i][k])
            cost[k, i] = clock() - t0
            _hash_action(h, action)
    return cost[start:], h.hexdigest()[:16]


def _figures(seconds: np.ndarray) -> dict[str, float]:
    """Mean, median and 99th percentile (us) of agent-cycle times given in s."""
    us = 1e6 * seconds.ravel()
    return {"mean": round(float(us.mean()), 1), "median": round(float(np.median(us)), 1),
            "p99": round(float(np.percentile(us, 99)), 1)}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", default="villa", help="left team (cli.teams name)")
    ap.add_argument("--away", default="villa", help="right team (cli.teams name)")
    ap.add_argument("--seconds", type=float, default=20.0, help="simulated seconds recorded from the kickoff")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--repeats", type=int, default=3, help="replays; the figures are the fastest one's")
    args = ap.parse_args(argv)
    if args.seconds <= 0 or args.repeats < 1:
        ap.error(f"--seconds must be > 0 and --repeats >= 1 (got {args.seconds}, {args.repeats})")
    try:
        factory(args.home), factory(args.away)
    except UnknownTeam as e:
        ap.error(str(e))
    made, percepts, kickoff, played = record(args.home, args.away, args.seconds, args.seed)
    runs = [replay(args.home, args.away, made, percepts, kickoff) for _ in range(args.repeats)]
    hashes = {played} | {h for _, h in runs}
    if len(hashes) != 1:
        raise SystemExit(f"the match and its replays disagree (actions {played} played, "
                         f"{[h for _, h in runs]} replayed): an agent is not a function of its seed "
                         "and percepts")
    cost = min((c for c, _ in runs), key=lambda c: c.mean())
    sides = np.array([a[0] for a in made])
    teams = {side: {"team": name, **_figures(cost[:, sides == side])}
             for side, name in (("L", args.home), ("R", args.away))}
    print(json.dumps({
        "benchmark": "agents", "sim_seconds": args.seconds, "seed": args.seed, "agents": len(made),
        "cycles": len(percepts[0]) - kickoff, "clock": "cpu (thread_time)",
        "us_per_agent_cycle": _figures(cost),
        "by_team": teams, "replays_mean_us": [round(1e6 * float(c.mean()), 1) for c, _ in runs],
        "actions_hash": runs[0][1], "machine": machine(),
    }))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

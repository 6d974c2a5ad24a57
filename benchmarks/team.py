"""The villa team in real matches: goals, falls, voting, time to the ball, speed.

Plays full matches through `server.match` (agents see only their percepts) and
prints one JSON line per match and one summary line per kind of match:

* villa against posture (`--games`, different seeds): goals for and against, own goals;
* villa against villa: goals, falls per player per minute, touches, possession;
* voting synchrony: the share of decision cycles in which every field player of a
  team follows the same role mapping, with voting and without (one villa against
  posture match each, `--sync-half-time` s halves);
* on the ball: time from becoming the on-ball player to that player's first touch of
  the ball (median, p90; episodes in which the role moved on first are counted apart),
  kicks begun and kicks that moved the ball at least 1 m;
* speed: real-time factor, mean and p99 wall time of one agent's cycle (villa players).

    python -m benchmarks.team [--games 4] [--half-time 300] [--workers 2] [--seed 0]
                              [--only posture|villa|sync]

Measured 2026-12-04 (defaults, 2-core AMD EPYC shared with other jobs, so the times
are pessimistic): villa against posture 6:0, 7:0, 8:0, 7:0 (goal difference 7.0 +- 0.41),
falls 0.29 per player-minute, 10.8 kicks begun a match (10.2 moved the ball 1 m);
villa against villa 1:0, 1:0, 2:0, 1:0 (every goal by the left team), 99.5 touches and
4 kicks a match; time from on-ball to its own first touch median 9.6 s (p90 24 s)
against posture and 9.2 s (p90 16.6 s) against villa; voting synchrony 100% with voting
and 97.4% without (the paper: 100% and 36%); 1.07-1.17x real time, 0.66-1.0 ms wall per
villa player-cycle then. After issue 46's speed rounds (every match bit for bit the same),
`--only villa --games 2 --workers 2`: 1:0 and 1:0 (both by the left team again), 2.14x and
2.15x real time, 262 us mean and 886 us p99 wall per villa player-cycle, on-ball to touch
median 9.2 s (p90 16.1 s), voting synchrony 100%.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace

import numpy as np

from agent.kicker import KICK
from agent.player import Player
from agent.posture import PostureAgent
from agent.teamconfig import VILLA
from benchmarks.machine import machine
from models.rules import PlayMode
from optimization.executor import one_thread
from server.match import Match

KICK_MOVED = 1.0  # m the ball must move within 3 s of a kick's start for the kick to count


class Timed:
    """An agent with a stopwatch on `act` (wall s per call)."""

    def __init__(self, agent) -> None:
        self.agent = agent
        self.times: list[float] = []

    def act(self, percept):
        t0 = time.perf_counter()
        out = self.agent.act(percept)
        self.times.append(time.perf_counter() - t0)
        return out


def _team(name: str, voting: bool = True):
    if name == "posture":
        return PostureAgent
    config = replace(VILLA, voting=voting)
    return lambda side, unum, robot_type, seed: Player(side, unum, robot_type, seed, config)


def play(home: str, away: str, seed: int, half_time: float, voting: bool = True) -> dict:
    """One match with the instruments; returns its figures."""
    m = Match(_team(home, voting), _team(away, voting), half_time=half_time, seed=seed,
              team_names=(home, away))
    m.agents = [Timed(a) for a in m.agents]
    w = m.world
    players = [a.agent for a in m.agents]
    villa = [i for i, a in enumerate(players) if isinstance(a, Player)]
    sides = {i: w.players[i].side for i in villa}
    on_since: dict[int, float | None] = {i: None for i in villa}
    waits: list[float] = []
    episode: dict[int, float | None] = {i: None for i in villa}  # when each became on-ball, untouched
    lost = 0
    kicks = {"L": [0, 0], "R": [0, 0]}  # begun, moved the ball
    kick_watch: list[tuple[float, str, np.ndarray]] = []
    last_state = {i: None for i in villa}
    sync = {"L": [0, 0], "R": [0, 0]}  # decision cycles with one mapping, all decision cycles
    touched = dict(m.referee.touches)
    start = time.perf_counter()
    while m.referee.mode != PlayMode.GAME_OVER:
        m.step()
        now = w.time
        counts = dict(m.referee.touches)
        toucher = m.referee.last_touch if counts != touched else None
        touched = counts
        for i in villa:
            a = players[i]
            s = a.on_ball_since
            if s is not None and on_since[i] is None:
                episode[i] = s
            elif s is None and episode[i] is not None:
                lost += 1  # the role went to another player (or the play stopped) before a touch
                episode[i] = None
            if toucher == i and episode[i] is not None:
                waits.append(now - episode[i])
                episode[i] = None
            on_since[i] = s
            k = a.body.kicker.state if a.body.kicking else None
            if k == KICK and last_state[i] != KICK:
                kicks[sides[i]][0] += 1
                kick_watch.append((now, sides[i], w.ball_position()[:2].copy()))
            last_state[i] = k
        for entry in list(kick_watch):
            if now - entry[0] >= 3.0:
                kick_watch.remove(entry)
                moved = float(np.hypot(*(w.ball_position()[:2] - entry[2])))
                kicks[entry[1]][1] += moved >= KICK_MOVED
        if m.cycle % 5 == 0 and m.referee.mode == PlayMode.PLAY_ON:
            for team in ("L", "R"):
                maps = [players[i].mapping for i in villa if sides[i] == team and players[i].unum != 1]
                maps = [mp for mp in maps if mp is not None]
                if len(maps) > 1:
                    sync[team][1] += 1
                    sync[team][0] += all(mp == maps[0] for mp in maps)
    wall = time.perf_counter() - start
    r = m.result(wall).to_dict()
    times = np.concatenate([m.agents[i].times for i in villa]) if villa else np.zeros(1)
    minutes = 2 * half_time / 60.0
    n = {"L": len(m.lineup.left), "R": len(m.lineup.right)}
    own = sum(1 for e in r["events"] if e["kind"] == "goal" and "own goal" in e["detail"])
    return {
        "home": home, "away": away, "seed": seed, "half_time": half_time, "voting": voting,
        "score": r["score"], "own_goals": own, "wall_seconds": round(wall, 1),
        "real_time_factor": round(2 * half_time / wall, 2),
        "falls_per_player_minute": {t: round(r["stats"][t]["falls"] / (n[t] * minutes), 3) for t in "LR"},
        "touches": {t: r["stats"][t]["ball_touches"] for t in "LR"},
        "possession": {t: r["stats"][t]["possession_share"] for t in "LR"},
        "kicks_begun": {t: kicks[t][0] for t in "LR"}, "kicks_moved_ball": {t: kicks[t][1] for t in "LR"},
        "on_ball_to_touch_s": [round(x, 2) for x in waits], "on_ball_lost_before_touch": lost,
        "voting_sync": {t: round(sync[t][0] / sync[t][1], 3) if sync[t][1] else None for t in "LR"},
        "agent_us_mean": round(1e6 * float(np.mean(times)), 1),
        "agent_us_p99": round(1e6 * float(np.percentile(times, 99)), 1),
        "timing": r["timing"],
    }


def summary(kind: str, rows: list[dict]) -> dict:
    """Means over matches; goals from the villa (home) side."""
    gf = [r["score"]["L"] for r in rows]
    ga = [r["score"]["R"] for r in rows]
    waits = [w for r in rows for w in r["on_ball_to_touch_s"]]
    out = {
        "benchmark": "team", "kind": kind, "matches": len(rows),
        "goals_for_mean": round(float(np.mean(gf)), 2), "goals_against_mean": round(float(np.mean(ga)), 2),
        "goal_difference_mean": round(float(np.mean(np.subtract(gf, ga))), 2),
        "goal_difference_se": round(float(np.std(np.subtract(gf, ga), ddof=1) / math.sqrt(len(rows))), 2)
        if len(rows) > 1 else None,
        "matches_with_a_goal": sum(1 for a, b in zip(gf, ga) if a + b > 0),
        "own_goals": sum(r["own_goals"] for r in rows),
        "falls_per_player_minute": round(float(np.mean([r["falls_per_player_minute"]["L"]
                                                         for r in rows])), 3),
        "touches_per_match": round(float(np.mean([r["touches"]["L"] for r in rows])), 1),
        "possession": round(float(np.mean([r["possession"]["L"] for r in rows])), 3),
        "kicks_begun_per_match": round(float(np.mean([r["kicks_begun"]["L"] for r in rows])), 1),
        "kicks_moved_ball_per_match": round(float(np.mean([r["kicks_moved_ball"]["L"] for r in rows])), 1),
        "on_ball_to_touch_median_s": round(float(np.median(waits)), 2) if waits else None,
        "on_ball_to_touch_p90_s": round(float(np.percentile(waits, 90)), 2) if waits else None,
        "on_ball_touched_share": round(len(waits) / max(1, len(waits) + sum(r["on_ball_lost_before_touch"]
                                                                          for r in rows)), 3),
        "real_time_factor_mean": round(float(np.mean([r["real_time_factor"] for r in rows])), 2),
        "agent_us_mean": round(float(np.mean([r["agent_us_mean"] for r in rows])), 1),
        "agent_us_p99": round(float(np.max([r["agent_us_p99"] for r in rows])), 1),
        "machine": machine(),
    }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--games", type=int, default=4, help="matches of each kind")
    ap.add_argument("--half-time", type=float, default=300.0)
    ap.add_argument("--sync-half-time", type=float, default=60.0)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", choices=("posture", "villa", "sync"))
    args = ap.parse_args()
    if args.games < 1 or args.half_time <= 0 or args.workers < 1 or not math.isfinite(args.half_time):
        ap.error("--games and --workers must be >= 1 and --half-time a positive number")
    jobs = []
    for kind in ("posture", "villa"):
        if args.only in (None, kind):
            jobs += [(kind, ("villa", kind, args.seed + g, args.half_time, True)) for g in range(args.games)]
    if args.only in (None, "sync"):
        jobs += [("sync", ("villa", "posture", args.seed, args.sync_half_time, v)) for v in (True, False)]
    rows: dict[str, list[dict]] = {}
    with ProcessPoolExecutor(args.workers, initializer=one_thread) as pool:
        futures = [(kind, pool.submit(play, *a)) for kind, a in jobs]
        for kind, f in futures:
            row = f.result()
            print(json.dumps({"benchmark": "team", "kind": kind, **row}), flush=True)
            rows.setdefault(kind, []).append(row)
    for kind in ("posture", "villa"):
        if kind in rows:
            print(json.dumps(summary(f"villa-vs-{kind}", rows[kind])), flush=True)
    if "sync" in rows:
        s = {("with" if r["voting"] else "without"): r["voting_sync"]["L"] for r in rows["sync"]}
        print(json.dumps({"benchmark": "team", "kind": "voting-sync", "share_one_mapping": s,
                          "paper": {"with": 1.0, "without": 0.36}, "machine": machine()}), flush=True)


if __name__ == "__main__":
    main()

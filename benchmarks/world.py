"""Speed of the MuJoCo world: 11 vs 11 agents (posture by default) for 60 simulated seconds.

Prints one JSON line: the real-time factor of the whole loop and of physics plus
server (everything but the agents), wall seconds per part of the loop ("vision"
is the part of "sensors" spent computing vision percepts), the vision time per
frame (all 22 players' percepts of one vision cycle) and the mean time of one
MuJoCo step. Goal (issue 2): physics plus server at least 8x real time on one core.

This machine's speed drifts by 10-20% from minute to minute (other tenants; the
work does not change: callgrind counts 6.6 million instructions per physics step
run after run), so `--repeats N` times N windows of `--seconds` one after
another in the same match and adds each window's physics-plus-server factor,
their median and their best; the other figures are over all windows.

`--home` and `--away` name the teams (`cli.teams`; posture by default) and
`--players` the players a side; the line then also gives each team's agent cost
(us per agent per cycle, wall). `--stages` times the parts of an agent's cycle
(world model, particle filter, ball filter, perception, decision, body, walk
engine, IK, IMU, motion) with light timers round their functions and prints a
second JSON line, `world_agent_stages`: per team and stage, the wall us per
agent cycle (or, with `--clock cpu`, this thread's CPU time, steadier on a shared
machine), inclusive (a stage's time holds that of the stages it calls: the
world model holds the particle and ball filters, perception and its IMU; the
body holds the walk engine, IK, motion and its IMUs). The timers add about 0.3
us a call, so the totals run a little above an untimed run's.

    python -m benchmarks.world [--seconds 60] [--repeats 1] [--seed 0]
    python -m benchmarks.world --home villa --away villa --seconds 20 --stages

Figures, villa against villa (2 cores AMD EPYC, 2026-12-04, `--clock cpu`; us per
agent cycle; the first 60 s, `--seconds 60 --stages`), before -> after issue 46's
second round (compiled walk, tilt estimate, ball filter, perception, particle filter;
the decision layer's Python trimmed; every match bit for bit the same):

    agent 744 -> 294 (untimed; with the stage timers ~360), world model 384 -> 139,
    particle filter 162 -> 53, ball filter 65 -> 9, perception 27 -> 10, see players
    33 -> 7, hear 20 -> 12, decision 125 -> ~100, body 202 -> 94 (walk + IK + motion
    137 -> 32 in one compiled walk_step), IMU 24 -> 13.

Real-time factor, first 60 s: 1.0 -> 2.03 (quiet machine). Whole match, `--seconds 60
--repeats 10`: 1.75 (agents 345 us, physics 91 s; load from other work) and 1.56 (385
us, physics 101 s: the machine ran 11% slower) against 1.16 (626 us) before; physics
alone is 5.9-6.6x real time and physics plus server 4.7-5.3x, so physics is now a third
of a match's time.

Third round (hearing routed in one compiled pass; the decision layer's formation
lookup, walking costs, collision avoidance and marking compiled; bit for bit the same),
whole match, `--seconds 60 --repeats 10 --clock cpu`, quiet machine: 2.16x real time
(277.8 s wall), agents 268 us a cycle, physics 86.0 s (6.97x alone), server 16.3 s
(sensors and hearing 9.0, vision 3.3, effectors 2.4, referee 1.6; hearing alone went
481 -> 82 us a cycle); `benchmarks.team --only villa --games 2 --workers 2`: 2.14x and
2.15x, agents 262 us mean and 886 us p99 (wall).

On a faster machine of the same kind (2 cores AMD EPYC, December 6, 2026, quiet; every
figure about 1.7x the ones above), whole match, `--home villa --away villa --seconds 60
--repeats 10`: 6.25x real time (96.0 s wall), physics 39.8 s (15.1x alone, 332 us a
step), physics plus server 13.5x, agents 51.1 s (77.5 us a cycle, wall): the match takes
2.4x its physics alone. The first 60 s with `--stages --clock cpu`: agent 83-91 us, world
model 39-42 (particle filter 16, hearing 3.5, perception 3.2, IMU 3.2, ball filter 2.7),
decision 14-15, body 22-24 (walk_step 8). Batches there: 24 games of villa:Soft against
villa on 2 workers took 107 s of wall time each, about 67 games an hour (80 of
villa:LowStep against villa: 70 minutes); `benchmarks.team --only villa --games 2 --workers
2`: 5.72x real time a match, agents 86.1 us mean and 292 us p99 (wall).

Where a physics step goes (MuJoCo's own timers, villa against villa 30 s into a match, 22
robots, nv 630, 62 contacts, 246 constraint rows in 23 islands; December 2026): 566 us a
step, of which the constraint solver 261 (Newton, 1.28 iterations on average), positions
198 (collision 64, kinematics 58, making the constraints 44, inertia 32), the integrator
51, velocities 31, actuation 10. Other solver settings, timed on the same saved state: CG
731 us, PGS 732, dense Jacobians 902, islands off 584, tolerance 1e-5 559, at most 5
iterations 556, Euler damping off 552. None buys the quarter the bare box scene suggests;
the Newton solver on islands is already the fastest, and the rest is the contacts and
bodies themselves.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from benchmarks.machine import machine
from cli.teams import factory
from models.rules import VISION_PERIOD, PlayMode
from server.match import Match, lineup_for


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="simulated seconds to time")
    ap.add_argument("--repeats", type=int, default=1, help="timed windows of --seconds, one after another")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--home", default="posture", help="left team (cli.teams name)")
    ap.add_argument("--away", default="posture", help="right team (cli.teams name)")
    ap.add_argument("--players", type=int, default=11, help="players a side (1-11)")
    ap.add_argument("--stages", action="store_true", help="time the stages of an agent's cycle")
    ap.add_argument("--clock", choices=("wall", "cpu"), default="wall",
                    help="clock of the per-team and per-stage agent times: wall, or this thread's "
                         "CPU time (steadier on a machine shared with other work)")
    args = ap.parse_args()
    if args.seconds <= 0 or args.repeats < 1:
        ap.error(f"--seconds must be > 0 and --repeats >= 1 (got {args.seconds}, {args.repeats})")
    if not 1 <= args.players <= 11:
        ap.error(f"--players must be 1 to 11 (got {args.players})")
    try:
        teams = {"L": factory(args.home), "R": factory(args.away)}
        lineup = lineup_for(teams["L"], teams["R"], args.players, args.players, (args.home, args.away))
    except ValueError as e:  # an unknown team (UnknownTeam) or robot types against the rule
        ap.error(str(e))
    m = Match(teams["L"], teams["R"], lineup,
              half_time=10 * args.seconds * args.repeats, seed=args.seed,
              team_names=(args.home, args.away))
    clock = TeamClock(m, time.thread_time if args.clock == "cpu" else time.perf_counter)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # beam and settle, untimed
        m.step()
    stages = StageTimers(clock) if args.stages else None
    clock.reset()
    cycles = round(args.seconds / 0.02)
    frames, wall, windows, totals = 0, 0.0, [], {}
    for _ in range(args.repeats):
        m.timing.__init__()
        start = time.perf_counter()
        for _ in range(cycles):
            frames += m.cycle % VISION_PERIOD == 0
            m.step()
        wall += time.perf_counter() - start
        t = m.timing.as_dict()
        windows.append(round(args.seconds / server_seconds(t), 2))
        totals = {k: totals.get(k, 0.0) + v for k, v in t.items()}
    t = {k: round(v, 3) for k, v in totals.items()}
    sim = args.seconds * args.repeats
    all_cycles = cycles * args.repeats
    print(json.dumps({
        "benchmark": "world", "players": len(m.world.players), "sim_seconds": sim,
        "timestep": m.world.model.opt.timestep, "wall_seconds": round(wall, 2),
        "real_time_factor": round(sim / wall, 2),
        "physics_plus_server_factor": round(sim / server_seconds(t), 2),
        "physics_factor": round(sim / t["physics"], 2),
        "windows_physics_plus_server_factor": windows,
        "median_window": float(np.median(windows)), "best_window": max(windows),
        "seconds": t, "vision_ms_per_frame": round(1e3 * t["vision"] / max(frames, 1), 3),
        "physics_us_per_step": round(1e6 * t["physics"] / (all_cycles * m.world.substeps), 1),
        "us_per_agent_cycle": round(1e6 * t["agents"] / (all_cycles * len(m.agents)), 1),
        "teams": {"L": args.home, "R": args.away}, "agent_clock": args.clock,
        "us_per_agent_cycle_by_team": clock.us_per_agent_cycle(all_cycles),
        "contacts": int(m.world.data.ncon), "machine": machine(),
    }))
    if stages is not None:
        stages.remove()
        print(json.dumps({
            "benchmark": "world_agent_stages", "teams": {"L": args.home, "R": args.away},
            "agent_clock": args.clock,
            "sim_seconds": sim, "us_per_agent_cycle": stages.table(clock, all_cycles),
            "machine": machine(),
        }))


class TeamClock:
    """Wall time of each team's agents: every agent's `act` is wrapped with a timer, and
    `current` names the team whose agent is acting (for `StageTimers`)."""

    def __init__(self, m: Match, now=time.perf_counter) -> None:
        self.now = now
        self.side = [p.side for p in m.world.players]
        self.count = {s: self.side.count(s) for s in ("L", "R")}
        self.seconds = {"L": 0.0, "R": 0.0}
        self.current = "L"
        for i, agent in enumerate(m.agents):
            agent.act = self._timed(agent.act, self.side[i])

    def _timed(self, act, side: str):
        def timed(percept):
            self.current = side
            t0 = self.now()
            try:
                return act(percept)
            finally:
                self.seconds[side] += self.now() - t0
        return timed

    def reset(self) -> None:
        self.seconds = {"L": 0.0, "R": 0.0}

    def us_per_agent_cycle(self, cycles: int) -> dict[str, float]:
        return {s: round(1e6 * self.seconds[s] / (cycles * self.count[s]), 1) for s in ("L", "R")}


# (stage, module, class or None, function): the functions timed per stage.
STAGES = (
    ("world_model", "agent.worldmodel", "WorldModel", "update"),
    ("particle_filter", "agent.localization", "ParticleFilter", "predict"),
    ("particle_filter", "agent.localization", "ParticleFilter", "update"),
    ("ball_filter", "agent.ballfilter", "BallFilter", "predict"),
    ("ball_filter", "agent.ballfilter", "BallFilter", "update"),
    ("perception", "agent.worldmodel", None, "observe"),
    ("see_players", "agent.worldmodel", "WorldModel", "_see_players"),
    ("hear", "agent.worldmodel", "WorldModel", "_hear"),
    ("decision", "agent.player", "Player", "view"),
    ("decision", "agent.player", "Player", "decide"),
    ("body", "agent.body", "Body", "execute"),
    ("walk_step", "skills.motion", "Motion", "walk_step"),  # tilt, walk and joint command: one compiled call
    ("walk_engine", "skills.walk", "WalkEngine", "update"),  # outside walk_step's compiled path
    ("ik", "skills.ik", "LegIK", "solve"),
    ("imu", "skills.imu", "TiltEstimator", "update"),
    ("motion_command", "skills.motion", "Motion", "command"),
)


class StageTimers:
    """Wall time per (team, stage), by wrapping the functions of `STAGES` with timers."""

    def __init__(self, clock: TeamClock) -> None:
        import importlib

        self.seconds: dict[tuple[str, str], float] = {}
        self.calls: dict[tuple[str, str], int] = {}
        self._saved = []
        for stage, module, cls, name in STAGES:
            owner = importlib.import_module(module)
            if cls is not None:
                owner = getattr(owner, cls)
            fn = getattr(owner, name)
            self._saved.append((owner, name, fn))
            setattr(owner, name, self._timed(fn, stage, clock))

    def _timed(self, fn, stage: str, clock: TeamClock):
        seconds, calls, now = self.seconds, self.calls, clock.now

        def timed(*args, **kwargs):
            t0 = now()
            try:
                return fn(*args, **kwargs)
            finally:
                key = (clock.current, stage)
                seconds[key] = seconds.get(key, 0.0) + now() - t0
                calls[key] = calls.get(key, 0) + 1
        return timed

    def remove(self) -> None:
        for owner, name, fn in reversed(self._saved):
            setattr(owner, name, fn)

    def table(self, clock: TeamClock, cycles: int) -> dict[str, dict[str, float]]:
        """{team side: {stage: us per agent cycle}}, with the agent's whole cycle as 'agent'."""
        out = {}
        for side in ("L", "R"):
            n = cycles * clock.count[side]
            row = {"agent": round(1e6 * clock.seconds[side] / n, 1)}
            for stage, *_ in STAGES:
                if (side, stage) in self.seconds:
                    row[stage] = round(1e6 * self.seconds[side, stage] / n, 1)
            out[side] = row
        return out


def server_seconds(t: dict[str, float]) -> float:
    """Wall seconds of physics plus server (everything but the agents and the log)."""
    return t["physics"] + t["sensors"] + t["effectors"] + t["referee"]


if __name__ == "__main__":
    main()

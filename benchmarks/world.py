"""Speed of the MuJoCo world: 11 vs 11 posture agents for 60 simulated seconds.

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

    python -m benchmarks.world [--seconds 60] [--repeats 1] [--seed 0]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from agent.posture import PostureAgent
from benchmarks.machine import machine
from models.rules import VISION_PERIOD, PlayMode
from server.match import Match


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="simulated seconds to time")
    ap.add_argument("--repeats", type=int, default=1, help="timed windows of --seconds, one after another")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    if args.seconds <= 0 or args.repeats < 1:
        ap.error(f"--seconds must be > 0 and --repeats >= 1 (got {args.seconds}, {args.repeats})")
    m = Match(PostureAgent, PostureAgent, half_time=10 * args.seconds * args.repeats, seed=args.seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # beam and settle, untimed
        m.step()
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
        "contacts": int(m.world.data.ncon), "machine": machine(),
    }))


def server_seconds(t: dict[str, float]) -> float:
    """Wall seconds of physics plus server (everything but the agents and the log)."""
    return t["physics"] + t["sensors"] + t["effectors"] + t["referee"]


if __name__ == "__main__":
    main()

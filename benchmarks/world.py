"""Speed of the MuJoCo world: 11 vs 11 posture agents for 60 simulated seconds.

Prints one JSON line: the real-time factor of the whole loop and of physics plus
server (everything but the agents), wall seconds per part of the loop ("vision"
is the part of "sensors" spent computing vision percepts), the vision time per
frame (all 22 players' percepts of one vision cycle) and the mean time of one
MuJoCo step. Goal (issue 2): physics plus server at least 8x real time on one core.

    python -m benchmarks.world [--seconds 60] [--seed 0]
"""

from __future__ import annotations

import argparse
import json
import time

from agent.posture import PostureAgent
from benchmarks.machine import machine
from models.rules import VISION_PERIOD, PlayMode
from server.match import Match


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=60.0, help="simulated seconds to time")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    m = Match(PostureAgent, PostureAgent, half_time=10 * args.seconds, seed=args.seed)
    while m.referee.mode == PlayMode.BEFORE_KICK_OFF:  # beam and settle, untimed
        m.step()
    m.timing.__init__()
    cycles = round(args.seconds / 0.02)
    frames = 0
    start = time.perf_counter()
    for _ in range(cycles):
        frames += m.cycle % VISION_PERIOD == 0
        m.step()
    wall = time.perf_counter() - start
    t = m.timing.as_dict()
    server = t["physics"] + t["sensors"] + t["effectors"] + t["referee"]
    print(json.dumps({
        "benchmark": "world", "players": len(m.world.players), "sim_seconds": args.seconds,
        "timestep": m.world.model.opt.timestep, "wall_seconds": round(wall, 2),
        "real_time_factor": round(args.seconds / wall, 2),
        "physics_plus_server_factor": round(args.seconds / server, 2),
        "physics_factor": round(args.seconds / t["physics"], 2),
        "seconds": t, "vision_ms_per_frame": round(1e3 * t["vision"] / max(frames, 1), 3),
        "physics_us_per_step": round(1e6 * t["physics"] / (cycles * m.world.substeps), 1),
        "us_per_agent_cycle": round(1e6 * t["agents"] / (cycles * len(m.agents)), 1),
        "contacts": int(m.world.data.ncon), "machine": machine(),
    }))


if __name__ == "__main__":
    main()

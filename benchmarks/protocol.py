"""Cost of the league's protocol per cycle: format + parse of every agent's percept and action.

Run: python -m benchmarks.protocol [--home N] [--away N] [--cycles C] [--repeats R]
The last line is the monitor port's cost per update (server.monitor): with no monitor
connected (one select) and with one reading monitor (kinematics, format, send).
Prints JSON lines: the machine, then microseconds per agent (percept format, percept
parse, action format, action parse; vision cycles and others apart, and their mean over
the 3-cycle vision period) and the whole protocol's cost per 20 ms cycle for every agent
on both ends (server and clients), with message sizes. Percepts come from a real
N vs N posture match; the clock is the best of `repeats` passes.
"""

from __future__ import annotations

import argparse
import json
import time

from benchmarks.machine import machine
from models.rules import VISION_PERIOD


def best_us(fn, items, repeats: int) -> float:
    """Best-of-`repeats` mean microseconds of fn(item) over items."""
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        for it in items:
            fn(it)
        best = min(best, (time.perf_counter() - t0) / len(items))
    return best * 1e6


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", type=int, default=11)
    ap.add_argument("--away", type=int, default=11)
    ap.add_argument("--cycles", type=int, default=6, help="cycles of percepts to time (default 6)")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    print(json.dumps({"machine": machine()}), flush=True)

    from agent.posture import PostureAgent
    from models.scene import Lineup
    from server.match import Match
    from server.protocol import PerceptParser, format_action, format_percept, parse_agent_message, velocities

    m = Match(PostureAgent, PostureAgent, Lineup.default(args.home, args.away), seed=0)
    for _ in range(60):  # past the beams, standing
        m.step()
    while m.cycle % VISION_PERIOD:
        m.step()
    samples = {"vision": [], "other": []}
    for _ in range(args.cycles):
        ps = m.percepts()
        acts = [a.act(p) for a, p in zip(m.agents, ps)]
        for p, a in zip(ps, acts):
            samples["vision" if p.vision is not None else "other"].append((p, a))
        m.step()
    out = {"players": len(m.agents)}
    for kind, items in samples.items():
        texts = [format_percept(p, "Home", "Away") for p, _ in items]
        parsers = [PerceptParser("Home", p.robot_type) for p, _ in items]
        atexts = [format_action(a, p.robot_type) for p, a in items]
        fp = best_us(lambda pa: format_percept(pa[0], "Home", "Away"), items, args.repeats)
        pp = best_us(lambda pt: pt[0].parse(pt[1]), list(zip(parsers, texts)), args.repeats)
        fa = best_us(lambda pa: format_action(pa[1], pa[0].robot_type), items, args.repeats)
        pa = best_us(lambda tt: velocities(parse_agent_message(tt[0]), tt[1]),
                     [(t, p.robot_type) for t, (p, _) in zip(atexts, items)], args.repeats)
        out[kind] = {"format_percept_us": round(fp, 1), "parse_percept_us": round(pp, 1),
                     "format_action_us": round(fa, 1), "parse_action_us": round(pa, 1),
                     "total_us": round(fp + pp + fa + pa, 1),
                     "percept_bytes": round(sum(map(len, texts)) / len(texts)),
                     "action_bytes": round(sum(map(len, atexts)) / len(atexts))}
    v, o = out["vision"], out["other"]
    mean = (v["total_us"] + (VISION_PERIOD - 1) * o["total_us"]) / VISION_PERIOD
    out["mean_per_agent_cycle_us"] = round(mean, 1)
    out["per_cycle_all_agents_ms"] = round(mean * len(m.agents) / 1000, 2)
    out["server_side_per_cycle_ms"] = round(len(m.agents) / 1000 * (
        (v["format_percept_us"] + v["parse_action_us"]
         + (VISION_PERIOD - 1) * (o["format_percept_us"] + o["parse_action_us"])) / VISION_PERIOD), 2)
    print(json.dumps(out), flush=True)
    print(json.dumps(monitor_cost(m, 50)), flush=True)


def monitor_cost(m, updates: int) -> dict:
    """Microseconds per monitor update of Match m (no monitor / one reading monitor)."""
    import socket
    import threading

    from server.monitor import MonitorServer, game_state
    from server.protocol import encode_frame

    mon = MonitorServer(port=0)
    try:
        t0 = time.perf_counter()
        for _ in range(updates):
            mon.update(m)
        idle = (time.perf_counter() - t0) / updates
        sock = socket.create_connection(mon.address, timeout=10)

        def drain():
            while True:
                try:
                    data = sock.recv(1 << 20)
                except OSError:
                    return
                if not data:
                    return
        th = threading.Thread(target=drain, daemon=True)
        th.start()
        while not mon.clients:
            mon.poll(m)
        mon.update(m)  # the full graph
        t0 = time.perf_counter()
        for _ in range(updates):
            mon.update(m)
        busy = (time.perf_counter() - t0) / updates
        scene = mon.scene
        delta = len(encode_frame(game_state(m, False) + scene.graph(False)))
        full = len(encode_frame(game_state(m, True) + scene.graph(True)))
    finally:
        mon.close()
    return {"monitor": {"robots": len(m.world.players), "no_monitor_us": round(idle * 1e6, 1),
                        "one_monitor_us": round(busy * 1e6, 1), "delta_bytes": delta,
                        "full_bytes": full}}


if __name__ == "__main__":
    main()

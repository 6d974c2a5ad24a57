"""IK kicks in physics: distance, direction error and success per kick and robot type.

    python -m benchmarks.ikkick [--types 0,1] [--kicks ik_forward_left,...] [--tries 10] [--seed 0]
                                [--jitter 0.01] [--params FILE ...]

One JSON line per kick and type. Each try: a robot (Trainer, no referee) stands
0.5 s at the origin, the ball is put at the kick's `spec.ball` plus a seeded
uniform offset within +-jitter (m) on x and y, the kick is reset with the ball's
true offset (robot frame) and played from percepts only; then the robot stands
while the ball rolls to a stop (at most `--roll` s; the rest is extrapolated by
`World.ball_rest_position`). Figures: distance the ball moved (m), direction
error (deg, against `spec.direction`), success (the ball's displacement along
the kick's direction is at least 1 m and the robot did not fall) and falls. The
kick never reads simulator state; the trial does, for the figures.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time
import zlib

import numpy as np

from benchmarks.walk import new_robot
from models.messages import Action
from skills.ikkick import IkKick, ik_kicks


def _wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def kick_trial(t: int, kick: IkKick, offset: tuple[float, float] = (0.0, 0.0), roll: float = 3.0,
               stand: float = 0.5) -> dict:
    """One kick in physics; returns distance (m), direction (rad, robot frame at the start),
    along (m, displacement along spec.direction), fell, contact time (s)."""
    tr, mo = new_robot(t)
    w = tr.world
    for _ in range(round(stand / 0.02)):
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
    x0, y0, h0 = w.player_pose(0)
    c, s = math.cos(h0), math.sin(h0)
    bx, by = kick.spec.ball[0] + offset[0], kick.spec.ball[1] + offset[1]
    w.place_ball((x0 + c * bx - s * by, y0 + s * bx + c * by))
    b0 = w.ball_position()[:2].copy()
    kick.reset((bx, by))
    fell = False
    while not kick.done:
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.command(kick.step(pc), pc))})
        if w.torso_up()[0] < 0.5:
            fell = True
            break
    mo.reset()
    n = round(roll / 0.02)
    for _ in range(n):
        if fell or np.linalg.norm(w.ball_velocity()[:2]) < 0.02:
            break
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        if w.torso_up()[0] < 0.5:
            fell = True
    d = w.ball_rest_position() - b0  # a ball still rolling is carried on to its stop
    dx, dy = c * d[0] + s * d[1], -s * d[0] + c * d[1]
    dist = math.hypot(dx, dy)
    direction = math.atan2(dy, dx)
    a = kick.spec.direction
    along = dx * math.cos(a) + dy * math.sin(a)
    return {"distance": dist, "direction": direction, "along": along, "fell": fell,
            "error": abs(_wrap(direction - a))}


def run(types, names, tries, seed, jitter, params, roll) -> list[dict]:
    out = []
    for t in types:
        kicks = ik_kicks(t, params)
        for name in names or list(kicks):
            kick = kicks[name]
            rng = np.random.default_rng([seed, t, zlib.crc32(name.encode())])
            res = []
            t0 = time.perf_counter()
            for _ in range(tries):
                off = tuple(rng.uniform(-jitter, jitter, 2))
                res.append(kick_trial(t, kick, off, roll))
            dist = np.array([r["distance"] for r in res])
            err = np.degrees([r["error"] for r in res])
            ok = [r["along"] >= 1.0 and not r["fell"] for r in res]
            line = {"kick": name, "type": t, "tries": tries, "jitter_m": jitter,
                    "distance_mean_m": round(float(dist.mean()), 3),
                    "distance_std_m": round(float(dist.std()), 3),
                    "direction_error_mean_deg": round(float(err.mean()), 1),
                    "success_rate": round(sum(ok) / tries, 2),
                    "falls": sum(r["fell"] for r in res),
                    "seconds": round(time.perf_counter() - t0, 1),
                    "machine": f"{platform.node()} {platform.processor() or platform.machine()}"}
            print(json.dumps(line), flush=True)
            out.append(line)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--types", default="0")
    ap.add_argument("--kicks", default="")
    ap.add_argument("--tries", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jitter", type=float, default=0.01)
    ap.add_argument("--roll", type=float, default=3.0)
    ap.add_argument("--params", nargs="*", default=[])
    a = ap.parse_args()
    run([int(x) for x in a.types.split(",")], [k for k in a.kicks.split(",") if k], a.tries, a.seed,
        a.jitter, a.params, a.roll)


if __name__ == "__main__":
    main()

"""IK kicks in physics: distance, direction error and success per kick and robot type.

    python -m benchmarks.ikkick [--types 0,1] [--kicks ik_forward_left,...] [--tries 10] [--seed 0]
                                [--jitter 0.01] [--params FILE ...]

One JSON line per kick and type. Each try: a robot (Trainer, no referee) stands
0.5 s at the origin, the ball is put at the kick's `spec.ball` plus a seeded
uniform offset within +-jitter (m) on x and y, the kick is reset with the ball's
true offset (robot frame) and played from percepts only; then the robot stands
while the ball rolls to a stop (at most `--roll` s; the rest is extrapolated by
`World.ball_rest_position`). Figures: distance the ball moved (m), direction
error (deg, against `spec.direction`: the mean of its size, and its signed mean
(the bias, + to the left) and standard deviation, which tell aim from scatter),
success (the ball's displacement along the kick's direction is at least 1 m and
the robot did not fall), falls, and the backswing's clearance of the ball at the
spec's offset (mm, kinematics: `backswing_clearance`; below zero the foot grazes
the ball before the strike). The kick never reads simulator state; the trial
does, for the figures.
"""

from __future__ import annotations

import argparse
import json
import platform
import time
import zlib

import numpy as np

from optimization.trials import backswing_clearance, kick_trial
from skills.kicks.ik import ik_kicks


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
            dev = np.degrees([r["deviation"] for r in res])
            ok = [r["along"] >= 1.0 and not r["fell"] for r in res]
            line = {"kick": name, "type": t, "tries": tries, "jitter_m": jitter,
                    "distance_mean_m": round(float(dist.mean()), 3),
                    "distance_std_m": round(float(dist.std()), 3),
                    "direction_error_mean_deg": round(float(err.mean()), 1),
                    "direction_bias_deg": round(float(dev.mean()), 1),
                    "direction_sd_deg": round(float(dev.std()), 1),
                    "success_rate": round(sum(ok) / tries, 2),
                    "falls": sum(r["fell"] for r in res),
                    "backswing_clearance_mm": round(1000.0 * backswing_clearance(kick)[0], 1),
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

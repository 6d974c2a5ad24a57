"""Dive benchmark: per robot type and dive, time to the ground, lateral reach and the getup.

A robot of each type stands still (the walk's stand, seeded heading and joint
noise), then plays each dive of `skills.dive.DIVES` from its percepts until the
dive reports done (standing again). Ground truth measures: the time until the
torso is below half the standing height, the farthest any collision geom gets
to the dive's side (for the central split, the total spread), the torso's
sideways travel, whether the robot stands again within 10 s and how long the
getup took. One JSON line per type and dive, after the machine.

    python -m benchmarks.dive [--types 0,1,2,3,4] [--tries 10]
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import dataclass

import numpy as np

from benchmarks.machine import machine
from models import nao
from models.messages import Action
from models.scene import Lineup
from server.trainer import Trainer
from skills.dive import DIVES, Dive

LIMIT = 10.0  # s from the dive's start to standing again
LOW = 0.5  # the torso is down below this fraction of the standing height


@dataclass
class DiveRun:
    """Ground truth of one dive (lateral: m along the robot's starting left, from its start)."""

    ground: float | None  # s until the torso was below LOW x standing height
    reach_left: float  # farthest any collision geom got to the left while diving and down
    reach_right: float  # ... to the right (negative)
    torso_lateral: float  # torso displacement to the left when the robot was down
    up_after: float | None  # s until the dive reported done
    upright_at_end: bool  # torso up and high when done, and still so 0.5 s later
    times: dict  # s from the dive's start at which each phase (last) began


def run_dive(robot_type: int, name: str, seed: int) -> DiveRun:
    """A robot stands still (walk stand, seeded heading and joint noise), then plays `name`."""
    rng = np.random.default_rng(seed)
    trainer = Trainer(Lineup((robot_type,), ()), seed=seed, vision=False)
    w = trainer.world
    dive = Dive(robot_type, name)
    q = dive.motion.walk.update(0.0, 0.0, 0.0).targets
    q = np.where(np.isnan(q), 0.0, q) + rng.normal(0.0, 0.01, q.shape)
    dive.motion.reset()
    heading = float(rng.uniform(-math.pi, math.pi))
    w.place_ball((10.0, 8.0))
    w.place_robot(0, 0.0, 0.0, heading, joints=q)
    w.settle_height(0)
    for _ in range(25):
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.motion.walk_step(pc, 0.0, 0.0, 0.0))})
    p = w.players[0]
    geoms = [g for g in range(p.geoms[0], p.geoms[1] + 1) if w.model.geom_contype[g]]
    start = w.torso_positions()[0].copy()
    left = np.array([-math.sin(heading), math.cos(heading)])
    stand = nao.standing_height(robot_type)
    t0 = w.time
    ground, up_after = None, None
    reach_l = reach_r = lateral = 0.0
    while w.time - t0 < LIMIT and up_after is None:
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
        torso = w.torso_positions()[0]
        if ground is None and torso[2] < LOW * stand:
            ground = w.time - t0
        if dive.phase in ("dive", "down"):
            y = (w.data.geom_xpos[geoms, :2] - start[:2]) @ left
            reach_l, reach_r = max(reach_l, float(y.max())), min(reach_r, float(y.min()))
            lateral = float((torso[:2] - start[:2]) @ left)
        if dive.done:
            up_after = w.time - t0

    def upright() -> bool:
        return bool(w.torso_up()[0] > 0.9 and w.torso_positions()[0, 2] > 0.8 * stand)

    ok = up_after is not None and upright()
    for _ in range(25):  # it keeps standing
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
    times = {k: v - t0 for k, v in dive.times.items()}
    return DiveRun(ground, reach_l, reach_r, lateral, up_after, ok and upright(), times)



def dive_stats(robot_type: int, name: str, tries: int) -> dict:
    """Aggregate of `tries` seeded dives (one JSON row)."""
    rs = [run_dive(robot_type, name, s) for s in range(tries)]
    side = -1 if name.endswith("RIGHT") else 1
    g = [r.ground for r in rs if r.ground is not None]
    ok = [r for r in rs if r.upright_at_end]
    reach = ([r.reach_left - r.reach_right for r in rs] if name == "DIVE_CENTER"
             else [r.reach_left if side > 0 else -r.reach_right for r in rs])
    return {
        "type": robot_type, "dive": name, "tries": tries, "down": len(g),
        "ground_s": round(float(np.mean(g)), 2) if g else None,
        "ground_max_s": round(float(np.max(g)), 2) if g else None,
        "reach_m": round(float(np.mean(reach)), 2), "reach_min_m": round(float(np.min(reach)), 2),
        "torso_lateral_m": round(float(np.mean([side * r.torso_lateral for r in rs])), 2),
        "up_again": len(ok),
        "getup_s": (round(float(np.mean([r.times["settle"] - r.times["relax"] for r in ok])), 2)
                    if ok else None),
        "done_s": round(float(np.mean([r.up_after for r in ok])), 2) if ok else None,
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0,1,2,3,4")
    ap.add_argument("--tries", type=int, default=10)
    args = ap.parse_args(argv)
    try:
        types = [int(v) for v in args.types.split(",")]
    except ValueError:
        ap.error(f"--types must be comma-separated robot types 0-4, not {args.types!r}")
    if any(t not in range(5) for t in types) or args.tries < 1:
        ap.error("--types must be within 0-4 and --tries at least 1")
    print(json.dumps({"machine": machine()}), flush=True)
    for t in types:
        for name in DIVES:
            print(json.dumps(dive_stats(t, name, args.tries)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

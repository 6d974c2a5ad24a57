"""Getup benchmark: success rate and mean time from lying on the front and on the back.

For each robot type, `--tries` attempts from each side: the robot is placed
lying (`World.place_robot(..., lying=...)`) at a random heading, then driven
only through its percepts. Two starts (`--start`):

* flat (the default; the start the getups were learned from): joint angles
  perturbed about 0 (seeded), held 0.5 s to settle, then `skills.falls.Getup`
  alone with a plain joint PID, its end pose held by `Getup.hold`;
* walk (as in a match): the walk's stand pose, perturbed, as a robot that falls
  while walking lands, and `skills.motion.Motion` in charge, as on the pitch:
  the walk's stand until its tilt estimate says the robot is down, then
  `Motion.recover`'s getups and the walk's stand again.

Success: within `--limit` seconds the torso's up-vector z exceeds 0.9 and its
height 0.8 x the stand height, with no getup playing, and both still hold after
standing 1 s more. Time is when that first held. Each rate comes with its 95%
interval (`benchmarks.stats.rate_ci`). Prints one JSON line per robot type.

    python benchmarks/getup.py [--types 0 1 2 3 4] [--tries 20] [--seed 0] [--start flat|walk]
                               [--params FILE ...]

`--params` loads getup parameter files after the shipped ones (e.g. a CMA-ES
best.txt), as `benchmarks.walk --params` does for the walk.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import sys
import time
from collections.abc import Callable, Sequence

import numpy as np

from benchmarks.stats import rate_ci
from models import nao
from models.messages import Action
from models.scene import Lineup
from optimization.getup import STARTS, lying_joints
from server.sensors import Proprioception
from server.trainer import Trainer
from server.world import World
from skills.control import JointPid
from skills.falls import Getup, load_getup_skills
from skills.motion import Motion

SETTLE = 0.5  # s lying still before the getup starts
HOLD = 1.0  # s the robot must stay up
UP_MIN = 0.9
HEIGHT_FRACTION = 0.8
JOINT_NOISE = 0.15  # rad, sigma of the joint perturbation (flat start)


def attempt(world: World, robot_type: int, lying: str, rng: np.random.Generator,
            limit: float = 3.0, getup: Getup | None = None) -> float | None:
    """One getup from `lying` ("front"/"back"); returns the time (s) to stand, or None on failure."""
    q0 = lying_joints(robot_type, rng, "flat", JOINT_NOISE)
    world.place_ball((10.0, 8.0))
    for i in range(1, len(world.players)):  # anyone else waits far away
        world.place_robot(i, 12.0, -8.0, 0.0)
    world.place_robot(0, -3.0, 3.0, rng.uniform(-math.pi, math.pi), joints=q0, lying=lying)
    world.settle_height(0)
    sense = Proprioception(world)
    act = world.players[0].actuators
    ctrl = np.zeros(world.model.nu)
    pid = JointPid.for_robot(robot_type)
    for _ in range(round(SETTLE / 0.02)):
        q = sense.read()[0][0]
        ctrl[act] = pid(q0, q)
        world.step(ctrl)
    getup = getup or Getup(robot_type)
    getup.reset()
    pid.reset()
    hold_targets = None

    def cycle() -> None:
        nonlocal hold_targets
        q, gyro, acc, _ = sense.read()[0]
        targets = getup.step(world.time, q, acc, gyro)
        if targets is None:  # the getup's end pose holds (balanced), or the start pose
            targets = getup.hold()
            if targets is None:
                hold_targets = q.copy() if hold_targets is None else hold_targets
                targets = hold_targets
        ctrl[act] = pid(targets, q)
        world.step(ctrl)

    return time_to_stand(world, robot_type, cycle, lambda: getup.busy, limit)


def attempt_walk(trainer: Trainer, robot_type: int, lying: str, rng: np.random.Generator,
                 limit: float = 3.0, getup: Getup | None = None) -> float | None:
    """One getup as in a match, from `lying` with the legs in the walk's stand pose;
    the time (s) to stand, or None on failure (see the module docstring)."""
    world = trainer.world
    mo = Motion(robot_type)
    if getup is not None:
        mo.getup = getup
    q0 = lying_joints(robot_type, rng, "walk")
    world.place_ball((10.0, 8.0))
    world.place_robot(0, -3.0, 3.0, rng.uniform(-math.pi, math.pi), joints=q0, lying=lying)
    world.settle_height(0)

    def cycle() -> None:
        pc = trainer.percepts()[0]
        v = mo.recover(pc)
        trainer.step({0: Action(mo.walk_step(pc, 0.0, 0.0, 0.0) if v is None else v)})

    return time_to_stand(world, robot_type, cycle, lambda: mo.getup.busy, limit)


def time_to_stand(world: World, robot_type: int, cycle: Callable[[], None], busy: Callable[[], bool],
                  limit: float) -> float | None:
    """Play `cycle` (one 20 ms step of the getup's control) until the robot has stood
    `HOLD` s with no getup playing (`busy` false): the time (s) it first stood, or None
    when it is not standing `limit` s after the start."""
    height = nao.standing_height(robot_type)
    t0 = world.time
    up_since = None
    while world.time - t0 < limit + HOLD + 1e-9:
        cycle()
        up = world.torso_up()[0] > UP_MIN and world.torso_positions()[0, 2] > HEIGHT_FRACTION * height
        if up and not busy():
            up_since = world.time if up_since is None else up_since
            if world.time - up_since >= HOLD - 1e-9:
                return up_since - t0
        else:
            up_since = None
            if world.time - t0 > limit:
                return None
    return None


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", type=int, nargs="+", default=[0, 1, 2, 3, 4])
    ap.add_argument("--tries", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--limit", type=float, default=3.0, help="s allowed to get up")
    ap.add_argument("--start", choices=STARTS, default="flat",
                    help="flat: joints about 0, the getup alone; walk: the walk's stand pose, "
                         "Motion in charge, as in a match")
    ap.add_argument("--params", nargs="+", default=[], metavar="FILE",
                    help="getup parameter files loaded after the shipped ones (e.g. a CMA-ES best.txt)")
    args = ap.parse_args(argv)
    if args.tries < 1 or args.limit <= 0:
        ap.error("--tries must be at least 1 and --limit above 0")
    for t in args.types:
        try:  # a bad file fails here, with file:line
            load_getup_skills(args.params, t)
        except (OSError, ValueError) as err:
            ap.error(str(err))
    for t in args.types:
        row = getup_stats(t, args.tries, args.seed, args.limit, args.start, args.params)
        print(json.dumps({"robot_type": t, **row}), flush=True)
    return 0


def getup_stats(robot_type: int, tries: int = 20, seed: int = 0, limit: float = 3.0,
                start: str = "flat", params: Sequence[str] = ()) -> dict:
    """Success rate and mean time (s) of `tries` getups from each side, from `start`
    ("flat" or "walk", see the module docstring), the getup parameter files `params`
    loaded after the shipped ones."""
    if start not in STARTS:
        raise ValueError(f"start must be one of {', '.join(STARTS)}, not {start!r}")
    rng = np.random.default_rng([seed, robot_type])
    row: dict = {"tries": tries, "limit_s": limit, "start": start, "params": list(params)}
    skills = load_getup_skills(params, robot_type)
    getup = functools.partial(Getup, robot_type, skills)  # a fresh one each try
    wall = time.perf_counter()
    world = World(Lineup((robot_type,), ())) if start == "flat" else None
    trainer = Trainer(Lineup((robot_type,), ()), vision=False) if start == "walk" else None
    for side in ("front", "back"):
        if world is not None:
            times = [attempt(world, robot_type, side, rng, limit, getup()) for _ in range(tries)]
        else:
            times = [attempt_walk(trainer, robot_type, side, rng, limit, getup()) for _ in range(tries)]
        ok = [x for x in times if x is not None]
        row[f"{side}_success"] = len(ok) / tries
        row[f"{side}_success_ci95"] = rate_ci(len(ok), tries)
        row[f"{side}_mean_time_s"] = round(float(np.mean(ok)), 3) if ok else None
    row["wall_s"] = round(time.perf_counter() - wall, 1)
    return row


if __name__ == "__main__":
    sys.exit(main())

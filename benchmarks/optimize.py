"""Optimization benchmark: trials per hour per core, and the speed-up with 2 workers.

For each task (go_to_target, position_to_dribble and the kick tasks
kick_distance, long_kick and kick_walking by default):

* one core: `--trials` trials run one after another in this process; wall
  seconds per trial, simulated seconds per trial, the real-time factor and
  trials per hour per core;
* parallel: the same number of trials through the job's evaluator with 1 and
  with 2 local worker processes (`--workers`), and the speed-up of 2 over 1.

Goal (issue 7): one go-to-target trial (about 30 simulated seconds) in at most
2 s of wall time on one core. The machine is shared: figures are noisy.
Prints one JSON line per task.

    python -m benchmarks.optimize [--tasks go_to_target,position_to_dribble] [--trials 4] [--workers 2]
"""

from __future__ import annotations

import argparse
import json
import sys
import time

from benchmarks.machine import machine
from optimization.executor import Evaluator, ExecutorFactory, TrialRequest
from optimization.paramvec import load_values
from optimization.task import TASKS, make_task

GOAL_S = 2.0  # s of wall time per go-to-target trial, one core
KICK_TASKS = ("kick_distance", "long_kick", "kick_walking")  # optimization.kick


def one_core(task, values: dict, trials: int) -> dict:
    wall, sim = [], []
    for k in range(trials):
        t0 = time.perf_counter()
        r = task.trial(values, 1000 + k)
        wall.append(time.perf_counter() - t0)
        sim.append(float(r.info.get("sim_seconds", r.info.get("sim_s", 0.0))))
    per = sum(wall) / trials
    return {"wall_s_per_trial": round(per, 3), "best_wall_s": round(min(wall), 3),
            "sim_s_per_trial": round(sum(sim) / trials, 2),
            "real_time_factor": round(sum(sim) / sum(wall), 1) if sum(sim) else None,
            "trials_per_hour_per_core": round(3600.0 / per)}


def parallel(task, values: dict, trials: int, workers: int) -> float:
    """Wall seconds for `trials` trials on `workers` local processes (pool start-up excluded)."""
    ev = Evaluator(task, ExecutorFactory(workers=workers))
    try:
        # Warm the pool up (process start, imports) with one short batch.
        ev.evaluate_all([TrialRequest(i, 0, 1, values) for i in range(workers)])
        t0 = time.perf_counter()
        ev.evaluate_all([TrialRequest(i, 0, 2000 + i, values) for i in range(trials)])
        return time.perf_counter() - t0
    finally:
        ev.close()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tasks", default="go_to_target,position_to_dribble," + ",".join(KICK_TASKS),
                    help="comma-separated task names (unregistered ones are reported as unavailable)")
    ap.add_argument("--trials", type=int, default=4, help="trials per measurement")
    ap.add_argument("--workers", type=int, default=2, help="workers of the parallel measurement")
    ap.add_argument("--type", dest="robot_type", type=int, default=0)
    args = ap.parse_args(argv)
    info = machine()
    for name in (n.strip() for n in args.tasks.split(",") if n.strip()):
        if name not in TASKS:
            print(json.dumps({"benchmark": "optimize", "task": name, "available": False,
                              "reason": "task not registered yet (its skill has no parameterized form)"}),
                  flush=True)
            continue
        task = make_task(name, args.robot_type)
        values = load_values(task.sets, args.robot_type)
        row: dict = {"benchmark": "optimize", "task": name, "available": True, "trials": args.trials}
        row.update(one_core(task, values, args.trials))
        if name == "go_to_target":
            row["goal_wall_s"] = GOAL_S
            row["meets_goal"] = row["wall_s_per_trial"] <= GOAL_S
        t1 = parallel(task, values, args.trials, 1)
        tn = parallel(task, values, args.trials, args.workers)
        row[f"wall_s_{args.trials}_trials_1_worker"] = round(t1, 2)
        row[f"wall_s_{args.trials}_trials_{args.workers}_workers"] = round(tn, 2)
        row[f"speedup_{args.workers}_workers"] = round(t1 / tn, 2)
        row["machine"] = info
        print(json.dumps(row), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

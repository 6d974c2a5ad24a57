"""`soccer optimize`: a CMA-ES job on a named task or a layered task file (`optimization`)."""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

from cli.args import OutputError, check_writable, checked, robot_type, scheduler, seed

EXIT_USAGE = 2
CONFIG = "job.json"

HELP = """\
TASK is a registered task (go_to_target, sprint, walk_forward, position_to_dribble,
getup_front, getup_back, kick_distance, long_kick, kick_walking, approach, dribble_walk,
position_walk, sphere, rosenbrock) or a task file of layers (optimization/tasks/NAME.task, or a path;
walk.task is the walk part of Figure 4.1).

Each generation prints one line on stderr; the job directory (--out) holds
checkpoint.pkl, history.csv, best.txt (UT-style parameters), mean.txt (the
search distribution's mean: with noisy trials usually the better pick) and
fitness.png, all updated after every generation. A task file runs its layers in
order, each in OUT/LAYER/. A killed job continues with --resume OUT and ends as
it would have.

examples:
  soccer optimize walk_forward --option seconds=3 --population 8 --generations 5 --out runs/fwd
  soccer optimize go_to_target --params my_walk.txt --workers 2 --out runs/gtt
  soccer optimize walk --generations 20 --out runs/walk        # optimization/tasks/walk.task
  soccer optimize sprint --scheduler tcp://10.0.0.5:8786 --out runs/sprint
  soccer optimize --resume runs/gtt
"""


_positive_int = checked(int, "expected a whole number", lambda n: 1 <= n <= 1_000_000,
                       "must be 1 to 1000000")
_workers = checked(int, "expected a whole number of workers", lambda n: 0 <= n <= 1024,
                   "workers must be 0 (in this process) to 1024")
_sigma = checked(float, "expected a number", lambda v: 0 < v < 1e6, "sigma must be positive")
_robot_type = robot_type


def _option(value: str) -> tuple[str, str]:
    k, sep, v = value.partition("=")
    if not sep or not k:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, not {value!r}")
    return k, v


def register(subparsers) -> dict:
    """Add `optimize` to the `soccer` command."""
    p = subparsers.add_parser("optimize", help="run a CMA-ES optimization job (resumable)",
                              description="Optimize skill parameters with CMA-ES on a training task.",
                              epilog=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("task", nargs="?", metavar="TASK", help="registered task or task file")
    p.add_argument("--params", type=Path, nargs="+", default=[], metavar="FILE",
                   help="parameter files loaded after the shipped defaults (starting values)")
    p.add_argument("--set", dest="sets", action="append", default=[], metavar="NAME",
                   help="parameter set to learn (repeatable; default: the task's)")
    p.add_argument("--option", dest="options", action="append", type=_option, default=[],
                   metavar="KEY=VALUE", help="task option, e.g. seconds=3 for walk_forward (repeatable)")
    p.add_argument("--type", dest="robot_type", type=_robot_type, default=None, metavar="T",
                   help="robot type 0-4 (default 0)")
    p.add_argument("--population", type=_positive_int, metavar="N", help="CMA-ES population")
    p.add_argument("--generations", type=_positive_int, metavar="G", help="generations (default 10)")
    p.add_argument("--sigma", type=_sigma, metavar="S",
                   help="initial step, in units of each parameter's scale (default 1)")
    p.add_argument("--trials", type=_positive_int, metavar="N",
                   help="seeded trials per candidate (default 1)")
    p.add_argument("--seed", type=seed, help="random seed (default 0)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_workers, metavar="W",
                       help="local worker processes (default: one per core; 0: this process)")
    where.add_argument("--scheduler", type=scheduler, metavar="tcp://HOST:8786",
                       help="run trials on a Dask cluster (pip install 'dask[distributed]')")
    p.add_argument("--out", type=Path, metavar="DIR", help="job directory (default runs/TASK)")
    p.add_argument("--resume", type=Path, metavar="DIR", help="continue the job in DIR")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    return {"optimize": cmd_optimize}


class _Usage(Exception):
    pass


def _config(args: argparse.Namespace) -> dict:
    """What the job is, from the command line (saved as OUT/job.json for --resume)."""
    if args.resume is not None:
        single = ("task", "population", "generations", "sigma", "trials", "seed", "robot_type", "out")
        given = ([o for o in single if getattr(args, o) is not None]
                 + [o for o in ("params", "sets", "options") if getattr(args, o)])
        if given:
            flag = "TASK" if given[0] == "task" else "--" + given[0].replace("_", "-")
            raise _Usage(f"--resume continues the job with its own settings; drop {flag} "
                         f"(only --workers or --scheduler may change)")
        path = args.resume / CONFIG
        if not path.is_file():
            raise _Usage(f"no job to resume in {args.resume} ({CONFIG} missing)")
        cfg = json.loads(path.read_text())
        cfg["out"] = str(args.resume)
        return cfg
    if args.task is None:
        raise _Usage("TASK is required (or --resume DIR)")
    from optimization.layered import find_task
    from optimization.task import TASKS

    file = find_task(args.task) if args.task not in TASKS else None
    if args.task not in TASKS and file is None:
        raise _Usage(f"unknown task {args.task!r}: neither a registered task ({', '.join(TASKS)}) "
                     f"nor a task file")
    if file is not None and (args.sets or args.options):
        raise _Usage(f"{args.task} is a task file: its layers name their sets and options "
                     f"(--set and --option are for a registered task)")
    for p in args.params:
        if not p.is_file():
            raise _Usage(f"parameter file {p} not found")
    out = args.out or Path("runs") / (file.stem if file else args.task)
    overrides = {k: getattr(args, k) for k in ("population", "generations", "sigma", "trials", "seed")}
    return {"task": args.task if file is None else None, "file": str(file.resolve()) if file else None,
            "params": [str(p.resolve()) for p in args.params], "sets": list(args.sets),
            "options": dict(args.options), "robot_type": args.robot_type or 0, "overrides": overrides,
            "out": str(out)}


def cmd_optimize(args: argparse.Namespace) -> int:
    from optimization.executor import ExecutorFactory
    from optimization.layered import read_task_file, run_layers, single_layer
    from skills.params import ParamError

    try:
        cfg = _config(args)
        out = Path(cfg["out"])
        check_writable(out, "--resume" if args.resume is not None else "--out", directory=True)
        if args.resume is None and (out / CONFIG).exists():
            raise _Usage(f"{out} already holds a job; continue it with --resume {out} or pick another --out")
        if cfg["file"]:
            layers = read_task_file(cfg["file"])
            subdirs = True
        else:
            layers = [single_layer(cfg["task"], cfg["options"], cfg["sets"])]
            subdirs = False
        # Build every layer's problem that can be built now, so bad input fails before any work.
        if not cfg["file"]:
            layers[0].problem(cfg["robot_type"], cfg["params"])
    except (_Usage, OutputError, ParamError, ValueError, KeyError, OSError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"soccer optimize: error: {msg}", file=sys.stderr)
        return EXIT_USAGE
    out.mkdir(parents=True, exist_ok=True)
    if args.resume is None:
        (out / CONFIG).write_text(json.dumps(cfg, indent=2) + "\n")
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("soccer optimize: %(levelname)s: %(message)s"))
    logger = logging.getLogger("optimization")
    logger.addHandler(handler)
    logger.setLevel(logging.WARNING)
    factory = ExecutorFactory(workers=args.workers, scheduler=args.scheduler)
    try:
        results = run_layers(layers, out, cfg["robot_type"], cfg["params"], cfg["overrides"], factory,
                             subdirs=subdirs, progress=open_null() if args.quiet else sys.stderr)
    except (ParamError, ValueError, KeyError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"soccer optimize: error: {msg}", file=sys.stderr)
        return EXIT_USAGE
    except RuntimeError as exc:
        print(f"soccer optimize: error: {exc}", file=sys.stderr)
        return 1
    finally:
        factory.close()
        logger.removeHandler(handler)
    for name, r in results.items():
        where = r.out_dir
        print(f"{name}: best fitness {r.best_fitness:.4g} +- {r.best_spread:.3g} (generation "
              f"{r.best_generation + 1}, {r.history[-1]['evaluations'] if r.history else 0} trials); "
              f"{where / 'best.txt'}, {where / 'history.csv'}, {where / 'fitness.png'}"
              + (f"; {len(r.failures)} failed trials" if r.failures else ""))
    return 0


def open_null():
    import os
    return open(os.devnull, "w")  # noqa: SIM115 - lives for the job


if __name__ == "__main__":
    from cli.main import main
    sys.exit(main(["optimize", *sys.argv[1:]]))

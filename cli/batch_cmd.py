"""`soccer batch`: many seeded matches between two teams, in parallel, with the mean
goal difference and its standard error (`server.batch`)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from cli import teams
from cli.args import OutputError, check_writable, checked, half_time, scheduler, seed

EXIT_USAGE = 2
EXIT_WORSE = 3  # --against: significantly worse than the baseline
MAX_GAMES = 1_000_000
MAX_WORKERS = 1024

HELP = """\
Team A (--home) against team B (--away): game i uses seed S0 + i, and A plays left
in even games and right in odd ones, so the field's sides cancel. A team is a
name (see soccer match --help) or package.module:factory, a callable
(side, unum, robot_type, seed) -> agent.

DIR/games.jsonl gets one JSON line per finished game (score, goal difference from
A's side, goals, events by kind, falls, possession, touches, territory: the ball's mean
x in play toward B's goal in m, times, version);
DIR/summary.json the summary printed at the end. A killed batch continues with
the same command and --resume, playing only the missing games. A game that
fails is an error row (its seed and the error) and the batch goes on.

Regression: --save-baseline FILE stores the batch's goal difference (n, mean, sd,
standard error, settings, commit) as the last accepted team's; --against FILE
compares the batch with a stored one by Welch's two-sample t-test, one-sided
(is the new mean lower?), and exits with status 3 when it is, at p < 0.05.

examples:
  soccer batch --home posture --away posture --games 20 --half-time 10 --out runs/pp
  soccer batch --home mypkg.team:make_agent --away posture --games 100 --out runs/mine --resume
  soccer batch --home posture --away posture --games 200 --scheduler tcp://10.0.0.5:8786 --out runs/big
  soccer batch --home villa --away posture --games 100 --out runs/v --against base.json
"""

_games = checked(int, "expected a whole number of games", lambda n: 1 <= n <= MAX_GAMES,
                 f"games must be 1 to {MAX_GAMES}")
_workers = checked(int, "expected a whole number of workers", lambda n: 0 <= n <= MAX_WORKERS,
                   f"workers must be 0 (in this process) to {MAX_WORKERS}")
_team_size = checked(int, "team size must be a whole number", lambda n: 1 <= n <= 11,
                     "team size must be 1 to 11")


def register(subparsers) -> dict:
    """Add `batch` to the `soccer` command."""
    p = subparsers.add_parser("batch", help="many matches: mean goal difference +- standard error",
                              description="Play a batch of seeded matches between two teams.",
                              epilog=HELP, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--home", default="villa", metavar="TEAM", help="team A (default villa)")
    p.add_argument("--away", default="posture", metavar="TEAM", help="team B (default posture)")
    p.add_argument("--games", type=_games, required=True, metavar="N", help="number of games")
    p.add_argument("--half-time", type=half_time, default=300.0, metavar="SECONDS",
                   help="game seconds per half (default 300)")
    p.add_argument("--seed", type=seed, default=0, metavar="S0", help="seed of game 0 (default 0)")
    p.add_argument("--home-size", type=_team_size, default=11, metavar="N", help="players of team A")
    p.add_argument("--away-size", type=_team_size, default=11, metavar="N", help="players of team B")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=_workers, metavar="W",
                       help="local worker processes (default: one per core; 0: this process)")
    where.add_argument("--scheduler", type=scheduler, metavar="tcp://HOST:8786",
                       help="play on a Dask cluster (pip install -e '.[distributed]')")
    p.add_argument("--out", type=Path, required=True, metavar="DIR", help="batch directory")
    p.add_argument("--resume", action="store_true", help="continue the batch in DIR")
    p.add_argument("--logs", action="store_true", help="keep every game's match log in DIR/logs/")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--against", type=Path, metavar="BASELINE.json",
                   help="exit 3 when the mean goal difference is significantly below this baseline's "
                        "(Welch, one-sided, p < 0.05)")
    p.add_argument("--save-baseline", type=Path, metavar="FILE",
                   help="write this batch's goal difference as a baseline (atomically)")
    return {"batch": cmd_batch}


def cmd_batch(args: argparse.Namespace) -> int:
    import os
    import time

    from optimization.executor import ExecutorFactory
    from server.batch import BatchError, BatchSettings, prepare, read_baseline, run_batch
    from server.match import team_types

    settings = BatchSettings(args.home, args.away, args.half_time, args.seed, args.home_size,
                             args.away_size)
    try:
        for spec, size in ((args.home, args.home_size), (args.away, args.away_size)):
            team_types(teams.factory(spec), size, spec)  # a bad team fails here, not in every game
        check_writable(args.out, "--out", directory=True)
        prepare(settings, args.out, args.resume)
        baseline = read_baseline(args.against) if args.against is not None else None
        if args.save_baseline is not None:
            check_writable(args.save_baseline, "--save-baseline")
    except (ValueError, OutputError, BatchError) as exc:  # UnknownTeam is a ValueError
        print(f"soccer batch: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    factory = ExecutorFactory(workers=args.workers, scheduler=args.scheduler)
    inflight = None if args.scheduler else 2 * max(1, args.workers if args.workers is not None
                                                   else os.cpu_count() or 1)
    if args.workers == 0:
        inflight = 1
    played = []
    start = time.perf_counter()
    try:
        summary = run_batch(settings, args.games, args.out, teams.factory, factory, resume=args.resume,
                            logs=args.logs, inflight=inflight,
                            progress=None if args.quiet else sys.stderr, on_row=played.append)
    except BatchError as exc:
        print(f"soccer batch: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except RuntimeError as exc:  # e.g. no Dask, or the scheduler unreachable
        print(f"soccer batch: error: {exc}", file=sys.stderr)
        return 1
    finally:
        factory.close()
    wall = time.perf_counter() - start
    print(format_summary(summary))
    if played:
        print(f"played {len(played)} games in {wall:.1f} s on {factory.describe()}: "
              f"{3600 * len(played) / wall:.0f} games/hour")
    for r in played:
        if "error" in r:
            print(f"  game {r['game']} (seed {r['seed']}) failed: {r['error']}")
    print(f"results: {args.out / 'games.jsonl'}, {args.out / 'summary.json'}")
    return regression(summary, baseline, args.against, args.save_baseline)


def regression(summary: dict, baseline: dict | None, against: Path | None, save: Path | None) -> int:
    """--save-baseline and --against: print the comparison; the exit status."""
    from server.batch import against as compare_with
    from server.batch import baseline_stats, describe_dict, save_baseline, settings_mismatch

    status = 0
    if baseline is not None:
        print(f"against baseline {against} ({baseline.get('commit', 'unknown commit')}, "
              f"{baseline.get('created', 'undated')}):")
        for diff in settings_mismatch(baseline, summary):
            print(f"  warning: {diff}")
        try:
            result = compare_with(describe_dict(summary["goal_difference"]), baseline_stats(baseline))
        except ValueError as exc:
            print(f"soccer batch: error: {exc}", file=sys.stderr)
            status = EXIT_USAGE
        else:
            print("\n".join("  " + line for line in result.text().splitlines()))
            if result.worse:
                status = EXIT_WORSE
    if save is not None:
        save_baseline(save, summary)
        print(f"baseline written: {save}")
    return status


def format_summary(s: dict) -> str:
    """The summary as a small table."""
    a, b = s["teams"]["A"], s["teams"]["B"]
    gd = s["goal_difference"]
    lines = [f"{a} (A) vs {b} (B): {s['games']} games of 2 x {s['half_time']:g} s from seed {s['seed']}"
             + (f", {s['errors']} failed (games {', '.join(map(str, s['error_games']))})"
                if s["errors"] else "")]
    if gd["mean"] is None:
        lines.append("goal difference A - B: no finished games")
        return "\n".join(lines)
    text = f"goal difference A - B: {gd['mean']:+.3f}"
    if gd["se"] is not None:
        lo, hi = gd["ci95"]
        text += f" +- {gd['se']:.3f} (standard error; 95% interval {lo:+.3f} .. {hi:+.3f})"
    lines.append(text)
    lines.append(f"A wins {s['wins']}, draws {s['draws']}, losses {s['losses']};"
                 f" goals {s['goals_for']} : {s['goals_against']}")
    ter = s.get("territory") or {}
    if ter.get("mean") is not None:
        text = f"territory A (the ball's mean x in play toward B's goal): {ter['mean']:+.2f} m"
        if ter.get("se") is not None:
            text += f" +- {ter['se']:.2f}"
        lines.append(text)
    lines.append(f"{'':16s}{'falls/game':>12s}{'possession':>12s}{'crashes':>9s}")
    for t, name in (("A", a), ("B", b)):
        falls, pos = s["falls"][t], s["possession"][t]
        lines.append(f"{t} {name[:14]:14s}{falls:12.2f}{100 * pos:11.0f}%{s['agent_crashes'][t]:9d}")
    return "\n".join(lines)


if __name__ == "__main__":
    from cli.main import main
    sys.exit(main(["batch", *sys.argv[1:]]))

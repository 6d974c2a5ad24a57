"""The villa variants against the base team: "Positioning to Win" Table 2's first column.

Every variant (`villa:NAME`, agent.teamconfig.VARIANTS) plays a batch against the
base team `villa` through `server.batch` (game i from seed S0 + i, sides
alternating); its mean goal difference (variant - base) and standard error are
printed beside the paper's (100 ten-minute 11 vs 11 games), as one JSON line per
variant and then a Markdown table, with the machine it ran on.

    python -m benchmarks.ablation [--games N] [--half-time S] [--workers W]
                                  [--variants a,b] [--size N] [--seed S0] [--out DIR]

The full comparison is 100 games of 2 x 300 s, 11 vs 11 per variant: days of CPU on
two cores. Small settings (fewer players, short halves) measure something else.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

from agent.teamconfig import PAPER_TABLE2, VARIANTS, UnknownVariant, variant_name
from benchmarks.machine import machine
from cli import teams
from optimization.executor import ExecutorFactory
from server.batch import BatchSettings, run_batch


def _fmt(mean, se) -> str:
    if mean is None:
        return "-"
    return f"{mean:+.2f}" + (f" ({se:.2f})" if se is not None else "")


def table(rows: list[dict]) -> str:
    """The Markdown table of the results beside the paper's."""
    lines = ["| variant | games | goal difference vs villa (se) | paper (se) |", "|---|---:|---:|---:|"]
    for r in rows:
        paper = PAPER_TABLE2.get(r["variant"])
        lines.append(f"| {r['variant']} | {r['n']} | {_fmt(r['mean'], r['se'])} | "
                     f"{_fmt(*paper) if paper else '-'} |")
    return "\n".join(lines)


def run(names: list[str], games: int, half_time: float, size: int, seed: int, workers: int | None,
        out: Path) -> list[dict]:
    rows = []
    factory = ExecutorFactory(workers=workers)
    try:
        for name in names:
            settings = BatchSettings(f"villa:{name}", "villa", half_time, seed, size, size)
            start = time.perf_counter()
            s = run_batch(settings, games, out / name, teams.factory, factory, progress=None)
            gd = s["goal_difference"]
            paper = PAPER_TABLE2.get(name)
            row = {"variant": name, "n": gd["n"], "mean": gd["mean"], "se": gd["se"], "sd": gd["sd"],
                   "wins": s["wins"], "draws": s["draws"], "losses": s["losses"], "errors": s["errors"],
                   "paper_mean": paper[0] if paper else None, "paper_se": paper[1] if paper else None,
                   "half_time": half_time, "size": size, "wall": round(time.perf_counter() - start, 1)}
            print(json.dumps(row), flush=True)
            rows.append(row)
    finally:
        factory.close()
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.ablation", description=__doc__.split("\n\n")[0])
    p.add_argument("--games", type=int, default=100, help="games per variant (default 100)")
    p.add_argument("--half-time", type=float, default=300.0, help="s per half (default 300)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default one per core)")
    p.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated (default all)")
    p.add_argument("--size", type=int, default=11, help="players a side (default 11)")
    p.add_argument("--seed", type=int, default=0, help="seed of game 0 (default 0)")
    p.add_argument("--out", type=Path, default=None, help="keep the batches here (default a temp dir)")
    args = p.parse_args(argv)
    try:
        names = [variant_name(v) for v in args.variants.split(",") if v.strip()]
    except UnknownVariant as exc:
        print(f"benchmarks.ablation: error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps({"machine": machine()}), flush=True)
    with tempfile.TemporaryDirectory(prefix="ablation-") as tmp:
        out = args.out or Path(tmp)
        rows = run(names, args.games, args.half_time, args.size, args.seed, args.workers, out)
    print()
    print(f"{args.games} games per variant of 2 x {args.half_time:g} s, {args.size} vs {args.size}, "
          f"from seed {args.seed}; paper: 100 games of 2 x 300 s, 11 vs 11")
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())

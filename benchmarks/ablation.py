"""The villa variants against the base team: "Positioning to Win" Table 2's first column.

Every variant (`villa:NAME`, agent.teamconfig.VARIANTS) plays a batch against the
base team `villa` through `server.batch` (game i from seed S0 + i, sides
alternating; the same seeds for every variant); its mean goal difference
(variant - base) and standard error are printed beside the paper's (100
ten-minute 11 vs 11 games), as one JSON line per variant and then a Markdown
table, with the machine it ran on and the rank correlation of our means with
the paper's (Spearman's rho, and its 95% interval over our means redrawn from their
standard errors: whether our games can tell the order at all).

Games are played in rounds of `--round` games per variant (default 2, one from
each side), every variant in turn, so a run stopped at any time leaves a table in
which each variant has played as many games as the others (give or take one
round). With `--out DIR` each round's table is written to DIR/table.md,
DIR/ablation.jsonl and DIR/ablation.png (our means with 95% intervals beside
the paper's), and `--resume` continues a stopped run (the games already in
DIR/VARIANT/games.jsonl are not played again); one pool of worker processes
serves the whole run.

    python -m benchmarks.ablation [--games N] [--round K] [--half-time S] [--workers W]
                                  [--variants a,b] [--size N] [--seed S0] [--out DIR] [--resume]
    python -m benchmarks.ablation --out DIR --report [--variants a,b]

The full comparison is 100 games of 2 x 300 s, 11 vs 11 per variant: days of CPU on
two cores. Small settings (fewer players, short halves) measure something else.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import json
import math
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

from agent.teamconfig import PAPER_TABLE2, VARIANTS, UnknownVariant, variant_name
from benchmarks.machine import machine
from cli import teams
from optimization.executor import ExecutorFactory, shutdown
from server.batch import GAMES, SETTINGS, BatchError, BatchSettings, read_games, run_batch, summarize
from server.files import write_bytes, write_text


def _fmt(mean, se) -> str:
    if mean is None:
        return "-"
    return f"{mean:+.2f}" + (f" ({se:.2f})" if se is not None else "")


def table(rows: list[dict]) -> str:
    """The Markdown table of the results beside the paper's."""
    lines = ["| variant | games | goal difference vs villa (se) | W-D-L | paper (se) |",
             "|---|---:|---:|:---:|---:|"]
    for r in rows:
        paper = PAPER_TABLE2.get(r["variant"])
        lines.append(f"| {r['variant']} | {r['n']} | {_fmt(r['mean'], r['se'])} | "
                     f"{r['wins']}-{r['draws']}-{r['losses']} | {_fmt(*paper) if paper else '-'} |")
    return "\n".join(lines)


def write_plot(path: Path, rows: list[dict], title: str) -> None:
    """Each variant's mean goal difference against villa with its 95% interval (1.96
    standard errors) beside the paper's, as a PNG (matplotlib, Agg backend)."""
    import io

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = [r["variant"] for r in rows]
    y = np.arange(len(rows))
    fig, ax = plt.subplots(figsize=(7.0, 0.45 * len(rows) + 1.8), dpi=100)
    ours = [(r["mean"], 1.96 * (r["se"] or 0.0)) if r["mean"] is not None else (np.nan, 0.0) for r in rows]
    paper = [(PAPER_TABLE2[n][0], 1.96 * PAPER_TABLE2[n][1]) if n in PAPER_TABLE2 else (np.nan, 0.0)
             for n in names]
    ax.errorbar([m for m, _ in ours], y - 0.15, xerr=[e for _, e in ours], fmt="o", capsize=3,
                label="ours (95% interval)")
    ax.errorbar([m for m, _ in paper], y + 0.15, xerr=[e for _, e in paper], fmt="s", capsize=3,
                label="Positioning to Win, Table 2")
    ax.axvline(0.0, color="0.5", lw=0.8)
    ax.set_yticks(y, [f"{n} ({r['n']})" for n, r in zip(names, rows)])
    ax.invert_yaxis()
    ax.set_xlabel("goal difference, variant - villa")
    ax.set_title(title, fontsize=9)
    ax.grid(axis="x", alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09 - 0.6 / (len(rows) + 3)), ncol=2, fontsize=8)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    write_bytes(path, buf.getvalue())


def rank_agreement(rows: list[dict], draws: int = 2000, seed: int = 0) -> dict | None:
    """Spearman's rank correlation of our means with the paper's, over the variants in
    both with a mean (None for fewer than three); +1 is the paper's order. With it, the
    95% interval of rho over `draws` redraws of our means from their standard errors
    (normal, seeded): how far our games alone could move it."""
    pairs = [(r["mean"], r.get("se") or 0.0, PAPER_TABLE2[r["variant"]][0]) for r in rows
             if r["variant"] in PAPER_TABLE2 and r["mean"] is not None]
    if len(pairs) < 3:
        return None
    from scipy.stats import spearmanr

    ours, se, paper = (np.array(c, dtype=float) for c in zip(*pairs))
    res = spearmanr(ours, paper)
    rho, p = float(res.statistic), float(res.pvalue)
    redrawn = ours + se * np.random.default_rng(seed).standard_normal((draws, len(ours)))
    rhos = np.array([spearmanr(d, paper).statistic for d in redrawn], dtype=float)
    rhos = rhos[np.isfinite(rhos)]
    low, high = (round(float(q), 3) for q in np.percentile(rhos, (2.5, 97.5))) if len(rhos) else (None, None)
    return {"variants": len(pairs), "spearman_rho": None if math.isnan(rho) else round(rho, 3),
            "p": None if math.isnan(p) else round(p, 4), "rho_95": [low, high]}


class SharedPool:
    """One executor for every batch of a run, so worker processes start (and load the
    model and the compiled kernels) once; remade when a worker died and broke it.

    Called, it lends the executor to `server.batch.run_batch`, whose shutdown at the
    end of each batch then only gives it back (a cancelling shutdown, after an
    interrupt, closes it)."""

    def __init__(self, factory: Callable[[], cf.Executor]) -> None:
        self.factory = factory
        self.executor: cf.Executor | None = None

    def __call__(self) -> cf.Executor:
        if self.executor is None or getattr(self.executor, "_broken", False):
            if self.executor is not None:
                self.executor.shutdown(wait=False)
            self.executor = self.factory()
        return _Lease(self)

    def close(self) -> None:
        if self.executor is not None:
            self.executor.shutdown(wait=True)
            self.executor = None


class _Lease(cf.Executor):
    def __init__(self, pool: SharedPool) -> None:
        self.pool = pool
        self.executor = pool.executor

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        return self.executor.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        if cancel_futures and self.pool.executor is self.executor:
            shutdown(self.executor, wait)
            self.pool.executor = None


def variant_row(name: str, summary: dict, half_time: float, size: int, wall: float) -> dict:
    """One variant's line of the table (a JSON row) from its batch summary."""
    gd = summary["goal_difference"]
    paper = PAPER_TABLE2.get(name)
    return {"variant": name, "n": gd["n"], "mean": gd["mean"], "se": gd["se"], "sd": gd["sd"],
            "wins": summary["wins"], "draws": summary["draws"], "losses": summary["losses"],
            "goals_for": summary["goals_for"], "goals_against": summary["goals_against"],
            "errors": summary["errors"], "falls": summary["falls"],
            "paper_mean": paper[0] if paper else None, "paper_se": paper[1] if paper else None,
            "half_time": half_time, "size": size, "wall": round(wall, 1)}


def run(names: list[str], games: int, half_time: float, size: int, seed: int, workers: int | None,
        out: Path, per_round: int = 2, resume: bool = False, progress=sys.stderr,
        factory: Callable[[], cf.Executor] | None = None) -> list[dict]:
    """Play the variants in rounds of `per_round` games each up to `games`, writing the
    table after each round to OUT/table.md and OUT/ablation.jsonl; the rows of the last."""
    executors = ExecutorFactory(workers=workers)
    pool = SharedPool(factory or executors)
    rows: dict[str, dict] = {}
    walls = dict.fromkeys(names, 0.0)
    try:
        played = 0
        while played < games:
            played = min(games, played + per_round)
            for name in names:
                settings = BatchSettings(f"villa:{name}", "villa", half_time, seed, size, size)
                start = time.perf_counter()
                s = run_batch(settings, played, out / name, teams.factory, pool,
                              resume=resume or played > per_round, progress=None)
                walls[name] += time.perf_counter() - start
                rows[name] = variant_row(name, s, half_time, size, walls[name])
            ordered = [rows[n] for n in names]
            write_outputs(out, ordered, header(games=played, half_time=half_time, size=size, seed=seed))
            if progress is not None:
                print(f"round: {played} of {games} games per variant", file=progress, flush=True)
                print(table(ordered), file=progress, flush=True)
    finally:
        pool.close()
        executors.close()
    return [rows[n] for n in names]


def report(out: Path, names: list[str] | None = None) -> tuple[list[dict], str | None]:
    """The rows of the games already in OUT (every game each variant has, so the
    counts may differ by a round), without playing, each variant's settings read
    from its batch.json; table.md, ablation.jsonl and ablation.png rewritten.
    names: the variants to show (default all), those with games in OUT. Returns the rows
    and the rank correlation's sentence."""
    names = [n for n in (VARIANTS if names is None else names) if (out / n / GAMES).exists()]
    if not names:
        raise BatchError(f"{out} holds no variant's {GAMES}")
    rows, settings = [], None
    for name in names:
        path = out / name / SETTINGS
        try:
            saved = json.loads(path.read_text())
            settings = BatchSettings(*(saved[k] for k in ("home", "away", "half_time", "seed",
                                                          "home_size", "away_size")))
        except (OSError, ValueError, KeyError) as exc:
            raise BatchError(f"{path}: cannot read the batch's settings ({exc})") from None
        done, _ = read_games(out / name / GAMES)
        rows.append(variant_row(name, summarize(settings, list(done.values())), settings.half_time,
                                settings.home_size, 0.0))
    n = min(r["n"] for r in rows)
    head = header(n, settings.half_time, settings.home_size, settings.seed) + " (at least; see each count)"
    return rows, write_outputs(out, rows, head)


def agreement_line(agree: dict | None) -> str | None:
    """`rank_agreement`'s answer as a sentence (None: too few variants)."""
    if agree is None:
        return None
    low, high = agree["rho_95"]
    return (f"Spearman rank correlation with the paper's column over {agree['variants']} variants: "
            f"rho {agree['spearman_rho']}, p {agree['p']} (95% interval {low} .. {high} over our means "
            f"redrawn from their standard errors)")


def write_outputs(out: Path, rows: list[dict], head: str) -> str | None:
    """OUT/ablation.jsonl (one row a variant), OUT/table.md (the table under `head`, with the
    rank correlation with the paper's column below it) and OUT/ablation.png; that sentence."""
    write_text(out / "ablation.jsonl", "".join(json.dumps(r) + "\n" for r in rows))
    agree = agreement_line(rank_agreement(rows))
    write_text(out / "table.md", head + "\n\n" + table(rows) + "\n" + (f"\n{agree}\n" if agree else ""))
    write_plot(out / "ablation.png", rows, head)
    return agree


def header(games: int, half_time: float, size: int, seed: int) -> str:
    return (f"{games} games per variant of 2 x {half_time:g} s, {size} vs {size}, from seed {seed}; "
            f"paper: 100 games of 2 x 300 s, 11 vs 11")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks.ablation", description=__doc__.split("\n\n")[0])
    p.add_argument("--games", type=int, default=100, help="games per variant (default 100)")
    p.add_argument("--round", type=int, default=2, dest="per_round",
                   help="games per variant in each round (default 2: one from each side)")
    p.add_argument("--half-time", type=float, default=300.0, help="s per half (default 300)")
    p.add_argument("--workers", type=int, default=None, help="worker processes (default one per core)")
    p.add_argument("--variants", default=",".join(VARIANTS), help="comma-separated (default all)")
    p.add_argument("--size", type=int, default=11, help="players a side (default 11)")
    p.add_argument("--seed", type=int, default=0, help="seed of game 0 (default 0)")
    p.add_argument("--out", type=Path, default=None,
                   help="keep the batches and tables here (default a temp dir)")
    p.add_argument("--resume", action="store_true", help="continue the run in --out")
    p.add_argument("--report", action="store_true",
                   help="only tabulate the games already in --out (a stopped run's every game)")
    args = p.parse_args(argv)
    if args.games < 1 or args.per_round < 1:
        p.error(f"--games and --round must be at least 1 (got {args.games} and {args.per_round})")
    if (args.resume or args.report) and args.out is None:
        p.error("--resume and --report need the --out of a run")
    try:
        names = [variant_name(v) for v in args.variants.split(",") if v.strip()]
    except UnknownVariant as exc:
        print(f"benchmarks.ablation: error: {exc}", file=sys.stderr)
        return 2
    if args.report:
        try:
            rows, agree = report(args.out, names if args.variants != ",".join(VARIANTS) else None)
        except BatchError as exc:
            print(f"benchmarks.ablation: error: {exc}", file=sys.stderr)
            return 2
        print(table(rows))
        if agree:
            print(f"\n{agree}")
        return 0
    print(json.dumps({"machine": machine()}), flush=True)
    with tempfile.TemporaryDirectory(prefix="ablation-") as tmp:
        out = args.out or Path(tmp)
        try:
            rows = run(names, args.games, args.half_time, args.size, args.seed, args.workers, out,
                       args.per_round, args.resume)
        except BatchError as exc:
            print(f"benchmarks.ablation: error: {exc}", file=sys.stderr)
            return 2
    for r in rows:
        print(json.dumps(r))
    agree = rank_agreement(rows)
    print(json.dumps({"rank_agreement_with_paper": agree}))
    print()
    print(header(args.games, args.half_time, args.size, args.seed))
    print(table(rows))
    if agree is not None:
        print(f"\n{agreement_line(agree)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

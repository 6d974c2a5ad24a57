"""Batches of matches: many seeded games between two teams, in parallel, judged as
UT Austin Villa judged every change: by the mean goal difference and its standard error.

Game i uses seed S0 + i; team A plays left in even games and right in odd ones,
so the field's sides cancel. Each finished game is one JSON line appended to
DIR/games.jsonl (one write, flushed and fsynced); a killed batch continues with
`resume=True`, playing only the missing games (a torn last line is ignored), and
ends with the same DIR/summary.json as an uninterrupted one.

Teams are given by spec (a string) and turned into agent factories by a `resolve`
function the caller passes in (the CLI passes `cli.teams.factory`), in each worker,
so this module imports no team code. A game that fails (an exception, a factory
that raises, physics that diverges) is an error row with its seed and the
traceback's last line; the batch goes on. An agent that crashes is not a failed
game: the match goes on without it (an "agent_crashed" event).

The statistics (`describe`, `compare`) are pure functions of numbers.
"""

from __future__ import annotations

import concurrent.futures as cf
import json
import math
import os
import subprocess
import sys
import time
import traceback
from collections import Counter, deque
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import IO

GAMES = "games.jsonl"
SUMMARY = "summary.json"
SETTINGS = "batch.json"
LOGS = "logs"
RETRIES = 1  # extra attempts of a game whose worker died (not of a game that raised)


class BatchError(ValueError):
    """A batch that cannot start or continue (one line, for the command line)."""


# ---------------------------------------------------------------------- statistics


@dataclass(frozen=True)
class Stats:
    """Sample statistics of n numbers: mean, standard deviation (ddof 1), standard
    error of the mean and the 95% t-interval of the mean (None where n is too small)."""

    n: int
    mean: float | None
    sd: float | None
    se: float | None
    ci95: tuple[float, float] | None

    def to_dict(self) -> dict:
        d = asdict(self)
        d["ci95"] = list(self.ci95) if self.ci95 is not None else None
        return d


def describe(values: Iterable[float], confidence: float = 0.95) -> Stats:
    """Mean, standard deviation, standard error and the t-interval of the mean."""
    from scipy import stats as st

    x = [float(v) for v in values]
    n = len(x)
    if n == 0:
        return Stats(0, None, None, None, None)
    mean = math.fsum(x) / n
    if n == 1:
        return Stats(1, mean, None, None, None)
    sd = math.sqrt(math.fsum((v - mean) ** 2 for v in x) / (n - 1))
    se = sd / math.sqrt(n)
    half = float(st.t.ppf(0.5 + confidence / 2, n - 1)) * se
    return Stats(n, mean, sd, se, (mean - half, mean + half))


@dataclass(frozen=True)
class Comparison:
    """A two-sample test of means; unpacks as (t, p)."""

    t: float
    p: float
    df: float
    test: str = "Welch's two-sample t-test (unequal variances)"

    def __iter__(self):
        return iter((self.t, self.p))


def compare(a: Stats, b: Stats) -> Comparison:
    """Welch's t-test of mean(a) != mean(b) from two samples' statistics (two-sided)."""
    from scipy import stats as st

    if a.n < 2 or b.n < 2 or a.sd is None or b.sd is None:
        raise ValueError("compare needs at least 2 values in each sample")
    t, p = st.ttest_ind_from_stats(a.mean, a.sd, a.n, b.mean, b.sd, b.n, equal_var=False)
    va, vb = a.sd ** 2 / a.n, b.sd ** 2 / b.n
    df = (va + vb) ** 2 / (va ** 2 / (a.n - 1) + vb ** 2 / (b.n - 1)) if va + vb > 0 else float("nan")
    return Comparison(float(t), float(p), float(df))


# -------------------------------------------------------------------------- games


@dataclass(frozen=True)
class BatchSettings:
    """What a batch is: teams A (home) and B (away) by spec, half time, first seed and
    team sizes. A resumed batch must have the same."""

    home: str
    away: str
    half_time: float
    seed: int = 0
    home_size: int = 11
    away_size: int = 11

    def game_seed(self, index: int) -> int:
        return self.seed + index

    @staticmethod
    def a_side(index: int) -> str:
        """Team A's side in game `index`: left in even games, right in odd ones."""
        return "L" if index % 2 == 0 else "R"


def last_line(exc: BaseException) -> str:
    """The last line of the exception's traceback ("Type: message")."""
    lines = traceback.format_exception_only(type(exc), exc)
    text = "".join(lines).strip().splitlines()
    return text[-1] if text else type(exc).__name__


_FACTORIES: dict[tuple, Callable] = {}  # per worker process: resolved once


def _factory(resolve: Callable[[str], Callable], spec: str) -> Callable:
    key = (resolve, spec)
    if key not in _FACTORIES:
        _FACTORIES[key] = resolve(spec)
    return _FACTORIES[key]


def play_game(settings: BatchSettings, index: int, resolve: Callable[[str], Callable],
              log_dir: str | None = None) -> dict:
    """Play game `index` (in a worker) and return its row; a failure is an error row."""
    from server.log import write_log
    from server.match import Match, lineup_for

    side = settings.a_side(index)
    seed = settings.game_seed(index)
    row: dict = {"game": index, "seed": seed, "a_side": side,
                 "teams": {"A": settings.home, "B": settings.away}}
    start = time.perf_counter()
    try:
        fa, fb = _factory(resolve, settings.home), _factory(resolve, settings.away)
        if side == "L":
            left, right, sizes = fa, fb, (settings.home_size, settings.away_size)
            names = (settings.home, settings.away)
        else:
            left, right, sizes = fb, fa, (settings.away_size, settings.home_size)
            names = (settings.away, settings.home)
        match = Match(left, right, lineup_for(left, right, *sizes, names), half_time=settings.half_time,
                      seed=seed, record=log_dir is not None, team_names=names)
        result = match.run().to_dict()
        if log_dir is not None:
            path = Path(log_dir) / f"game_{index:05d}.npz"
            write_log(match.match_log(), path)
            row["log"] = str(path)
    except Exception as exc:  # noqa: BLE001 - a failed game is a row, the batch goes on
        row["error"] = last_line(exc)
        row["wall_time"] = round(time.perf_counter() - start, 3)
        return row
    row.update(game_row(result, side))
    return row


def game_row(result: dict, a_side: str) -> dict:
    """A match result (`MatchResult.to_dict`) seen from team A, which played `a_side`."""
    b_side = "R" if a_side == "L" else "L"
    ab = {a_side: "A", b_side: "B"}
    score = {"A": result["score"][a_side], "B": result["score"][b_side]}
    goals = Counter(ab.get(e["team"]) for e in result["events"] if e["kind"] == "goal")
    stats = result["stats"]
    crashes = [{"team": ab.get(e["team"]), "player": e["player"], "time": e["time"], "reason": e["detail"]}
               for e in result["events"] if e["kind"] == "agent_crashed"]
    # Game time of each goal, for the scoring team (own goals count for the other team).
    goal_times = [{"team": ab.get(e["team"]), "time": e["time"], "player": e["player"]}
                  for e in result["events"] if e["kind"] == "goal"]
    return {
        "score": score, "goal_difference": score["A"] - score["B"],
        "goals": {"A": goals.get("A", 0), "B": goals.get("B", 0)}, "goal_times": goal_times,
        "events": dict(sorted(Counter(e["kind"] for e in result["events"]).items())),
        "crashes": crashes,
        "falls": {"A": stats[a_side]["falls"], "B": stats[b_side]["falls"]},
        **({"types": {"A": result["lineup"][a_side], "B": result["lineup"][b_side]}}
           if "lineup" in result else {}),
        "possession": {"A": stats[a_side]["possession_share"], "B": stats[b_side]["possession_share"]},
        "touches": {"A": stats[a_side]["ball_touches"], "B": stats[b_side]["ball_touches"]},
        # the ball's mean x in play toward B's goal (m); older results have none
        **({"territory": stats[a_side]["territory"]} if "territory" in stats[a_side] else {}),
        "wall_time": result["wall_time"], "game_time": result["game_time"],
    }


def provenance() -> dict:
    """The project's version and git commit (with -dirty), where known."""
    out: dict = {}
    try:
        from importlib.metadata import version
        out["version"] = version("nao-soccer")
    except Exception:  # noqa: BLE001 - not installed: no version
        pass
    try:
        here = Path(__file__).resolve().parent.parent
        commit = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"], cwd=here,
                                capture_output=True, text=True, timeout=10)
        if commit.returncode == 0 and commit.stdout.strip():
            out["commit"] = commit.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        pass
    return out


# -------------------------------------------------------------------- games.jsonl


def read_games(path: Path) -> tuple[dict[int, dict], int]:
    """The rows of a games.jsonl by game index (the last row of an index wins) and
    the length of its complete part; a torn last line (a killed write) is ignored."""
    if not path.exists():
        return {}, 0
    data = path.read_bytes()
    rows: dict[int, dict] = {}
    good = 0
    lines = data.split(b"\n")
    for k, line in enumerate(lines):
        complete = k < len(lines) - 1
        if not line.strip():
            good += len(line) + complete
            continue
        try:
            row = json.loads(line)
            index = int(row["game"])
        except (ValueError, KeyError, TypeError):
            if not complete or k == len(lines) - 2 and not lines[-1]:
                break  # the torn last line of a killed batch
            raise BatchError(f"{path}:{k + 1}: not a game record; repair or remove the line") from None
        if not complete:
            break  # parses, but its newline never made it: write it again
        rows[index] = row
        good += len(line) + 1
    return rows, good


class GameLog:
    """Appends rows to games.jsonl: one write per line, flushed and fsynced."""

    def __init__(self, path: Path, keep: int) -> None:
        self.fd = os.open(path, os.O_WRONLY | os.O_CREAT, 0o666)
        os.ftruncate(self.fd, keep)  # drop a torn last line
        os.lseek(self.fd, 0, os.SEEK_END)

    def append(self, row: dict) -> None:
        data = (json.dumps(row, separators=(",", ":")) + "\n").encode()
        view = memoryview(data)
        while view:
            view = view[os.write(self.fd, view):]
        os.fsync(self.fd)

    def close(self) -> None:
        os.close(self.fd)


# ------------------------------------------------------------------------ summary


def summarize(settings: BatchSettings, rows: Sequence[dict]) -> dict:
    """The batch's summary from its rows (order does not matter)."""
    rows = sorted(rows, key=lambda r: r["game"])
    ok = [r for r in rows if "error" not in r]
    gd = describe(r["goal_difference"] for r in ok)

    def mean(values: list[float]) -> float | None:
        return round(math.fsum(values) / len(values), 6) if values else None

    def rounded(s: Stats) -> dict:
        d = s.to_dict()
        for k in ("mean", "sd", "se"):
            if d[k] is not None:
                d[k] = round(d[k], 6)
        if d["ci95"] is not None:
            d["ci95"] = [round(v, 6) for v in d["ci95"]]
        return d

    return {
        "teams": {"A": settings.home, "B": settings.away},
        "half_time": settings.half_time, "seed": settings.seed,
        "sizes": {"A": settings.home_size, "B": settings.away_size},
        "games": len(rows), "played": len(ok), "errors": len(rows) - len(ok),
        "error_games": [r["game"] for r in rows if "error" in r],
        "goal_difference": rounded(gd),
        "wins": sum(r["goal_difference"] > 0 for r in ok),
        "draws": sum(r["goal_difference"] == 0 for r in ok),
        "losses": sum(r["goal_difference"] < 0 for r in ok),
        "goals_for": sum(r["score"]["A"] for r in ok),
        "goals_against": sum(r["score"]["B"] for r in ok),
        "goal_difference_by_a_side": {
            s: mean([r["goal_difference"] for r in ok if r["a_side"] == s]) for s in ("L", "R")},
        "falls": {t: mean([r["falls"][t] for r in ok]) for t in ("A", "B")},
        "possession": {t: mean([r["possession"][t] for r in ok]) for t in ("A", "B")},
        "territory": rounded(describe(r["territory"] for r in ok if "territory" in r)),
        "agent_crashes": {t: sum(c["team"] == t for r in ok for c in r.get("crashes", ())) for t in "AB"},
    }


def running(rows: Iterable[dict]) -> str:
    """Mean goal difference +- standard error so far, for the progress bar."""
    s = describe(r["goal_difference"] for r in rows if "error" not in r)
    if s.mean is None:
        return "GD -"
    return f"GD {s.mean:+.2f}" + (f" +- {s.se:.2f}" if s.se is not None else "")


# ------------------------------------------------------------------------- runner


def _settings_dict(settings: BatchSettings) -> dict:
    return asdict(settings)


def prepare(settings: BatchSettings, out: Path, resume: bool) -> tuple[dict[int, dict], int]:
    """Check DIR against the settings (BatchError when it may not be used) and return
    the rows already there and the length of games.jsonl's complete part."""
    games, saved = out / GAMES, out / SETTINGS
    if not resume:
        if games.exists():
            raise BatchError(f"{out} already holds a batch ({GAMES}); continue it with --resume "
                             f"or pick another --out")
        return {}, 0
    if not games.exists():
        return {}, 0
    if not saved.exists():
        raise BatchError(f"{out} has {GAMES} but no {SETTINGS}: cannot check what batch it was")
    try:
        recorded = json.loads(saved.read_text())
    except ValueError:
        raise BatchError(f"{saved} is not valid JSON") from None
    now = _settings_dict(settings)
    diff = [f"{k} {recorded.get(k)!r} != {now[k]!r}" for k in now if recorded.get(k) != now[k]]
    if diff:
        raise BatchError(f"cannot resume {out}: it was a different batch ({'; '.join(diff)})")
    return read_games(games)


def run_batch(settings: BatchSettings, games: int, out: str | os.PathLike,
              resolve: Callable[[str], Callable], executor_factory: Callable[[], cf.Executor],
              resume: bool = False, logs: bool = False, inflight: int | None = None,
              progress: IO | None = sys.stderr, on_row: Callable[[dict], None] | None = None) -> dict:
    """Play games 0..games-1 (those not yet in DIR with `resume`) and return the summary,
    also written to DIR/summary.json. `executor_factory()` gives the executor (called
    again if a local worker dies); `inflight` bounds the games submitted at once."""
    from server.files import write_text

    out = Path(out)
    done, keep = prepare(settings, out, resume)
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / SETTINGS, json.dumps({**_settings_dict(settings), "games": games}, indent=2) + "\n")
    log_dir = str(out / LOGS) if logs else None
    if log_dir:
        Path(log_dir).mkdir(exist_ok=True)
    meta = provenance()
    todo = deque(i for i in range(games) if i not in done)
    rows = [r for i, r in done.items() if i < games]
    bar = None
    if progress is not None:
        from tqdm import tqdm
        bar = tqdm(total=games, initial=len(rows), unit="game", file=progress, dynamic_ncols=True,
                   mininterval=0.2 if getattr(progress, "isatty", lambda: False)() else 10.0)
        bar.set_postfix_str(running(rows), refresh=False)
    gamelog = GameLog(out / GAMES, keep)
    executor = executor_factory() if todo else None
    limit = inflight or max(len(todo), 1)
    pending: dict[cf.Future, int] = {}
    attempts: Counter = Counter()

    def record(row: dict) -> None:
        row.update(meta)
        gamelog.append(row)
        rows.append(row)
        if on_row is not None:
            on_row(row)
        if bar is not None:
            bar.update(1)
            bar.set_postfix_str(running(rows), refresh=False)

    clean = False
    try:
        while todo or pending:
            while todo and len(pending) < limit:
                i = todo.popleft()
                pending[executor.submit(play_game, settings, i, resolve, log_dir)] = i
            finished, _ = cf.wait(list(pending), return_when=cf.FIRST_COMPLETED)
            broken = False
            for fut in sorted(finished, key=lambda f: pending[f]):
                i = pending.pop(fut)
                try:
                    row = fut.result()
                except KeyboardInterrupt:
                    raise
                except BaseException as exc:  # noqa: BLE001 - the worker, not the game, failed
                    broken = broken or isinstance(exc, cf.BrokenExecutor)
                    attempts[i] += 1
                    if attempts[i] <= RETRIES:
                        todo.appendleft(i)
                        continue
                    row = {"game": i, "seed": settings.game_seed(i), "a_side": settings.a_side(i),
                           "teams": {"A": settings.home, "B": settings.away},
                           "error": f"worker failed: {last_line(exc)}"}
                record(row)
            if broken:  # a dead local worker broke the pool: its games in flight run again
                todo.extendleft(sorted(pending.values(), reverse=True))
                pending.clear()
                _shutdown(executor)
                executor = executor_factory()
        clean = True
    finally:
        gamelog.close()
        if bar is not None:
            bar.close()
        if executor is not None:
            _shutdown(executor, cancel=not clean)
    summary = summarize(settings, rows)
    write_text(out / SUMMARY, json.dumps(summary, indent=2) + "\n")
    return summary


def _shutdown(executor: cf.Executor, cancel: bool = False) -> None:
    try:
        executor.shutdown(wait=not cancel, cancel_futures=cancel)
    except TypeError:  # Dask's executor has no cancel_futures
        executor.shutdown(wait=not cancel)


# ----------------------------------------------------------------------- baselines

BASELINE_KIND = "nao-soccer batch baseline"
ALPHA = 0.05  # one-sided significance of "worse than the baseline"


def make_baseline(summary: dict, note: str = "") -> dict:
    """A baseline (the last accepted team's goal difference) from a batch summary."""
    gd = summary["goal_difference"]
    out = {"kind": BASELINE_KIND, "teams": summary["teams"], "half_time": summary["half_time"],
           "seed": summary["seed"], "sizes": summary["sizes"], "games": summary["played"],
           "goal_difference": {k: gd[k] for k in ("n", "mean", "sd", "se")},
           "wins": summary["wins"], "draws": summary["draws"], "losses": summary["losses"],
           "created": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), **provenance()}
    if note:
        out["note"] = note
    return out


def save_baseline(path: str | os.PathLike, summary: dict, note: str = "") -> dict:
    """Write the baseline of `summary` to `path` atomically and return it."""
    from server.files import write_json

    base = make_baseline(summary, note)
    write_json(path, base)
    return base


def read_baseline(path: str | os.PathLike) -> dict:
    """A stored baseline; BatchError (one line) when it is missing or malformed."""
    path = Path(path)
    try:
        base = json.loads(path.read_text())
    except OSError as exc:
        raise BatchError(f"cannot read baseline {path}: {exc.strerror or exc}") from None
    except ValueError:
        raise BatchError(f"baseline {path} is not valid JSON") from None
    if not isinstance(base, dict) or base.get("kind") != BASELINE_KIND:
        raise BatchError(f"{path} is not a batch baseline (no \"kind\": {BASELINE_KIND!r})")
    try:
        baseline_stats(base)
    except (KeyError, TypeError, ValueError):
        raise BatchError(f"baseline {path} has no goal_difference n, mean and sd") from None
    return base


def describe_dict(gd: dict) -> Stats:
    """Stats from their dict (a summary's goal_difference)."""
    ci = gd.get("ci95")
    return Stats(int(gd["n"]), gd["mean"], gd.get("sd"), gd.get("se"), tuple(ci) if ci else None)


def baseline_stats(base: dict) -> Stats:
    """The goal-difference statistics a baseline stores."""
    gd = base["goal_difference"]
    n = int(gd["n"])
    mean = None if gd["mean"] is None else float(gd["mean"])
    sd = None if gd.get("sd") is None else float(gd["sd"])
    se = sd / math.sqrt(n) if sd is not None and n > 0 else None
    return Stats(n, mean, sd, se, None)


@dataclass(frozen=True)
class Regression:
    """A batch against a baseline: is its mean goal difference significantly worse?"""

    new: Stats
    base: Stats
    t: float | None
    df: float | None
    p: float | None  # one-sided: P(a t this low | the means are equal)
    worse: bool
    alpha: float = ALPHA
    test: str = "Welch's two-sample t-test, one-sided (new mean < baseline mean)"
    reason: str = ""  # why there is no p where there is none

    def text(self) -> str:
        def fmt(s: Stats) -> str:
            sd = "-" if s.sd is None else f"{s.sd:.3f}"
            se = "-" if s.se is None else f"{s.se:.3f}"
            mean = "-" if s.mean is None else f"{s.mean:+.3f}"
            return f"{mean} (se {se}, sd {sd}, n {s.n})"
        lines = [f"goal difference: new {fmt(self.new)}, baseline {fmt(self.base)}"]
        if self.t is None:
            lines.append(f"{self.test}: p = {self.p:g}, {self.reason}")
        else:
            lines.append(f"{self.test}: t = {self.t:+.3f}, df = {self.df:.1f}, p = {self.p:.4f}")
        verdict = "WORSE than the baseline" if self.worse else "not significantly worse than the baseline"
        lines.append(f"verdict at p < {self.alpha:g}: {verdict}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"new": self.new.to_dict(), "baseline": self.base.to_dict(), "t": self.t, "df": self.df,
                "p": self.p, "worse": self.worse, "alpha": self.alpha, "test": self.test,
                "reason": self.reason}


def against(new: Stats, base: Stats, alpha: float = ALPHA) -> Regression:
    """Is `new`'s mean significantly below `base`'s (Welch, one-sided, p < alpha)?
    Needs n >= 2 on both sides (ValueError otherwise). Two samples without any spread
    compare their means exactly (p 0 when lower, 1 otherwise)."""
    from scipy import stats as st

    if new.n < 2 or base.n < 2 or new.sd is None or base.sd is None:
        raise ValueError(f"a comparison with the baseline needs at least 2 games on each side "
                         f"(new {new.n}, baseline {base.n})")
    vn, vb = new.sd ** 2 / new.n, base.sd ** 2 / base.n
    if vn + vb == 0.0:
        lower = new.mean < base.mean
        return Regression(new, base, None, None, 0.0 if lower else 1.0, lower, alpha,
                          reason="no spread in either sample: the means compared exactly")
    c = compare(new, base)
    p = float(st.t.cdf(c.t, c.df))
    return Regression(new, base, c.t, c.df, p, p < alpha, alpha)


def settings_mismatch(base: dict, summary: dict) -> list[str]:
    """How a batch's settings differ from its baseline's (teams, half time, sizes)."""
    out = []
    for key in ("teams", "half_time", "sizes"):
        if base.get(key) != summary.get(key):
            out.append(f"{key} {base.get(key)!r} in the baseline, {summary.get(key)!r} now")
    return out

"""A CMA-ES job: generations of seeded, parallel trials, checkpointed and resumable.

Each generation: CMA-ES proposes `population` points (`cma` package, minimizing
minus the fitness); each point is evaluated over `trials` seeded trials (the
same seeds for every point of a generation, new seeds each generation); its
fitness is the trials' mean, its spread their standard deviation. Results are
sorted by candidate and trial before CMA-ES sees them, so a job's result does
not depend on how many workers ran it or in what order they finished.

Files in the job's directory, all written atomically (temporary file, then
``os.replace``) after every generation:

* ``checkpoint.pkl``: the CMA-ES object (whose normal sampler draws from its own
  seeded ``numpy.random.RandomState``, pickled with it, so no global RNG state
  is involved), the generation, the history and the best point;
* ``history.csv``: one row per generation (fitness best, mean, spreads, sigma);
* ``best.txt``: the best point's parameters, UT style (all sets the task uses,
  prefixed by set), readable by the sets' loaders (`skills.walk.load_walk_sets`);
* ``mean.txt``: the same for the mean of CMA-ES's search distribution. With
  noisy trials the best point's fitness is biased up (it is the luckiest of
  many draws); the mean averages over the population and is usually the
  better pick to validate on fresh seeds;
* ``fitness.png``: best and mean fitness per generation (redrawn at most every
  `PLOT_EVERY` seconds of wall time, and when the job ends).

A killed job resumed from its directory continues from its last checkpoint and
ends with the same result as an uninterrupted run with the same seed.
"""

from __future__ import annotations

import csv
import io
import logging
import math
import pickle
import sys
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import TextIO

import cma
import numpy as np

from optimization.executor import Evaluator, ExecutorFactory, TrialRequest
from optimization.paramvec import ParamSpace, write_param_file
from optimization.types import Task, Values
from server.files import write_bytes, write_text

CHECKPOINT = "checkpoint.pkl"
HISTORY = "history.csv"
BEST = "best.txt"
MEAN = "mean.txt"
PLOT = "fitness.png"
FORMAT = 1
PLOT_EVERY = 30.0  # s of wall time between redraws of the plot

log = logging.getLogger("optimization")


@dataclass(frozen=True)
class JobSettings:
    """population None: CMA-ES's default 4 + 3 ln(n); sigma: initial step in units of each
    parameter's scale; trials: seeded trials per candidate; seed: CMA-ES and trial seeds."""

    population: int | None = None
    generations: int = 10
    sigma: float = 1.0
    trials: int = 1
    seed: int = 0


@dataclass
class Problem:
    """What a job optimizes: the task, the parameter space, and a label for files and logs."""

    task: Task
    space: ParamSpace
    label: str = ""


@dataclass
class Best:
    """The best candidate so far (by mean fitness over its trials)."""

    fitness: float = -math.inf
    spread: float = 0.0
    generation: int = -1
    z: np.ndarray | None = None


@dataclass
class JobResult:
    best_fitness: float
    best_spread: float
    best_generation: int
    best_values: Values
    best_named: dict[str, float]
    history: list[dict]
    out_dir: Path
    failures: list[str] = field(default_factory=list)


def trial_seed(seed: int, generation: int, trial: int) -> int:
    """The seed of trial `trial` of every candidate in `generation`."""
    return int(np.random.SeedSequence([seed, generation, trial]).generate_state(1)[0])


def new_es(space: ParamSpace, settings: JobSettings) -> cma.CMAEvolutionStrategy:
    lo, hi = space.z_bounds()
    bounded = any(math.isfinite(v) for v in lo + hi)
    rng = np.random.RandomState(settings.seed % 2**32)
    opts = {"seed": settings.seed % 2**32 or 1, "randn": rng.randn, "verbose": -9,
            "maxiter": settings.generations, "tolfun": 0.0, "tolfunhist": 0.0, "tolx": 0.0,
            "tolstagnation": 10**9, "tolflatfitness": 10**9}
    if settings.population:
        opts["popsize"] = settings.population
    if bounded:
        opts["bounds"] = [[v if math.isfinite(v) else None for v in lo],
                          [v if math.isfinite(v) else None for v in hi]]
    return cma.CMAEvolutionStrategy(np.zeros(space.dim), settings.sigma, opts)


COLUMNS = ("generation", "evaluations", "best", "mean", "std", "trial_spread", "best_so_far",
           "best_so_far_spread", "sigma", "failures", "elapsed_s")


class Job:
    """One CMA-ES run in `out_dir` (created). Use `Job.resume(out_dir, ...)` to continue one."""

    def __init__(self, problem: Problem, settings: JobSettings, out_dir: Path | str,
                 executor: ExecutorFactory | Callable | None = None, progress: TextIO | None = sys.stderr,
                 plot: bool = True) -> None:
        self.problem = problem
        self.settings = settings
        self.out_dir = Path(out_dir)
        self.factory = executor if executor is not None else ExecutorFactory()
        self.progress = progress
        self.plot = plot
        self.es = new_es(problem.space, settings)
        self.generation = 0
        self.history: list[dict] = []
        self.best = Best()
        self.failures: list[str] = []
        self.elapsed = 0.0
        self._plotted: float | None = None  # wall clock of the last plot

    # -------------------------------------------------------------- checkpoints

    @classmethod
    def resume(cls, out_dir: Path | str, executor: ExecutorFactory | Callable | None = None,
               progress: TextIO | None = sys.stderr, plot: bool = True) -> Job:
        """The job saved in `out_dir`, ready to continue where its last checkpoint left it."""
        path = Path(out_dir) / CHECKPOINT
        if not path.exists():
            raise FileNotFoundError(f"no checkpoint in {out_dir} ({CHECKPOINT} missing)")
        with open(path, "rb") as fh:
            state = pickle.load(fh)
        if state.get("format") != FORMAT:
            raise ValueError(f"{path}: checkpoint format {state.get('format')} is not {FORMAT}")
        job = cls(state["problem"], state["settings"], out_dir, executor, progress, plot)
        job.es = pickle.loads(state["es"])
        job.generation = state["generation"]
        job.history = state["history"]
        job.best = state["best"]
        job.failures = state["failures"]
        job.elapsed = state["elapsed"]
        return job

    def _checkpoint(self) -> None:
        state = {"format": FORMAT, "problem": self.problem, "settings": self.settings,
                 "es": pickle.dumps(self.es), "generation": self.generation, "history": self.history,
                 "best": self.best, "failures": self.failures, "elapsed": self.elapsed,
                 "done": self.done}
        write_bytes(self.out_dir / CHECKPOINT, pickle.dumps(state), fsync=True)

    @property
    def done(self) -> bool:
        return self.generation >= self.settings.generations

    # ------------------------------------------------------------------ running

    def run(self) -> JobResult:
        """Run the remaining generations; files are updated after each one."""
        self.out_dir.mkdir(parents=True, exist_ok=True)
        evaluator = Evaluator(self.problem.task, self.factory)
        try:
            if self.generation == 0 and not self.history:
                s = self.settings
                where = self.factory.describe() if isinstance(self.factory, ExecutorFactory) else "executor"
                self._say(f"{self.problem.label or self.problem.task.name}: {self.problem.space.dim} "
                          f"parameters, population {self.es.popsize}, {s.trials} trial(s) per candidate, "
                          f"{s.generations} generations, seed {s.seed}, {where}")
            while not self.done:
                self._generation(evaluator)
        finally:
            evaluator.close()
        return self.result()

    def _generation(self, evaluator: Evaluator) -> None:
        start = time.perf_counter()
        space, s = self.problem.space, self.settings
        X = self.es.ask()
        seeds = [trial_seed(s.seed, self.generation, t) for t in range(s.trials)]
        requests = [TrialRequest(c, t, seeds[t], space.values(x)) for c, x in enumerate(X)
                    for t in range(s.trials)]
        before = len(evaluator.failures)
        outcomes = evaluator.evaluate_all(requests)
        F = np.empty((len(X), s.trials))
        for o in outcomes:
            F[o.candidate, o.trial] = o.fitness
        means = F.mean(axis=1)
        spreads = F.std(axis=1, ddof=1) if s.trials > 1 else np.zeros(len(X))
        self.es.tell(X, list(-means))
        k = int(np.argmax(means))
        if means[k] > self.best.fitness:
            self.best = Best(float(means[k]), float(spreads[k]), self.generation, np.array(X[k]))
        new_failures = evaluator.failures[before:]
        self.failures.extend(f"generation {self.generation}: {m}" for m in new_failures)
        self.elapsed += time.perf_counter() - start
        row = {"generation": self.generation,
               "evaluations": (self.history[-1]["evaluations"] if self.history else 0) + len(requests),
               "best": float(means[k]), "mean": float(means.mean()), "std": float(means.std()),
               "trial_spread": float(spreads.mean()), "best_so_far": self.best.fitness,
               "best_so_far_spread": self.best.spread, "sigma": float(self.es.sigma),
               "failures": len(new_failures), "elapsed_s": round(self.elapsed, 3)}
        self.history.append(row)
        self.generation += 1
        self._write_outputs()
        self._checkpoint()
        self._say(f"gen {row['generation'] + 1}/{s.generations}  evals {row['evaluations']}  "
                  f"best {row['best']:.4g}  mean {row['mean']:.4g}  spread {row['trial_spread']:.3g}  "
                  f"best-so-far {self.best.fitness:.4g}  sigma {row['sigma']:.3g}"
                  + (f"  failed {row['failures']}" if row["failures"] else "")
                  + f"  {self.elapsed:.1f} s")

    def _say(self, line: str) -> None:
        if self.progress is not None:
            print(line, file=self.progress, flush=True)

    # ------------------------------------------------------------------ outputs

    def result(self) -> JobResult:
        z = self.best.z if self.best.z is not None else np.zeros(self.problem.space.dim)
        sp = self.problem.space
        return JobResult(self.best.fitness, self.best.spread, self.best.generation, sp.values(z), sp.named(z),
                         list(self.history), self.out_dir, list(self.failures))

    def _write_outputs(self) -> None:
        buf = io.StringIO()
        w = csv.DictWriter(buf, fieldnames=COLUMNS, lineterminator="\n")
        w.writeheader()
        for row in self.history:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})
        write_text(self.out_dir / HISTORY, buf.getvalue(), fsync=True)
        if self.best.z is not None:
            sp = self.problem.space
            header = (f"best parameters of {self.problem.label or self.problem.task.name} "
                      f"(task {self.problem.task.name}), soccer optimize\n"
                      f"fitness {self.best.fitness:.6g} +- {self.best.spread:.3g} over "
                      f"{self.settings.trials} trial(s), generation {self.best.generation + 1}, "
                      f"seed {self.settings.seed}\n" + optimized_lines(sp))
            write_param_file(self.out_dir / BEST, sp.values(self.best.z), header)
            write_param_file(self.out_dir / MEAN, sp.values(np.asarray(self.es.mean, dtype=float)),
                             f"mean of the CMA-ES search distribution of "
                             f"{self.problem.label or self.problem.task.name} (task "
                             f"{self.problem.task.name}) after generation {self.generation}, "
                             f"seed {self.settings.seed}\n" + optimized_lines(sp))
        now = time.monotonic()
        if self.plot and (self.done or self._plotted is None or now - self._plotted > PLOT_EVERY):
            write_plot(self.out_dir / PLOT, self.history, self.problem.label or self.problem.task.name)
            self._plotted = now


def optimized_lines(space: ParamSpace, width: int = 100) -> str:
    """'optimized SET: a, b, ...' lines, wrapped."""
    import textwrap

    lines = []
    for set_name in dict.fromkeys(s for s, _ in space.keys):
        names = ", ".join(n for s, n in space.keys if s == set_name)
        lines += textwrap.wrap(f"optimized {set_name}: {names}", width, subsequent_indent="    ")
    return "\n".join(lines)


def write_plot(path: Path, history: list[dict], title: str) -> None:
    """Best, mean and best-so-far fitness per generation (matplotlib, Agg backend)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    g = [r["generation"] + 1 for r in history]
    fig, ax = plt.subplots(figsize=(6.4, 4.0), dpi=100)
    mean = np.array([r["mean"] for r in history])
    std = np.array([r["std"] for r in history])
    ax.plot(g, [r["best"] for r in history], "o-", ms=3, label="best of generation")
    ax.plot(g, mean, "s-", ms=3, label="mean of generation")
    ax.fill_between(g, mean - std, mean + std, alpha=0.2, label="mean +- std")
    ax.plot(g, [r["best_so_far"] for r in history], "--", label="best so far")
    ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(integer=True))
    ax.set_xlabel("generation")
    ax.set_ylabel("fitness (higher is better)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    write_bytes(path, buf.getvalue(), fsync=True)


def settings_dict(settings: JobSettings) -> dict:
    return asdict(settings)

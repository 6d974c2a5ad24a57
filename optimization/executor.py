"""Parallel trial evaluation through `concurrent.futures.Executor`, with retries.

`make_executor` gives local worker processes (`ProcessPoolExecutor`, the
default), the calling process itself (``workers=0``, for debugging and
profiling), or a Dask cluster (``scheduler="tcp://host:8786"``; Dask's
``Client.get_executor()`` is a `concurrent.futures.Executor`).

`evaluate_all` runs a batch of trial requests and returns their outcomes in
request order, whatever order they finish in, so results do not depend on
worker count or scheduling. A trial that raises, or whose worker dies, is
retried once (on a rebuilt pool when a local worker died and broke it); if it
fails again it gets the task's worst fitness and the reason is logged. The
job goes on.

Each local worker runs its BLAS and OpenMP libraries on one thread
(`one_thread`): a worker is one match or trial on one core, and two workers'
thread pools spinning against each other on a 2-core machine made building a
match 5x slower.
"""

from __future__ import annotations

import concurrent.futures as cf
import logging
import os
import traceback
from collections.abc import Callable, Sequence
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field

from optimization.types import Task, TrialResult, Values

log = logging.getLogger("optimization")
RETRIES = 1  # extra attempts after a failure


@dataclass(frozen=True)
class TrialRequest:
    """One trial to run: which candidate, which of its trials, the seed and the values."""

    candidate: int
    trial: int
    seed: int
    values: Values
    attempt: int = 0


@dataclass
class TrialOutcome:
    """A trial's fitness, or the task's worst fitness and why."""

    candidate: int
    trial: int
    fitness: float
    info: dict = field(default_factory=dict)
    error: str | None = None
    attempts: int = 1


def run_trial(task: Task, request: TrialRequest) -> TrialResult:
    """Run one trial (in a worker). A non-finite fitness counts as a failure."""
    result = task.trial(request.values, request.seed)
    f = float(result.fitness)
    if f != f or f in (float("inf"), float("-inf")):
        raise ValueError(f"trial returned a non-finite fitness {f}")
    return result


def one_thread() -> None:
    """Limit this process's BLAS and OpenMP thread pools to one thread: those loaded
    (numpy's OpenBLAS) through threadpoolctl, those loaded later (scipy's OpenBLAS,
    pinocchio's OpenMP) through the variables they read when they load. The
    initializer of local worker processes."""
    from threadpoolctl import threadpool_limits

    for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[name] = "1"
    threadpool_limits(1)


class InlineExecutor(cf.Executor):
    """Runs each call at submit time in this process (``--workers 0``)."""

    def submit(self, fn, /, *args, **kwargs):  # type: ignore[override]
        fut: cf.Future = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: BLE001 - reported through the future
            if isinstance(exc, KeyboardInterrupt):
                raise
            fut.set_exception(exc)
        return fut


@dataclass
class ExecutorFactory:
    """Makes (and, after a local worker died, remakes) the executor of a job."""

    workers: int | None = None
    scheduler: str | None = None
    client: object | None = None

    def describe(self) -> str:
        if self.scheduler:
            return f"dask scheduler {self.scheduler}"
        if self.workers == 0:
            return "in-process"
        return f"{self.workers or os.cpu_count()} local worker processes"

    def __call__(self) -> cf.Executor:
        if self.scheduler:
            try:
                from distributed import Client
            except ImportError:
                raise RuntimeError("--scheduler needs Dask: pip install 'dask[distributed]'") from None
            if self.client is None:
                self.client = Client(self.scheduler, timeout=30)
            return self.client.get_executor(pure=False)
        if self.workers == 0:
            return InlineExecutor()
        return cf.ProcessPoolExecutor(max_workers=self.workers or os.cpu_count(), initializer=one_thread)

    def close(self) -> None:
        if self.client is not None:
            self.client.close()
            self.client = None


def shutdown(executor: cf.Executor, wait: bool) -> None:
    """Shut an executor down, dropping queued calls where it can (Dask's cannot)."""
    try:
        executor.shutdown(wait=wait, cancel_futures=True)
    except TypeError:
        executor.shutdown(wait=wait)


def _describe(exc: BaseException) -> str:
    last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
    where = f" at {last[0].filename}:{last[0].lineno}" if last else ""
    return f"{type(exc).__name__}: {exc}{where}"


def _broken(exc: BaseException) -> bool:
    """True when the executor itself is unusable (a local worker process died)."""
    return isinstance(exc, BrokenProcessPool | cf.BrokenExecutor)


class Evaluator:
    """Evaluates batches of trials on an executor, retrying failures once."""

    def __init__(self, task: Task, factory: ExecutorFactory | Callable[[], cf.Executor],
                 retries: int = RETRIES) -> None:
        self.task = task
        self.factory = factory
        self.retries = retries
        self.executor: cf.Executor | None = None
        self.failures: list[str] = []

    def _exec(self) -> cf.Executor:
        if self.executor is None:
            self.executor = self.factory()
        return self.executor

    def _rebuild(self) -> None:
        if self.executor is not None:
            shutdown(self.executor, wait=False)
        self.executor = None

    def evaluate_all(self, requests: Sequence[TrialRequest]) -> list[TrialOutcome]:
        """Outcomes of every request, in request order.

        When a local worker dies the whole pool breaks and every trial in flight
        fails with it; those trials are then rerun one at a time on a new pool,
        so that only the trial that kills its worker again is charged the failure.
        """
        outcomes: list[TrialOutcome | None] = [None] * len(requests)
        pending = {self._submit(r): (k, r) for k, r in enumerate(requests)}
        suspects: list[tuple[int, TrialRequest]] = []
        while pending:
            done, _ = cf.wait(list(pending), return_when=cf.FIRST_COMPLETED)
            broken = False
            for fut in done:
                k, req = pending.pop(fut)
                exc = self._collect(fut, k, req, outcomes)
                if exc is None:
                    continue
                if _broken(exc):
                    broken = True
                    suspects.append((k, req))
                else:
                    self._failed(k, req, _describe(exc), outcomes, pending)
            if broken:
                suspects.extend(pending.values())
                pending.clear()
                self._rebuild()
        for k, req in sorted(suspects, key=lambda kr: kr[0]):
            req = TrialRequest(req.candidate, req.trial, req.seed, req.values, req.attempt + 1)
            while True:
                fut = self._submit(req)
                cf.wait([fut])
                exc = self._collect(fut, k, req, outcomes)
                if exc is None:
                    break
                if _broken(exc):
                    self._rebuild()
                if req.attempt >= self.retries:
                    self._give_up(k, req, _describe(exc), outcomes)
                    break
                req = TrialRequest(req.candidate, req.trial, req.seed, req.values, req.attempt + 1)
        return [o for o in outcomes if o is not None]

    def _collect(self, fut: cf.Future, k: int, req: TrialRequest,
                 outcomes: list[TrialOutcome | None]) -> BaseException | None:
        """Store a finished future's outcome; return its exception instead if it failed."""
        try:
            res = fut.result()
        except KeyboardInterrupt:
            raise
        except BaseException as exc:  # noqa: BLE001 - any failure of a trial is handled
            return exc
        outcomes[k] = TrialOutcome(req.candidate, req.trial, float(res.fitness), dict(res.info),
                                   attempts=req.attempt + 1)
        return None

    def _failed(self, k: int, req: TrialRequest, reason: str, outcomes: list[TrialOutcome | None],
                pending: dict) -> None:
        if req.attempt < self.retries:
            log.warning("candidate %d trial %d failed (%s); retrying", req.candidate, req.trial, reason)
            again = TrialRequest(req.candidate, req.trial, req.seed, req.values, req.attempt + 1)
            pending[self._submit(again)] = (k, again)
        else:
            self._give_up(k, req, reason, outcomes)

    def _give_up(self, k: int, req: TrialRequest, reason: str, outcomes: list[TrialOutcome | None]) -> None:
        msg = (f"candidate {req.candidate} trial {req.trial} failed {req.attempt + 1} times; "
               f"given the worst fitness {self.task.worst:g}: {reason}")
        log.error(msg)
        self.failures.append(msg)
        outcomes[k] = TrialOutcome(req.candidate, req.trial, float(self.task.worst), error=reason,
                                   attempts=req.attempt + 1)

    def _submit(self, req: TrialRequest) -> cf.Future:
        try:
            return self._exec().submit(run_trial, self.task, req)
        except BrokenProcessPool:
            self._rebuild()
            return self._exec().submit(run_trial, self.task, req)

    def close(self) -> None:
        if self.executor is not None:
            shutdown(self.executor, wait=True)
            self.executor = None
        if isinstance(self.factory, ExecutorFactory):
            self.factory.close()

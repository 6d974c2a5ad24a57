"""CMA-ES jobs: improvement, determinism, checkpoints and resume, failing trials."""

import csv
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from optimization.executor import ExecutorFactory
from optimization.job import Job, JobSettings, Problem
from optimization.paramvec import ParamSpace, load_values
from optimization.task import AnalyticTask, make_task
from tests.optimization.helpers import FaultyTask

ROOT = Path(__file__).resolve().parents[2]


def problem(task) -> Problem:
    return Problem(task, ParamSpace.build(load_values(task.sets, 0), task.optimize), task.name)


def run(task, out, workers=0, **settings):
    s = JobSettings(**{"population": 8, "generations": 8, "seed": 5, **settings})
    return Job(problem(task), s, out, ExecutorFactory(workers=workers), progress=None, plot=False).run()


def rows(path):
    with open(path) as fh:
        return [{k: v for k, v in r.items() if k != "elapsed_s"} for r in csv.DictReader(fh)]


@pytest.mark.parametrize("name", ["sphere", "rosenbrock"])
def test_cmaes_improves_an_analytic_task(tmp_path, name):
    task = make_task(name, dim=4)
    start = task.trial(load_values(task.sets, 0), 0).fitness
    r = run(task, tmp_path, generations=25)
    assert r.best_fitness > 0.2 * start  # fitness is minus the loss: at least 5 times smaller
    assert r.history[-1]["mean"] > r.history[0]["mean"]
    assert (tmp_path / "best.txt").exists() and len(rows(tmp_path / "history.csv")) == 25


def test_mean_file_holds_the_search_distribution_mean(tmp_path):
    from skills.params import read_entries

    task = make_task("sphere", dim=4, noise=0.3)
    start = task.trial(load_values(task.sets, 0), 0).fitness
    run(task, tmp_path, generations=25, trials=2)
    entries = read_entries([tmp_path / "mean.txt"])
    values = {"analytic": {n[len("analytic_"):]: e.value for n, e in entries.items()}}
    mean_fitness = task.trial(values, 0).fitness  # the noise is seeded: same draw as `start`
    assert mean_fitness > 0.2 * start  # the distribution has moved to the optimum too


def test_noisy_trials_report_mean_and_spread(tmp_path):
    r = run(make_task("sphere", dim=3, noise=0.5), tmp_path, trials=4, generations=3)
    assert all(h["trial_spread"] > 0 for h in r.history)
    assert r.best_spread > 0


def test_result_does_not_depend_on_worker_count(tmp_path):
    task = make_task("sphere", dim=3, noise=0.2)
    a = run(task, tmp_path / "a", workers=0, trials=2, generations=4)
    b = run(task, tmp_path / "b", workers=2, trials=2, generations=4)
    assert a.best_named == b.best_named
    assert rows(tmp_path / "a/history.csv") == rows(tmp_path / "b/history.csv")


def test_killed_job_resumes_to_the_same_result(tmp_path):
    args = ["optimize", "sphere", "--option", "dim=4", "--option", "noise=0.3", "--population", "6",
            "--generations", "8", "--trials", "2", "--seed", "11", "--workers", "0"]
    whole = tmp_path / "whole"
    cut = tmp_path / "cut"
    from cli.main import main
    assert main([*args, "--out", str(whole), "--quiet"]) == 0
    # The same job with slow trials, killed (SIGKILL) once a few generations are checkpointed.
    slow = [*args, "--option", "delay=0.03", "--out", str(cut), "--quiet"]
    proc = subprocess.Popen([sys.executable, "-m", "cli.main", *slow], cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        h = cut / "history.csv"
        if h.exists() and len(rows(h)) >= 3:
            break
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=10)
    assert proc.returncode == -signal.SIGKILL
    done = len(rows(cut / "history.csv"))
    assert 3 <= done < 8, "the job was not killed in the middle"
    assert main(["optimize", "--resume", str(cut), "--workers", "0", "--quiet"]) == 0
    assert rows(cut / "history.csv") == rows(whole / "history.csv")
    strip = [ln for ln in (whole / "best.txt").read_text().splitlines() if not ln.startswith("#")]
    assert [ln for ln in (cut / "best.txt").read_text().splitlines() if not ln.startswith("#")] == strip


def test_a_failing_trial_gets_the_worst_fitness_and_the_job_goes_on(tmp_path, caplog):
    task = FaultyTask(dim=3, mode="raise", threshold=0.3)
    r = run(task, tmp_path, generations=3)
    assert len(r.history) == 3 and r.failures
    assert all("failed 2 times" in f and "out of the simulator's range" in f for f in r.failures)
    assert "retrying" in caplog.text
    assert all(h["best"] > task.worst for h in r.history)  # the healthy candidates still count
    assert sum(h["failures"] for h in r.history) == len(r.failures)


def test_a_flaky_trial_is_retried(tmp_path):
    (tmp_path / "marks").mkdir()
    task = FaultyTask(dim=3, mode="flaky", marks=str(tmp_path / "marks"))
    r = run(task, tmp_path / "job", workers=2, generations=2)
    assert not r.failures
    clean = run(AnalyticTask(dim=3), tmp_path / "clean", workers=2, generations=2)
    assert r.best_named == clean.best_named


def test_a_dying_worker_is_replaced_and_only_its_trial_fails(tmp_path):
    task = FaultyTask(dim=3, mode="exit", threshold=0.3)
    r = run(task, tmp_path / "job", workers=2, generations=2, population=6)
    assert len(r.history) == 2 and r.failures
    assert all("BrokenProcessPool" in f or "terminated abruptly" in f for f in r.failures)
    # Every candidate that did not crash got its true fitness: the same as a job in which
    # crashing candidates just score the worst fitness.
    ref = run(FaultyTask(dim=3, mode="raise", threshold=0.3), tmp_path / "ref", workers=0, generations=2,
              population=6)
    assert r.best_named == ref.best_named
    assert [h["failures"] for h in r.history] == [h["failures"] for h in ref.history]

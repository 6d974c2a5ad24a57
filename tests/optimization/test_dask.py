"""The Dask path: a scheduler and two workers on loopback give the process pool's result."""

import pytest

from optimization.executor import ExecutorFactory
from optimization.job import Job, JobSettings, Problem
from optimization.paramvec import ParamSpace, load_values
from optimization.task import make_task

distributed = pytest.importorskip(
    "distributed", reason="Dask is not installed (pip install 'dask[distributed]')")


def job(task, out, factory):
    space = ParamSpace.build(load_values(task.sets, 0), task.optimize)
    return Job(Problem(task, space, task.name), JobSettings(population=6, generations=3, trials=2, seed=9),
               out, factory, progress=None, plot=False).run()


def test_dask_cluster_matches_the_process_pool(tmp_path):
    task = make_task("sphere", dim=3, noise=0.2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, death_timeout=30) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:") and len(cluster.workers) == 2
        factory = ExecutorFactory(scheduler=cluster.scheduler_address)  # what --scheduler does
        try:
            on_dask = job(task, tmp_path / "dask", factory)
        finally:
            factory.close()
        ran = cluster.scheduler.task_prefixes["run_trial"].state_counts["memory"]
    assert ran == 6 * 3 * 2  # population x generations x trials, all on the cluster
    local = job(task, tmp_path / "pool", ExecutorFactory(workers=2))
    assert on_dask.best_named == local.best_named
    assert [h["best"] for h in on_dask.history] == [h["best"] for h in local.history]

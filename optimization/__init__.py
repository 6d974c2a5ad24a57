"""CMA-ES optimization of skill parameters (dissertation chapters 3-4, Appendix A).

Modules, bottom up:

* `types`: what the others share: `ParamSpec`, `ParamSetDef`, `Values`,
  `TrialResult`, the `Task` protocol.
* `phases`: tasks built of phases (Appendix A.1.2): `WaypointPhase`,
  `StopPhase`, `MovePhase`, `run_phases` with the fall penalty and recovery
  (`TrainerRecovery`; `GetupRecovery` uses the getup skills).
* `dribble`: the position-to-dribble phase and its vision-only ball tracking.
* `getup`, `kick`: the getup and kick trials, their tasks and parameter sets.
* `paramvec`: named parameter sets (`PARAM_SETS`: the walk sets, the analytic
  test set), their starting values from UT-style parameter files, the CMA-ES
  vector <-> named values map (`ParamSpace`, per-parameter scales = initial
  sigma, file units) and `write_param_file`.
* `task`: the registered tasks (`TASKS`, `make_task`) and their fitness.
* `executor`: parallel trials on a `concurrent.futures.Executor` (local
  processes, in-process, or Dask), retrying failures once.
* `job`: the CMA-ES job: seeded trials, checkpoints, resume, history CSV,
  best parameter file and plot.
* `layered`: layered learning as task files (``optimization/tasks/*.task``).

The command line is ``soccer optimize`` (`cli.optimize_cmd`).
"""

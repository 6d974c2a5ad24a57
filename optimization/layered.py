"""Layered learning as files (dissertation chapter 3 and Figure 4.1).

A task file (``optimization/tasks/*.task``) holds one or more *layers*. Each
layer names its training task and what happens to every parameter set the
task uses:

* ``optimize SET [PARAM ...]``: learned here (all of the set's optimizable
  parameters, or only those named);
* ``freeze SET ...``: used by the task at its current values, not learned;
* ``input LAYER ...``: earlier layers whose best parameters (their
  ``best.txt``) are loaded; their sets are frozen unless learned here;
* ``overlap SET [PARAM ...]``: a set learned by an input layer, re-opened and
  learned together with this layer's sets (the "seam" of overlapping layered
  learning: PCLL when a subset, PLLR when a frozen layer is relearned later);
* ``seed SET FROM``: SET starts from FROM's current values (``h -> H``);
* ``params FILE ...``: parameter files (relative to the task file) loaded
  after the shipped defaults;
* ``task NAME [OPTION=VALUE ...]``, ``population N``, ``generations N``,
  ``sigma S``, ``trials N``, ``seed N``: the job's task and settings.

Example, the walk layers of Figure 4.1 (``walk.task``)::

    layer go_to_target                  # L2,1 Walk_GoToTarget
      task      go_to_target
      optimize  go_to_target

    layer sprint                        # L3,1 Walk_Sprint
      task      sprint
      input     go_to_target
      freeze    go_to_target
      seed      sprint go_to_target
      optimize  sprint

Comments start with ``#`` or ``//``. Errors raise `skills.params.ParamError`
with ``file:line:``. Layers run in file order, each in ``OUT/LAYER/``; a layer
whose directory holds a finished job is skipped, an unfinished one resumed.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

from optimization.executor import ExecutorFactory
from optimization.job import BEST, CHECKPOINT, Job, JobResult, JobSettings, Problem
from optimization.paramvec import PARAM_SETS, ParamSpace, load_values, param_set
from optimization.task import TASKS, make_task
from skills.params import ParamError, PathLike, strip_comment

TASK_DIR = Path(__file__).parent / "tasks"
_INT = ("population", "generations", "trials", "seed")
_FLOAT = ("sigma",)


@dataclass
class LayerSpec:
    """One layer of learning: a task and the roles of its parameter sets."""

    name: str
    task: str
    options: dict[str, str] = field(default_factory=dict)
    optimize: dict[str, tuple[str, ...] | None] = field(default_factory=dict)
    overlap: dict[str, tuple[str, ...] | None] = field(default_factory=dict)
    freeze: tuple[str, ...] = ()
    inputs: tuple[str, ...] = ()
    seed_from: dict[str, str] = field(default_factory=dict)
    params: tuple[Path, ...] = ()
    settings: dict[str, float] = field(default_factory=dict)
    where: str = ""  # "file:line: " of the layer's definition, for messages
    line: int = 0

    def learned(self) -> dict[str, tuple[str, ...] | None]:
        """Every set learned in this layer (optimized or overlapping) -> its parameters (None: all)."""
        out: dict[str, tuple[str, ...] | None] = {}
        for part in (self.optimize, self.overlap):
            for s, names in part.items():
                if s not in out:
                    out[s] = names
                elif out[s] is None or names is None:
                    out[s] = None
                else:
                    out[s] = tuple(dict.fromkeys((*out[s], *names)))
        return out

    def problem(self, robot_type: int = 0, files: Sequence[PathLike] = (),
                results: dict[str, Path] | None = None) -> Problem:
        """The task, the starting values of its sets and the parameter space of this layer.

        files: parameter files after the layer's own (``--params``); results:
        best-parameter files of the input layers, loaded last."""
        results = results or {}
        task = make_task(self.task, robot_type, **self.options)
        learned = self.learned()
        if not learned:
            learned = dict(task.optimize)
        used = list(dict.fromkeys([*task.sets, *learned, *self.freeze, *self.seed_from,
                                   *self.seed_from.values()]))
        inputs = []
        for name in self.inputs:
            if name not in results:
                raise ValueError(f"{self.where}layer {self.name}: input layer {name} has no result yet")
            inputs.append(results[name])
        base = load_values(used, robot_type, [*self.params, *files, *inputs])
        for target, source in self.seed_from.items():
            base[target] = {n: v for n, v in base[source].items() if n in param_set(target).schema}
        for s in learned:
            if s not in task.sets:
                raise ValueError(f"{self.where}layer {self.name}: task {task.name} does not use set {s}; "
                                 f"it uses {', '.join(task.sets)}")
        space = ParamSpace.build({s: base[s] for s in used}, learned)
        return Problem(task, space, self.name)

    def job_settings(self, overrides: dict | None = None) -> JobSettings:
        values = {**self.settings, **{k: v for k, v in (overrides or {}).items() if v is not None}}
        return JobSettings(**values)


def _error(path: PathLike | None, line: int, message: str, word: str = "") -> ParamError:
    return ParamError(path, line, message, word)


def parse_task_file(text: str, path: PathLike | None = None) -> list[LayerSpec]:
    """The layers of a task file, checked for consistency (see the module docstring)."""
    base_dir = Path(path).parent if path is not None else Path(".")
    layers: list[LayerSpec] = []
    cur: LayerSpec | None = None

    def learned_by(name: str) -> set[str]:
        for ly in layers:
            if ly.name == name:
                if ly.learned() or not ly.task:
                    return set(ly.learned())
                return set(make_task(ly.task, 0, **ly.options).optimize)
        return set()
    for n, raw in enumerate(text.splitlines(), start=1):
        words = strip_comment(raw).split()
        if not words:
            continue
        key, args = words[0].lower(), words[1:]
        where = f"{os.fspath(path) if path is not None else '<string>'}:{n}: "
        if key == "layer":
            if len(args) != 1:
                raise _error(path, n, "expected 'layer NAME'", raw.strip())
            if any(ly.name == args[0] for ly in layers):
                raise _error(path, n, "layer defined twice:", args[0])
            cur = LayerSpec(args[0], "", where=where, line=n)
            layers.append(cur)
            continue
        if cur is None:
            raise _error(path, n, "expected 'layer NAME' before", words[0])
        if not args:
            raise _error(path, n, f"missing value after {key}:", words[0])
        if key == "task":
            if args[0] not in TASKS:
                raise _error(path, n, f"unknown task (tasks are {', '.join(TASKS)}):", args[0])
            cur.task = args[0]
            for opt in args[1:]:
                k, sep, v = opt.partition("=")
                if not sep:
                    raise _error(path, n, "expected OPTION=VALUE, not", opt)
                cur.options[k] = v
        elif key in ("optimize", "overlap"):
            if args[0] not in PARAM_SETS:
                raise _error(path, n, f"unknown parameter set (sets are {', '.join(PARAM_SETS)}):", args[0])
            d = param_set(args[0])
            for p in args[1:]:
                try:
                    d.spec(p)
                except KeyError as exc:
                    raise _error(path, n, str(exc.args[0]) + ":", p) from None
            target = cur.optimize if key == "optimize" else cur.overlap
            if args[0] in target:
                raise _error(path, n, f"set named twice by {key} in this layer:", args[0])
            target[args[0]] = tuple(args[1:]) or None
            if key == "overlap" and not any(args[0] in learned_by(i) for i in cur.inputs):
                raise _error(path, n, "overlap needs an input layer that learned", args[0])
        elif key == "freeze":
            for s in args:
                if s not in PARAM_SETS:
                    raise _error(path, n, "unknown parameter set:", s)
            cur.freeze = (*cur.freeze, *args)
        elif key == "input":
            for name in args:
                if name == cur.name or all(ly.name != name for ly in layers):
                    raise _error(path, n, "input must be an earlier layer of this file:", name)
            cur.inputs = (*cur.inputs, *args)
        elif key == "seed":
            if len(args) != 2 or any(a not in PARAM_SETS for a in args):
                raise _error(path, n, "expected 'seed SET FROM_SET' with known sets:", " ".join(args))
            cur.seed_from[args[0]] = args[1]
        elif key == "params":
            cur.params = (*cur.params, *(base_dir / a for a in args))
        elif key in _INT or key in _FLOAT:
            try:
                cur.settings[key] = int(args[0]) if key in _INT else float(args[0])
            except ValueError:
                raise _error(path, n, f"{key} must be a number:", args[0]) from None
        else:
            raise _error(path, n, "unknown keyword", words[0])
        if key in ("optimize", "overlap", "freeze"):
            clash = set(cur.freeze) & set(cur.learned())
            if clash:
                raise _error(path, n, "set both frozen and learned:", sorted(clash)[0])
    if not layers:
        raise _error(path, 0, "no layer in the file")
    for ly in layers:
        if not ly.task:
            raise _error(path, ly.line, "layer names no task:", ly.name)
        try:
            make_task(ly.task, 0, **ly.options)
        except ValueError as exc:
            raise _error(path, ly.line, f"layer {ly.name}: {exc}") from None
    return layers


def read_task_file(path: PathLike) -> list[LayerSpec]:
    with open(path, encoding="utf-8") as fh:
        return parse_task_file(fh.read(), path)


def find_task(name: str) -> Path | None:
    """The task file `name` (a path, or a file of optimization/tasks/ with or without .task)."""
    for p in (Path(name), TASK_DIR / name, TASK_DIR / f"{name}.task"):
        if p.is_file():
            return p
    return None


def single_layer(task: str, options: dict[str, str] | None = None,
                 sets: Sequence[str] = ()) -> LayerSpec:
    """A one-layer job on a registered task; `sets`: the sets to learn (default: the task's)."""
    layer = LayerSpec(task, task, dict(options or {}))
    for s in sets:
        param_set(s)
        layer.optimize[s] = None
    return layer


def run_layers(layers: Sequence[LayerSpec], out_dir: Path, robot_type: int = 0,
               files: Sequence[PathLike] = (), overrides: dict | None = None,
               executor: ExecutorFactory | None = None, subdirs: bool = True, progress=None,
               ) -> dict[str, JobResult]:
    """Run the layers in order (each in OUT/LAYER/ when `subdirs`), feeding each layer's
    best parameters to the layers that name it as input; finished layers are skipped,
    unfinished ones resumed from their checkpoints."""
    import sys

    progress = sys.stderr if progress is None else progress
    results: dict[str, Path] = {}
    out: dict[str, JobResult] = {}
    for layer in layers:
        d = out_dir / layer.name if subdirs else out_dir
        if (d / CHECKPOINT).exists():
            job = Job.resume(d, executor, progress)
            if job.done:
                print(f"{layer.name}: finished earlier in {d}", file=progress, flush=True)
        else:
            problem = layer.problem(robot_type, files, results)
            job = Job(problem, layer.job_settings(overrides), d, executor, progress)
        out[layer.name] = job.run()
        results[layer.name] = d / BEST
    return out


def with_settings(layer: LayerSpec, **settings) -> LayerSpec:
    return replace(layer, settings={**layer.settings, **settings})

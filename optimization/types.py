"""The types the optimization modules share: parameter sets, their values, trials.

The registries that use them live elsewhere: `optimization.paramvec` maps set
names to `ParamSetDef` (`param_set`, `PARAM_SETS`), `optimization.task` maps task
names to factories (`TASKS`). The modules that define sets and tasks (walk,
`optimization.getup`, `optimization.kick`) import only this module, so every
import points one way: types <- getup, kick <- paramvec <- task.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Protocol

from skills.params import UNITS, PathLike

Values = dict[str, dict[str, float]]  # set name -> parameter name -> value (file units)


@dataclass(frozen=True)
class ParamSpec:
    """One optimizable parameter: initial standard deviation and bounds (file units)."""

    name: str
    sigma: float
    lower: float = -math.inf
    upper: float = math.inf


@dataclass(frozen=True)
class ParamSetDef:
    """A named parameter set as parameter files hold it.

    prefix: what the set's names carry in a file (``sprint_``); inherit: a set
    whose values this one starts from when the files do not name it (walk sets
    with a prefix start from go-to-target's); defaults: the shipped parameter
    files for a robot type; specs: the parameters optimized unless a task file
    names others.
    """

    name: str
    prefix: str
    schema: Mapping[str, str]
    specs: tuple[ParamSpec, ...]
    defaults: Callable[[int], list[PathLike]] | None = None
    inherit: str | None = None
    start: Mapping[str, float] = field(default_factory=dict)  # built-in values under the files
    named_specs: tuple[ParamSpec, ...] = ()

    def spec(self, name: str) -> ParamSpec:
        for s in (*self.specs, *self.named_specs):
            if s.name == name:
                return s
        if name not in self.schema:
            raise KeyError(f"set {self.name} has no parameter {name!r}")
        raise KeyError(f"parameter {name!r} of set {self.name} has no optimization spec (sigma, bounds)")

    def to_si(self, values: Mapping[str, float]) -> dict[str, float]:
        """File units -> SI."""
        return {n: v * UNITS[self.schema[n]] for n, v in values.items()}


@dataclass(frozen=True)
class TrialResult:
    """One trial's fitness (higher is better) and what else it measured."""

    fitness: float
    info: dict = field(default_factory=dict)


class Task(Protocol):
    """An optimization task (`optimization.task`): the sets it uses and learns, the
    fitness of a trial that could not run, and one seeded trial."""

    name: str
    sets: tuple[str, ...]
    optimize: Mapping[str, tuple[str, ...] | None]
    worst: float

    def trial(self, values: Values, seed: int) -> TrialResult: ...

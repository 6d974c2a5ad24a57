"""Tasks for the fault tests: picklable by reference (module level), cheap."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from optimization.task import AnalyticTask
from optimization.types import TrialResult


@dataclass(frozen=True)
class FaultyTask(AnalyticTask):
    """The sphere, except that candidates with x0 above `threshold` fail.

    mode "raise": the trial raises every time; "exit": the worker process dies
    every time; "flaky": the first attempt of each trial raises (remembered in
    files under `marks`, so across processes), the retry succeeds.
    """

    mode: str = "raise"
    threshold: float = 0.5
    marks: str = ""

    def trial(self, values, seed: int) -> TrialResult:
        x0 = values["analytic"]["x0"]
        if self.mode == "flaky":
            mark = Path(self.marks) / f"{seed}-{x0!r}"
            if not mark.exists():
                mark.write_text("failed once")
                raise RuntimeError("flaky trial, first attempt")
        elif x0 > self.threshold:
            if self.mode == "exit":
                os._exit(3)
            raise RuntimeError(f"x0 = {x0:.3f} is out of the simulator's range")
        return super().trial(values, seed)

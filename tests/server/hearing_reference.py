"""The interpreted hearing the compiled one replaced, kept as the tests' reference:
`server.hearing.Hearing.route` must answer as this one does, draw for draw (the rules
are in `server.hearing`'s docstring)."""

from __future__ import annotations

import math

import numpy as np

from models.messages import HeardMessage
from models.rules import HEAR_DISTANCE, HEAR_PERIOD


class ReferenceHearing:
    """Routes said messages to listeners, one cycle later (one listener at a time)."""

    def __init__(self, sides: np.ndarray, rng: np.random.Generator) -> None:
        self.sides = sides
        self.rng = rng
        n = len(sides)
        self.next_cycle = np.zeros((n, 2), dtype=np.int64)  # per listener: own team, other team

    def route(self, cycle: int, time: float, said: dict[int, str], positions: np.ndarray,
              headings: np.ndarray) -> dict[int, list[HeardMessage]]:
        """Messages heard at `cycle` + 1 for messages `said` (already validated) at `cycle`.

        positions are torso positions (n, 3), headings torso yaws (n,), world frame.
        """
        heard: dict[int, list[HeardMessage]] = {}
        if not said:
            return heard
        speakers = sorted(said)
        for j in range(len(self.sides)):
            msgs: list[HeardMessage] = []
            if j in said:
                msgs.append(HeardMessage(time, "self", 0.0, said[j]))
            for slot, same in ((0, True), (1, False)):
                if cycle < self.next_cycle[j, slot]:
                    continue
                cands = [s for s in speakers if s != j and (self.sides[s] == self.sides[j]) == same
                         and np.linalg.norm(positions[s, :2] - positions[j, :2]) <= HEAR_DISTANCE]
                if not cands:
                    continue
                s = cands[int(self.rng.integers(len(cands)))] if len(cands) > 1 else cands[0]
                dx, dy = positions[s, :2] - positions[j, :2]
                direction = math.remainder(math.atan2(dy, dx) - headings[j], 2 * math.pi)
                msgs.append(HeardMessage(time, "ours" if same else "theirs", direction, said[s]))
                self.next_cycle[j, slot] = cycle + HEAR_PERIOD
            if msgs:
                heard[j] = msgs
        return heard

"""Say and hear: the league's 20-character team messages.

A message said in one cycle is heard at the start of the next by every player
within 50 m. Each listener hears at most one message from its own team and one
from the other team in every two-cycle window (SimSpark's hearing capacity),
chosen at random among those said; a speaker always hears itself. A message
longer than 20 characters or with a character outside 0x21..0x7E (less '(' and
')') is dropped, and only its speaker is told why.
"""

from __future__ import annotations

import numpy as np

from models.messages import HeardMessage
from models.rules import HEAR_DISTANCE, HEAR_PERIOD, SAY_ALPHABET, SAY_MAX_LENGTH, Side
from server._kernels import hearing_choices

POOL = 1 << 12  # raw 32-bit draws per refill of the choice pool


def say_error(text: str) -> str | None:
    """Why `text` may not be said, or None when it may."""
    if not isinstance(text, str):
        return f"say text must be a str, not {type(text).__name__}"
    if len(text) == 0:
        return "empty say message"
    if len(text) > SAY_MAX_LENGTH:
        return f"say message of {len(text)} characters is over the limit of {SAY_MAX_LENGTH}"
    bad = sorted({c for c in text if c not in SAY_ALPHABET})
    if bad:
        return f"say message has characters outside the allowed alphabet: {bad!r}"
    return None


class Hearing:
    """Routes said messages to listeners, one cycle later.

    The choice among several speakers is `rng.integers(k)` of the seeded generator, made
    in the compiled `server._kernels.hearing_choices` from a pool of the generator's raw
    32-bit draws (taken as its `next_uint32` would: the low half of each 64-bit output,
    then the high half), so the messages heard are those of one `integers` call per
    choice, draw for draw.
    """

    def __init__(self, sides: np.ndarray, rng: np.random.Generator) -> None:
        self.sides = sides
        self.rng = rng
        n = len(sides)
        self._left = np.asarray(sides) == Side.LEFT
        self.next_cycle = np.zeros((n, 2), dtype=np.int64)  # per listener: own team, other team
        self._pool = np.empty(0, dtype=np.uint32)
        self._at = 0
        self._said = np.zeros(n, dtype=np.bool_)
        self._speaker = np.empty((n, 2), dtype=np.int64)
        self._direction = np.empty((n, 2))

    def _refill(self) -> None:
        """Keep the unused draws and add POOL fresh ones."""
        raw = self.rng.bit_generator.random_raw(POOL // 2).view(np.uint32)  # low, high, low, ...
        self._pool = np.concatenate([self._pool[self._at:], raw])
        self._at = 0

    def route(self, cycle: int, time: float, said: dict[int, str], positions: np.ndarray,
              headings: np.ndarray) -> dict[int, list[HeardMessage]]:
        """Messages heard at `cycle` + 1 for messages `said` (already validated) at `cycle`.

        positions are torso positions (n, 3), headings torso yaws (n,; rad in [-pi, pi]),
        world frame.
        """
        heard: dict[int, list[HeardMessage]] = {}
        if not said:
            return heard
        flags = self._said
        flags[:] = False
        flags[list(said)] = True
        speaker, direction = self._speaker, self._direction
        while True:
            at = hearing_choices(cycle, flags, self._left, positions, headings, self.next_cycle,
                                 HEAR_PERIOD, HEAR_DISTANCE, self._pool, self._at, speaker, direction)
            if at >= 0:
                break
            self._refill()
        self._at = at
        for j, ((s0, s1), (d0, d1)) in enumerate(zip(speaker.tolist(), direction.tolist())):
            msgs: list[HeardMessage] = []
            if j in said:
                msgs.append(HeardMessage(time, "self", 0.0, said[j]))
            if s0 >= 0:
                msgs.append(HeardMessage(time, "ours", d0, said[s0]))
            if s1 >= 0:
                msgs.append(HeardMessage(time, "theirs", d1, said[s1]))
            if msgs:
                heard[j] = msgs
        return heard

"""Voting coordination of role mappings (dissertation section 7.1).

Every agent broadcasts in its own time slot the mapping of agents to roles it
believes best. Each receiver keeps the last `window` received votes (the team
size in the papers); the mapping with the most votes wins and a tie goes to
the mapping, among those tied, that received the most recent vote. Dropped
messages simply leave fewer votes in the window; a wrong vote is outvoted.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Hashable, Iterable
from dataclasses import dataclass, field


def _key(mapping) -> Hashable:
    try:
        return tuple(int(x) for x in mapping)
    except TypeError:
        return mapping


@dataclass
class VoteWindow:
    """Sliding window of the last `window` votes received (sender, mapping)."""

    window: int = 11
    _votes: deque = field(default_factory=deque, init=False, repr=False)

    def __post_init__(self):
        if self.window < 1:
            raise ValueError(f"window must be >= 1, got {self.window}")
        self._votes = deque(maxlen=self.window)

    def receive(self, sender: int, mapping: Iterable[int]) -> None:
        """Adds one vote; the oldest vote leaves when the window is full."""
        self._votes.append((int(sender), _key(mapping)))

    def __len__(self) -> int:
        return len(self._votes)

    def winner(self, default=None):
        """Mapping with most votes (tie: the most recent vote among the tied)."""
        if not self._votes:
            return default
        counts: dict = {}
        latest: dict = {}
        for i, (_, mapping) in enumerate(self._votes):
            counts[mapping] = counts.get(mapping, 0) + 1
            latest[mapping] = i
        return max(counts, key=lambda m: (counts[m], latest[m]))

    def clear(self) -> None:
        self._votes.clear()


def elect(votes: Iterable, default=None):
    """Winner of a sequence of mappings, oldest first (same rule as VoteWindow)."""
    votes = list(votes)
    box = VoteWindow(max(1, len(votes)))
    for i, v in enumerate(votes):
        box.receive(i, v)
    return box.winner(default)

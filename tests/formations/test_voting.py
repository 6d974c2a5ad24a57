"""Voting coordination: a sliding window of votes agrees despite faults."""

from __future__ import annotations

import numpy as np
import pytest

from formations.voting import VoteWindow, elect


def test_most_votes_and_ties_to_most_recent():
    box = VoteWindow(5)
    box.receive(0, [0, 1, 2])
    box.receive(1, [1, 0, 2])
    assert box.winner() == (1, 0, 2)  # tie 1-1, most recent wins
    box.receive(2, [0, 1, 2])
    assert box.winner() == (0, 1, 2)
    for i in range(5):
        box.receive(3 + i, [2, 1, 0])
    assert len(box) == 5 and box.winner() == (2, 1, 0)  # old votes slid out
    assert VoteWindow(3).winner("none") == "none"
    assert elect([(1,), (2,), (1,), (2,)]) == (2,)
    with pytest.raises(ValueError):
        VoteWindow(0)


def test_team_agrees_under_dropped_and_wrong_votes():
    rng = np.random.default_rng(71)
    n = 11
    truth = tuple(rng.permutation(n).tolist())
    boxes = [VoteWindow(n) for _ in range(n)]
    last = [None] * n  # what each agent would use without voting
    agree = 0
    agree_last = 0
    cycles = 600
    for cycle in range(cycles):
        sender = cycle % n  # rotating time slots by uniform number
        if rng.random() < 0.2:
            vote = tuple(rng.permutation(n).tolist())  # noisy agent, wrong vote
        else:
            vote = truth
        for receiver, box in enumerate(boxes):
            if rng.random() < 0.15:  # message dropped for this receiver
                continue
            box.receive(sender, vote)
            last[receiver] = vote
        if cycle >= 2 * n:
            winners = {b.winner() for b in boxes}
            agree += winners == {truth}
            agree_last += set(last) == {truth}
    assert agree / (cycles - 2 * n) > 0.99
    # Without voting (last message only) the team is often split.
    assert agree_last / (cycles - 2 * n) < 0.9

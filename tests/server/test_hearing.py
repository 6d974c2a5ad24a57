"""Say and hear: the 20-character alphabet, capacity and per-agent warnings."""

import numpy as np
import pytest

from models.messages import Action
from server import hearing
from server.hearing import Hearing, say_error
from tests.server.hearing_reference import ReferenceHearing
from tests.server.helpers import run, standing_match


def test_say_rules():
    assert say_error("a" * 20) is None
    assert say_error("~!#$%&'*+,-./09:;<=>?@AZ[]^_`az{|}") is not None  # 34 characters
    assert "over the limit" in say_error("a" * 21)
    assert "alphabet" in say_error("hello world")  # space
    assert "alphabet" in say_error("f(x)")
    assert "alphabet" in say_error("caf\u00e9")
    assert say_error("") is not None


def test_bad_message_dropped_with_a_warning_for_its_speaker_only():
    m = standing_match(left=(0, 0), right=(0,))
    agents = m.agents

    class Talker:
        def __init__(self, inner, text):
            self.inner, self.text = inner, text

        def act(self, p):
            a = self.inner.act(p)
            return Action(a.joint_velocities, say=self.text)

    m.agents = [Talker(agents[0], "x" * 21), Talker(agents[1], "ok!"), agents[2]]
    m.step()
    p = m.percepts()
    assert p[0].warnings and "over the limit" in p[0].warnings[0]
    assert not p[1].warnings and not p[2].warnings
    heard0 = [h.text for h in p[0].heard]
    assert heard0 == ["ok!"]  # the teammate's good message, not its own bad one
    assert [h.team for h in p[1].heard] == ["self"]
    assert [(h.team, h.text) for h in p[2].heard] == [("theirs", "ok!")]
    run(m, 0.1)


def test_one_message_per_team_every_two_cycles():
    sides = np.array(["L", "L", "L", "R"])
    h = Hearing(sides, np.random.default_rng(0))
    pos = np.zeros((4, 3))
    heads = np.zeros(4)
    got = []
    for cycle in range(6):
        heard = h.route(cycle, cycle * 0.02, {0: f"a{cycle}", 1: f"b{cycle}", 3: f"c{cycle}"}, pos, heads)
        got.append([(x.team, x.text) for x in heard.get(2, [])])
    ours = [sum(1 for t, _ in g if t == "ours") for g in got]
    theirs = [sum(1 for t, _ in g if t == "theirs") for g in got]
    assert ours == [1, 0, 1, 0, 1, 0]
    assert theirs == [1, 0, 1, 0, 1, 0]


def test_out_of_earshot():
    sides = np.array(["L", "L"])
    h = Hearing(sides, np.random.default_rng(0))
    pos = np.array([[-15.0, -10.0, 0.4], [40.0, 10.0, 0.4]])
    assert 1 not in h.route(0, 0.0, {0: "far"}, pos, np.zeros(2))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_compiled_routing_hears_what_the_reference_heard(seed, monkeypatch):
    """Random speakers, places and headings over 400 cycles: the same messages, the same
    directions bit for bit, from the same seeded generator; a small pool is refilled often."""
    monkeypatch.setattr(hearing, "POOL", 64)
    rng = np.random.default_rng(seed)
    n = 22
    sides = np.array(["L"] * 11 + ["R"] * 11)
    new = Hearing(sides, np.random.default_rng(seed))
    ref = ReferenceHearing(sides, np.random.default_rng(seed))
    for cycle in range(400):
        speakers = np.flatnonzero(rng.random(n) < rng.random())
        said = {int(s): f"m{cycle}.{s}" for s in speakers}
        pos = np.column_stack([rng.uniform(-40, 40, n), rng.uniform(-12, 12, n), np.full(n, 0.4)])
        heads = rng.uniform(-np.pi, np.pi, n)
        heads[:2] = (np.pi, -np.pi)
        t = cycle * 0.02
        assert new.route(cycle, t, said, pos, heads) == ref.route(cycle, t, said, pos, heads)
    np.testing.assert_array_equal(new.next_cycle, ref.next_cycle)

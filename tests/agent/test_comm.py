"""The message codec: exact round trips, the say limits, garbage and foreign messages."""

from __future__ import annotations

import math
import random

from hypothesis import given, settings
from hypothesis import strategies as st

from agent import comm
from models.messages import HeardMessage
from models.rules import SAY_ALPHABET, SAY_MAX_LENGTH

coord_x = st.floats(-20.0, 20.0, allow_nan=False)
coord_y = st.floats(-14.0, 14.0, allow_nan=False)
angle = st.floats(-10.0, 10.0, allow_nan=False)
unum = st.integers(1, 11)
reports = st.builds(comm.PlayerReport, unum, coord_x, coord_y, angle, st.booleans())
messages = st.builds(
    comm.TeamMessage, unum=unum, x=coord_x, y=coord_y, heading=angle,
    ball=st.none() | st.tuples(coord_x, coord_y), fallen=st.booleans(), not_localized=st.booleans(),
    role_vote=st.none() | st.permutations(list(range(10))).map(tuple),
    kick=st.none() | st.builds(comm.KickTarget, coord_x, coord_y, st.booleans()),
    teammates=st.lists(reports.map(lambda r: comm.PlayerReport(r.unum, r.x, r.y, r.heading)),
                       max_size=3).map(tuple),
    opponents=st.lists(reports, max_size=3).map(tuple),
    robot_type=st.none() | st.integers(0, 4),
    time=st.integers(0, 30000).map(lambda c: round(c * 0.02, 6)))


@settings(max_examples=400, derandomize=True, deadline=None)
@given(messages)
def test_round_trip_is_exact(msg):
    text = comm.encode(msg)
    assert 0 < len(text) <= SAY_MAX_LENGTH
    assert set(text) <= SAY_ALPHABET
    sent = comm.quantize(msg)
    heard = HeardMessage(time=round(msg.time + 0.02, 6), team="ours", direction=0.0, text=text)
    assert comm.decode_heard(heard) == sent
    assert comm.quantize(sent) == sent  # quantizing is idempotent
    # What is sent is within half a step of what was asked for.
    assert abs(sent.x - min(max(msg.x, -16.0), 16.0)) <= comm.X10.step / 2 + 1e-9
    assert abs(math.remainder(sent.heading - msg.heading, 2 * math.pi)) <= comm.ANGLE6.step / 2 + 1e-9
    if sent.ball is not None:
        assert abs(sent.ball[1] - min(max(msg.ball[1], -11.0), 11.0)) <= comm.Y10.step / 2 + 1e-9
    assert sent.kick == (None if msg.kick is None else sent.kick)


def test_optional_sections_drop_by_priority():
    full = comm.TeamMessage(
        unum=4, x=1.0, y=2.0, heading=0.5, ball=(3.0, 4.0), role_vote=tuple(range(10)),
        kick=comm.KickTarget(10.0, 0.0), teammates=(comm.PlayerReport(2, 0.0, 0.0, 0.0),),
        robot_type=3, time=1.0)
    sent = comm.quantize(full)
    assert sent.ball is not None and sent.role_vote == tuple(range(10)) and sent.kick is not None
    assert sent.teammates == ()  # no room left after the kick
    small = comm.quantize(comm.TeamMessage(
        unum=4, x=1.0, y=2.0, heading=0.5, teammates=tuple(comm.PlayerReport(u, 0.0, 0.0, 0.0)
                                                          for u in (2, 3, 5)), time=1.0))
    assert [r.unum for r in small.teammates] == [2, 3]


def test_garbage_is_ignored():
    rng = random.Random(0)
    alphabet = sorted(SAY_ALPHABET)
    for _ in range(20000):
        n = rng.randint(0, 25)
        text = "".join(rng.choice(alphabet) for _ in range(n))
        assert comm.decode(text, 10.0) is None
    for bad in ("", "(" * 20, "a" * 19, "a" * 21, "é" * 20, " " * 20):
        assert comm.decode(bad, 0.0) is None
    assert comm.decode(None) is None  # type: ignore[arg-type]


def test_foreign_stale_and_altered_messages_are_rejected():
    msg = comm.TeamMessage(unum=5, x=-3.0, y=1.0, heading=0.2, ball=(0.5, 0.5), time=4.0)
    text = comm.encode(msg)
    assert comm.decode_heard(HeardMessage(4.02, "ours", 0.0, text)) is not None
    assert comm.decode_heard(HeardMessage(4.02, "theirs", 0.0, text)) is None  # the other team
    assert comm.decode_heard(HeardMessage(4.5, "ours", 0.0, text)) is None  # stale
    for k in range(SAY_MAX_LENGTH):  # one character changed
        ch = "!" if text[k] != "!" else "#"
        assert comm.decode(text[:k] + ch + text[k + 1:], 4.02) is None


def test_time_slots_rotate_by_uniform_number():
    speakers = []
    for cycle in range(44):
        t = cycle * 0.02
        who = [u for u in range(1, 12) if comm.may_speak(u, t)]
        assert len(who) == (1 if cycle % 2 == 0 else 0)
        speakers += who
    assert speakers == list(range(1, 12)) * 2

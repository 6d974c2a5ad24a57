"""The league's message formats: S-expressions, framing, percepts and agent messages."""

import math
import struct

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from models import nao
from models.messages import Action, HeardMessage
from server.protocol import (
    FrameReader,
    PerceptParser,
    ProtocolError,
    encode_frame,
    format_action,
    format_init,
    format_percept,
    format_scene,
    parse_action,
    parse_agent_message,
    parse_sexp,
)
from tests.server.helpers import run, standing_match

# ------------------------------------------------------------------ S-expressions


def test_sexp_nested_lists_and_atoms():
    assert parse_sexp("(a 1)(b (c 2.5) d)") == [["a", "1"], ["b", ["c", "2.5"], "d"]]
    assert parse_sexp(b" ( x ) \n") == [["x"]]
    assert parse_sexp("") == []
    assert parse_sexp("()") == [[]]


@pytest.mark.parametrize("bad, why", [
    ("(a", "unclosed"), ("a)", "outside"), (")", "unbalanced"), ("x", "outside"),
    ("(a))", "unbalanced"), ("(" * 20 + ")" * 20, "deeper"), (b"(a \xff)", "non-ASCII"),
])
def test_sexp_malformed_is_a_protocol_error(bad, why):
    with pytest.raises(ProtocolError, match=why):
        parse_sexp(bad)


def test_sexp_size_limit():
    with pytest.raises(ProtocolError, match="over the limit"):
        parse_sexp("(a " + "1 " * 100 + ")", max_size=50)


@settings(max_examples=300, deadline=None)
@given(st.one_of(st.binary(max_size=300), st.text(max_size=300),
                 st.text(alphabet="() ab1.-\n", max_size=200)))
def test_fuzz_parsers_raise_only_protocol_errors(data):
    for parse in (parse_sexp, parse_agent_message, PerceptParser("A", 4).parse,
                  lambda d: parse_action(d, 0)):
        try:
            parse(data)
        except ProtocolError:
            pass


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200))
def test_fuzz_frame_reader(data):
    r = FrameReader(max_size=64)
    try:
        for k in range(0, len(data), 7):
            for f in r.feed(data[k:k + 7]):
                assert len(f) <= 64
    except ProtocolError:
        pass
    assert r.pending <= 64 + 4 + 7


# ------------------------------------------------------------------------- frames


def test_frames_split_and_joined():
    r = FrameReader()
    data = encode_frame("(syn)") + encode_frame(b"(a 1)(b 2)")
    got = []
    for k in range(len(data)):  # one byte at a time
        got += r.feed(data[k:k + 1])
    assert got == [b"(syn)", b"(a 1)(b 2)"]
    assert r.pending == 0
    assert data[:4] == struct.pack(">I", 5)


def test_oversized_frames_refused():
    with pytest.raises(ProtocolError, match="over the limit"):
        FrameReader(max_size=100).feed(struct.pack(">I", 101))
    with pytest.raises(ProtocolError, match="over the limit"):
        encode_frame("x" * 101, max_size=100)


# ----------------------------------------------------------------------- percepts


@pytest.fixture(scope="module")
def percepts():
    """Real percepts of a 2 vs 1 match (types 0, 4 and 1) on a vision cycle, with messages."""
    m = standing_match((0, 4), (1,))
    run(m, 0.1)
    while m.cycle % 3:
        m.step()
    ps = m.percepts()
    ps[0].heard = (HeardMessage(1.5, "self", 0.0, "hi!"), HeardMessage(1.5, "ours", 0.7, "x"),
                   HeardMessage(1.5, "theirs", -2.0, "y"))
    return ps


def test_percept_text_in_league_order_and_units(percepts):
    p = percepts[1]  # L2, type 4
    text = format_percept(p, "Ours", "Theirs", first=True)
    assert text.startswith(f"(time (now {p.time:.2f}))(GS (unum 2) (team left) (sl 0) (sr 0) "
                           f"(t {p.game_time:.2f}) (pm PlayOn))(GYR (n torso) (rt ")
    deg = math.degrees(p.joints[nao.joint_names(4).index("llj4")])
    assert f"(HJ (n llj4) (ax {deg:.2f}))" in text
    assert "(HJ (n rlj7) (ax " in text  # the toe
    assert "(FRP (n lf) (c 0.00 0.00 -0.01) (f 0.00 0.00 " in text
    assert "(See (" in text and "(P (team Theirs) (id 1) (head (pol " in text
    assert "(L (pol " in text
    # standing still: the accelerometer reads about +9.81 up
    assert "(ACC (n torso) (a " in text and " 9.8" in text.split("(ACC")[1].split(")")[1]
    assert "(unum" not in format_percept(p, "Ours", "Theirs")


def test_percept_round_trip_exact(percepts):
    for p in percepts:
        team, opp = ("Ours", "Theirs") if p.side == "L" else ("Theirs", "Ours")
        q = PerceptParser(team, p.robot_type).parse(format_percept(p, team, opp, first=True, digits=None))
        assert (q.time, q.game_time, q.play_mode, q.side, q.unum, q.robot_type) == (
            p.time, p.game_time, p.play_mode, p.side, p.unum, p.robot_type)
        for a in ("joints", "gyro", "accel", "foot_forces"):
            np.testing.assert_allclose(getattr(q, a), getattr(p, a), rtol=1e-12, atol=1e-12)
        v, w = p.vision, q.vision
        assert v is not None and w is not None
        assert w.landmark_names == v.landmark_names
        for a in ("landmarks", "lines", "players"):
            np.testing.assert_allclose(getattr(w, a), getattr(v, a), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(w.ball, v.ball, rtol=1e-12)
        np.testing.assert_array_equal(w.player_ours, v.player_ours)
        np.testing.assert_array_equal(w.player_unum, v.player_unum)
        np.testing.assert_array_equal(w.player_part, v.player_part)
        assert len(q.heard) == len(p.heard)
        for h, g in zip(p.heard, q.heard):
            assert (g.team, g.text, g.time) == (h.team, h.text, h.time)
            assert g.direction == pytest.approx(h.direction, abs=1e-12)


def test_percept_parser_keeps_state_between_messages(percepts):
    p = percepts[2]
    pp = PerceptParser("R", p.robot_type)
    pp.parse(format_percept(p, "R", "L", first=True))
    q = pp.parse("(time (now 9.00))(GS (sl 1) (sr 2) (t 3.00) (pm KickOff_Left))(HJ (n hj1) (ax 90))")
    assert (q.time, q.game_time, q.play_mode, q.side, q.unum) == (9.0, 3.0, "KickOff_Left", "R", 1)
    assert (q.score_left, q.score_right) == (1, 2)
    assert q.joints[0] == pytest.approx(math.pi / 2)
    np.testing.assert_allclose(q.joints[1:], p.joints[1:], atol=1e-4)  # 2 decimals of degrees
    assert q.vision is None and not q.foot_forces.any()  # no FRP: no contact


def test_hear_without_team_from_older_servers():
    q = PerceptParser("A").parse("(hear 1.00 self abc)(hear 1.00 -90 de)(hear B 1.00 45 f)")
    assert [(h.team, h.text) for h in q.heard] == [("self", "abc"), ("ours", "de"), ("theirs", "f")]
    assert q.heard[1].direction == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize("bad", [
    "(GYR (n torso) (rt 1 2))", "(HJ (n hj1) (ax nope))", "(GS (team middle))",
    "(See (B (pol 1 2)))", "(See (P (team A) (id x)))", "(hear 1)", "(time (now))",
])
def test_percept_malformed_known_expressions(bad):
    with pytest.raises(ProtocolError):
        PerceptParser("A").parse(bad)


def test_percept_unknown_expressions_ignored():
    q = PerceptParser("A").parse("(AgentState (temp 48) (battery 75))(TCH n bumper val 0)")
    assert q.vision is None


# ------------------------------------------------------------------------ actions


def test_agent_handshake_messages():
    m = parse_agent_message(format_scene(3) + format_init(7, "Villa"))
    assert m.scene == ("rsg/agent/nao/nao_hetero.rsg", 3) and m.init == (7, "Villa") and not m.errors
    assert parse_agent_message("(scene rsg/agent/nao/nao.rsg)").scene == ("rsg/agent/nao/nao.rsg", 0)
    assert parse_agent_message("(init (unum 0)(teamname a b))").errors  # team name with a space
    assert parse_agent_message("(scene x 9)").errors


def test_action_round_trip_and_units():
    rng = np.random.default_rng(1)
    for t in range(5):
        v = rng.uniform(-6, 6, len(nao.joints(t)))
        a = Action(v, say="ab+-=", beam=(-3.0, 1.5, math.radians(30.0)))
        text = format_action(a, t, digits=None)
        assert text.endswith("(say ab+-=)(syn)") and "(beam -3.0 1.5 " in text
        b = parse_action(text, t)
        np.testing.assert_array_equal(b.joint_velocities, v)
        assert b.say == a.say and b.beam == pytest.approx(a.beam)
    assert "(he1 0.12346)" in format_action(Action(np.full(22, 0.123456)), 0)


def test_effectors_not_sent_keep_their_velocity():
    prev = np.arange(22, dtype=float)
    a = parse_action("(he2 -1.5)(lle4 2)", 0, previous=prev)
    assert a.joint_velocities[1] == -1.5 and a.joint_velocities[nao.joint_names(0).index("llj4")] == 2
    assert a.joint_velocities[0] == 0.0 and a.joint_velocities[21] == 21.0
    assert parse_action("(lle7 1)", 0).joint_velocities.sum() == 0  # a toe on a type 0: ignored


@pytest.mark.parametrize("bad", ["(he1)", "(he1 x)", "(he1 nan)", "(hx9 1)", "(beam 1 2)",
                                 "(say a b)", "(fly 1)", "((he1 1))"])
def test_bad_commands(bad):
    m = parse_agent_message(bad + "(he2 1)(syn)")
    assert m.errors and m.syn and m.velocities["he2"] == 1.0  # the rest of the message stands
    with pytest.raises(ProtocolError):
        parse_action(bad, 0)

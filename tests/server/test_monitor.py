"""The monitor port: scene graph structure, poses, game state, bad input, no effect on the match."""

import socket
import struct
import threading

import mujoco
import numpy as np

from agent.posture import PostureAgent
from models.rules import PlayMode
from models.scene import Lineup
from server.match import Match
from server.monitor import MONITOR_PLAY_MODES, STATIC_NODES, MonitorServer, part_order
from server.netclient import recv_frame, run_agent
from server.netserver import NetServer
from server.protocol import encode_frame, parse_sexp

LINEUP = Lineup((0, 4), (1,))


def poll_until(mon, m, mode: PlayMode, tries: int = 50) -> None:
    """Let the monitor server read commands until the referee is in `mode` (or give up)."""
    for _ in range(tries):
        mon.poll(m)
        if m.referee.mode == mode:
            return
        threading.Event().wait(0.01)

def parse_monitor(frame: bytes):
    gs, header, graph = parse_sexp(frame, max_depth=16, max_size=1 << 22)
    return {k[0]: k[1:] for k in gs}, header, graph


def slt(node) -> np.ndarray:
    """A transform node's 4x4 matrix (SLT is column-major)."""
    s = next(c for c in node if isinstance(c, list) and c and c[0] == "SLT")
    assert len(s) == 17
    return np.array([float(v) for v in s[1:]]).reshape(4, 4).T


def children(node):
    return [c for c in node if isinstance(c, list) and c and c[0] == "nd"]


def meshes(node):
    """Every StaticMesh below node: (model, materials)."""
    out = []
    for c in children(node):
        if c[1:2] == ["StaticMesh"]:
            load = next(x for x in c if isinstance(x, list) and x[0] == "load")[1]
            mats = next(x for x in c if isinstance(x, list) and x[0] == "resetMaterials")[1:]
            out.append((load, mats))
        out += meshes(c)
    return out


def check_poses(m: Match, graph, full: bool) -> None:
    w = m.world
    assert len(graph) == STATIC_NODES + 1 + len(w.players)
    ball = graph[STATIC_NODES]
    np.testing.assert_allclose(slt(ball)[:3, 3], w.ball_position(), atol=6e-5)
    for p, node in zip(w.players, graph[STATIC_NODES + 1:]):
        parts = children(node)
        assert len(parts) == len(part_order(p.robot_type))
        torso = slt(parts[0])
        q = w.data.qpos[p.root_qpos:p.root_qpos + 7]  # the torso's free joint: x y z, quaternion
        R = np.empty(9)
        mujoco.mju_quat2Mat(R, q[3:])
        R = R.reshape(3, 3)  # project axes: x forward, y left
        np.testing.assert_allclose(torso[:3, 3], q[:3], atol=6e-5)
        np.testing.assert_allclose(torso[:3, 1], R[:, 0], atol=6e-5)  # SimSpark y = forward
        np.testing.assert_allclose(torso[:3, 0], -R[:, 1], atol=6e-5)  # SimSpark x = right
        np.testing.assert_allclose(torso[3], [0, 0, 0, 1])
        if full:
            team = "matLeft" if p.side == "L" else "matRight"
            found = [ms for ms in meshes(node) if f"matNum{p.unum}" in ms[1] and team in ms[1]]
            assert found and found[0][0] == "models/naobody.obj"
            names = {ms[0] for ms in meshes(node)}
            assert {"models/naohead.obj", "models/lfoot.obj", "models/rthigh.obj"} <= names
        else:
            assert all(c == ["nd"] for c in graph[:STATIC_NODES])


def check_state(m: Match, gs: dict, full: bool) -> None:
    ref = m.referee
    assert float(gs["time"][0]) == round(ref.game_time, 2)
    assert gs["score_left"] == [str(ref.score["L"])] and gs["score_right"] == [str(ref.score["R"])]
    assert MONITOR_PLAY_MODES[int(gs["play_mode"][0])] == ref.mode.value
    assert gs["half"] == [str(ref.half)]
    if full:
        assert gs["play_modes"] == list(MONITOR_PLAY_MODES)
        assert gs["FieldLength"] == ["30"] and gs["FieldWidth"] == ["20"]
        assert gs["team_left"] == [m.team_names[0]] and gs["team_right"] == [m.team_names[1]]
    else:
        assert "team_left" not in gs and "play_modes" not in gs


def connect(mon: MonitorServer) -> socket.socket:
    s = socket.create_connection(mon.address, timeout=10)
    return s


def test_header_and_updates_match_the_world():
    m = Match(PostureAgent, PostureAgent, LINEUP, seed=3)
    mon = MonitorServer(port=0)
    try:
        c = connect(mon)
        for k in range(60):
            m.step()
            mon.update(m)
            if k < 3 or k % 20 == 19:  # the full graph, then deltas (the beams move the robots)
                gs, header, graph = parse_monitor(recv_frame(c))
                full = k == 0
                assert header == (["RSG", "0", "1"] if full else ["RDS", "0", "1"])
                check_state(m, gs, full)
                check_poses(m, graph, full)
            else:
                recv_frame(c)
        assert m.referee.mode != PlayMode.BEFORE_KICK_OFF  # the play mode changed on the way
        c.close()
    finally:
        mon.close()


def test_monitors_and_bad_input_leave_the_match_alone():
    n = 50
    ref = Match(PostureAgent, PostureAgent, LINEUP, seed=7)
    for _ in range(n):
        ref.step()
    m = Match(PostureAgent, PostureAgent, LINEUP, seed=7)
    mon = MonitorServer(port=0)
    try:
        reader, quitter, silent, garbage = (connect(mon) for _ in range(4))
        for k in range(n):
            m.step()
            mon.update(m)
            recv_frame(reader)
            if k < 5:
                recv_frame(quitter)
            elif k == 5:
                quitter.close()  # mid-match
            if k == 10:
                bad = [b"(((", b")(", b"\xff\xfe", b"(ball (pos a b c))", b"(ball (pos 1e9 0 0))",
                       b"(playMode NoSuchMode)", b"(kickOff Middle)", b"(agent (unum 1))", b"()",
                       b"(" * 100, b"atom", b"(ball (pos 1 2))"]
                garbage.sendall(b"".join(encode_frame(x) for x in bad) + b"\x00\x00")
            if k == 20:
                garbage.sendall(b"\x00\x00" + struct.pack(">I", 1 << 30))  # oversized: dropped
        np.testing.assert_array_equal(m.world.data.qpos, ref.world.data.qpos)
        assert m.referee.events == ref.referee.events
        assert len(mon.clients) == 2  # reader and silent; quitter and garbage are gone
        silent.close()
        reader.close()
        garbage.close()
    finally:
        mon.close()


def test_monitor_commands():
    m = Match(PostureAgent, PostureAgent, LINEUP, seed=1)
    mon = MonitorServer(port=0)
    try:
        c = connect(mon)
        m.step()
        mon.update(m)
        recv_frame(c)
        c.sendall(encode_frame("(ball (pos 1 2 0.5) (vel 0 0 0))") + encode_frame("(playMode PlayOn)"))
        poll_until(mon, m, PlayMode.PLAY_ON)
        assert m.referee.mode == PlayMode.PLAY_ON
        np.testing.assert_allclose(m.world.ball_position(), [1, 2, 0.5])
        c.sendall(encode_frame("(kickOff Right)") + encode_frame("(reqfullstate)"))
        poll_until(mon, m, PlayMode.KICK_OFF_RIGHT)
        assert m.referee.mode == PlayMode.KICK_OFF_RIGHT
        m.step()
        mon.update(m)
        assert parse_monitor(recv_frame(c))[1] == ["RSG", "0", "1"]
        c.close()
    finally:
        mon.close()


def test_netserver_monitor_port():
    srv = NetServer(port=0, players=1, seed=2, join_timeout=30, monitor_port=0)
    host, port = srv.address
    frames = []
    connected = threading.Event()

    def watch():
        with socket.create_connection(srv.monitor.address, timeout=20) as s:
            connected.set()
            while True:
                try:
                    frames.append(recv_frame(s))
                except (ConnectionError, OSError):
                    return
    threading.Thread(target=watch, daemon=True).start()
    assert connected.wait(10)
    agent = threading.Thread(target=run_agent, args=(host, port, "Home", 1, 0, PostureAgent),
                             kwargs={"timeout": 20}, daemon=True)
    agent.start()
    srv.run(max_cycles=10)
    agent.join(10)
    for _ in range(100):
        if len(frames) >= 10:
            break
        threading.Event().wait(0.02)
    assert len(frames) == 10
    gs, header, graph = parse_monitor(frames[0])
    assert header == ["RSG", "0", "1"] and gs["team_left"] == ["Home"]
    assert all(parse_monitor(f)[1] == ["RDS", "0", "1"] for f in frames[1:])
    assert len(graph) == STATIC_NODES + 1 + 2  # the away side gets one robot without an agent

"""The league's protocol over real sockets (127.0.0.1, ephemeral ports): our server with
remote agents plays like the same match in-process, and bad agents never stop it."""

import socket
import struct
import threading

import numpy as np
import pytest

from agent.posture import PostureAgent
from models.scene import Lineup
from server.match import Match
from server.netclient import recv_frame, run_agent
from server.netserver import NetServer
from server.protocol import encode_frame, format_init, format_scene

CYCLES = 60  # 1.2 game s


def start_clients(srv, specs, **kw):
    """One thread per (team, unum, type) running our client with posture agents."""
    host, port = srv.address
    results, threads = {}, []

    def play(team, unum, t):
        results[(team, unum)] = run_agent(host, port, team, unum, t, PostureAgent, timeout=20, **kw)
    for spec in specs:
        th = threading.Thread(target=play, args=spec, daemon=True)
        th.start()
        threads.append(th)
    return results, threads


def raw_client(srv, team, unum, behave):
    """A hand-written client: connects, says scene and init, then `behave(sock)`."""
    def run():
        with socket.create_connection(srv.address, timeout=20) as s:
            s.sendall(encode_frame(format_scene(0)) + encode_frame(format_init(unum, team)))
            behave(s)
    th = threading.Thread(target=run, daemon=True)
    th.start()
    return th


def test_remote_match_equals_in_process_match():
    srv = NetServer(port=0, players=3, seed=5, digits=None, join_timeout=30)
    # The first team to init plays left; start it alone so that the sides are known.
    results, threads = start_clients(srv, [("Home", 2, 4), ("Home", 1, 0)], digits=None)
    results2, threads2 = {}, []
    srv_thread_done = threading.Event()

    def away():
        import time
        while not srv.teams:  # wait for the home team's init before the away team connects
            time.sleep(0.01)
        r, t = start_clients(srv, [("Away", 1, 1)], digits=None)
        results2["away"] = r
        threads2.extend(t)
        srv_thread_done.set()
    threading.Thread(target=away, daemon=True).start()
    srv.join()
    srv_thread_done.wait(10)
    m = srv.build()
    assert m.team_names == ("Home", "Away") and m.lineup == Lineup((0, 4), (1,))
    srv.run(max_cycles=CYCLES)
    for th in threads + threads2:
        th.join(10)
    ref = Match(PostureAgent, PostureAgent, Lineup((0, 4), (1,)), seed=5)
    for _ in range(CYCLES):
        ref.step()
    # Exact numbers on the wire; degrees <-> radians round to within an ulp, nothing more.
    np.testing.assert_allclose(m.world.data.qpos, ref.world.data.qpos, atol=1e-9)
    assert not m.crashed
    all_results = {**results, **results2["away"]}
    assert all(r.cycles >= CYCLES for r in all_results.values())
    assert all_results[("Away", 1)].side == "R" and all_results[("Home", 2)].unum == 2


def test_league_precision_stays_close():
    """With the league's 2 decimals the agents see rounded angles: the match drifts a little."""
    srv = NetServer(port=0, players=2, seed=1, join_timeout=30)
    _, threads = start_clients(srv, [("A", 1, 0), ("B", 1, 0)])
    srv.join()
    m = srv.build()
    srv.run(max_cycles=CYCLES)
    for th in threads:
        th.join(10)
    left = m.world.players[0] if m.team_names[0] == "A" else m.world.players[1]
    assert not m.crashed
    ref = Match(PostureAgent, PostureAgent, Lineup((0,), (0,)), seed=1)
    for _ in range(CYCLES):
        ref.step()
    d = np.abs(m.world.data.qpos - ref.world.data.qpos).max()
    assert d < 1e-3, d  # 7.6e-5 (rad or m) after 1.2 s when measured
    assert left.unum == 1


def test_silent_agent_times_out_and_the_match_goes_on():
    srv = NetServer(port=0, players=2, seed=2, timeout=0.05, join_timeout=30)
    stop = threading.Event()
    silent = raw_client(srv, "Mute", 1, lambda s: stop.wait(20))  # reads nothing, says nothing
    _, threads = start_clients(srv, [("Talk", 1, 0)])
    srv.join()
    m = srv.build()
    i = [p.side for p in m.world.players].index("L" if m.team_names[0] == "Mute" else "R")
    srv.run(max_cycles=10)
    stop.set()
    silent.join(10)
    for th in threads:
        th.join(10)
    assert m.cycle == 10 and i not in m.crashed  # slow, not crashed
    assert m.agents[i].missed == 10


def test_garbage_and_disconnects_never_stop_the_server():
    srv = NetServer(port=0, players=3, seed=4, timeout=0.2, join_timeout=30)

    def garbage(s):
        recv_frame(s), recv_frame(s)  # the two handshake answers
        for bad in (b"(((", b"\xff\xfe", b"(he1 x)(fly 3)(he2 1)(syn)", b")"):
            recv_frame(s)
            s.sendall(encode_frame(bad) if bad != b")" else struct.pack(">I", 1) + bad)
        recv_frame(s)
        s.sendall(struct.pack(">I", 1 << 30))  # an oversized frame: crashed

    def quitter(s):
        recv_frame(s), recv_frame(s)
        recv_frame(s)
        s.sendall(encode_frame("(he1 1)(syn)"))  # one answer, then gone

    g = raw_client(srv, "Bad", 1, garbage)
    q = raw_client(srv, "Bad", 2, quitter)
    _, threads = start_clients(srv, [("Good", 1, 0)])
    srv.join()
    m = srv.build()
    srv.run(max_cycles=15)
    for th in [g, q] + threads:
        th.join(10)
    assert m.cycle == 15
    reasons = {m.world.players[i].unum: r for i, r in m.crashed.items()}
    assert set(reasons) == {1, 2}
    assert "over the limit" in reasons[1] and "disconnected" in reasons[2]
    bad = [a for a in m.agents if getattr(a, "team", None) == "Bad"]
    assert bad[0].errors >= 4  # malformed x2, bad he1 value, unknown fly
    events = [e for e in m.referee.events if e.kind == "agent_crashed"]
    assert len(events) == 2


def after_first_team(srv, fn):
    """Run fn in a thread once the server (joining in this thread) knows the first team."""
    import time

    def run():
        while not srv.teams:
            time.sleep(0.01)
        fn()
    th = threading.Thread(target=run, daemon=True)
    th.start()
    return th


def test_lobby_refuses_taken_numbers_and_a_third_team():
    srv = NetServer(port=0, players=3, seed=0, join_timeout=30)
    closed = []

    def expect_close(s):
        try:
            while True:
                recv_frame(s)
        except (ConnectionError, OSError):
            closed.append(True)
    start_clients(srv, [("A", 1, 0)], max_cycles=1)
    t1 = after_first_team(srv, lambda: raw_client(srv, "A", 1, expect_close).join(10))  # taken

    def then_b_c():
        start_clients(srv, [("B", 0, 0)], max_cycles=1)  # unum 0: any free number
        import time
        while len(srv.teams) < 2:
            time.sleep(0.01)
        raw_client(srv, "C", 1, expect_close).join(10)  # a third team
        start_clients(srv, [("A", 0, 0)], max_cycles=1)
    t2 = after_first_team(srv, then_b_c)
    srv.join()
    t1.join(10)
    t2.join(10)
    assert closed == [True, True]
    m = srv.build()
    assert m.lineup == Lineup((0, 0), (0,))
    srv.run(max_cycles=2)


class _Joining:
    """An agent in the lobby that said its scene (its robot type) and now says init."""

    def __init__(self, robot_type):
        self.robot_type, self.side, self.unum, self.team, self.closed = robot_type, None, None, None, ""
        self.name = f"type {robot_type}"

    def close(self, why):
        self.closed = why

    def send(self, text):
        pass


def test_lobby_holds_a_team_to_the_robot_type_rule():
    srv = NetServer(port=0, players=11, seed=0, join_timeout=1)
    try:
        def join(t):
            a = _Joining(t)
            srv.lobby.append(a)
            srv._init(a, 0, "A")
            return a.closed
        assert [join(4) for _ in range(7)] == [""] * 7
        assert "8 robots of type 4; at most 7" in join(4)
        assert [join(0), join(0)] == ["", ""]
        assert "10 robots of two types; at most 9" in join(0)
        assert join(1) == ""
        assert [a.unum for a in srv._joined()] == list(range(1, 11))
        assert join(3) == ""  # the 11th: three types
    finally:
        srv.listener.close()


def test_bad_server_settings():
    with pytest.raises(ValueError, match="players"):
        NetServer(port=0, players=0)


def test_cli_server_and_agents(tmp_path, capsys):
    """`soccer server` and two `soccer agent`s play a short match to GameOver."""
    import json
    import time

    from cli.main import main
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    rc = {}
    out = tmp_path / "result.json"
    server = threading.Thread(target=lambda: rc.setdefault("server", main([
        "server", "--port", str(port), "--players", "2", "--sync", "--half-time", "0.1", "--quiet",
        "--out", str(out)])), daemon=True)
    server.start()
    agents = []
    for name in ("A", "B"):
        for _ in range(200):  # until the server listens
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                time.sleep(0.02)
        th = threading.Thread(target=lambda n=name: rc.setdefault(n, main([
            "agent", "--port", str(port), "--team", n, "--unum", "1", "--team-impl", "posture"])),
            daemon=True)
        th.start()
        agents.append(th)
    server.join(60)
    for th in agents:
        th.join(10)
    assert rc == {"server": 0, "A": 0, "B": 0}
    result = json.loads(out.read_text())
    assert result["game_time"] == pytest.approx(0.2) and result["teams"] == {"L": "A", "R": "B"} or \
        result["teams"] == {"L": "B", "R": "A"}
    assert "GameOver" in capsys.readouterr().out


@pytest.mark.parametrize("args, needle", [
    (["agent", "--team", "a b"], "team name"), (["agent", "--team", "A", "--unum", "12"], "unum"),
    (["server", "--players", "0"], "players"), (["server", "--port", "x"], "port"),
    (["server", "--monitor-port", "70000"], "port"), (["server", "--monitor-interval", "0"], "interval"),
])
def test_cli_bad_options(args, needle, capsys):
    from cli.main import main
    with pytest.raises(SystemExit) as e:
        main(args)
    assert e.value.code == 2 and needle in capsys.readouterr().err

"""One of our agents (any team factory) as a client of a league server.

`run_agent` connects, says scene and init, then answers every percept that
carries joint angles: the percept is parsed into a `Percept`
(`server.protocol.PerceptParser`, the inverse of `format_percept`), the agent's
`act` makes an Action, and the client sends every hinge effector, beam, say and
`(syn)` in one frame. The agent is made once the server has told the side (the
first GS with `team`). It stops at GameOver, when the server closes the
connection, or after `max_cycles` answers; an exception in `act` ends it (the
server then treats the robot as crashed, as the league does).
"""

from __future__ import annotations

import logging
import socket
from collections.abc import Callable
from dataclasses import dataclass

from models.rules import PlayMode
from server.protocol import (
    HEADER,
    MAX_MESSAGE,
    PerceptParser,
    ProtocolError,
    encode_frame,
    format_action,
    format_init,
    format_scene,
)

log = logging.getLogger(__name__)


@dataclass
class ClientResult:
    cycles: int = 0  # percepts answered
    messages: int = 0  # frames received
    side: str | None = None
    unum: int = 0
    last_time: float = 0.0
    last_mode: str = ""
    reason: str = ""  # why it stopped


def recv_exact(sock: socket.socket, n: int) -> bytes:
    buf = bytearray()
    while len(buf) < n:
        chunk = sock.recv(n - len(buf))
        if not chunk:
            raise ConnectionError("server closed the connection")
        buf += chunk
    return bytes(buf)


def recv_frame(sock: socket.socket, max_size: int = MAX_MESSAGE) -> bytes:
    (n,) = HEADER.unpack(recv_exact(sock, 4))
    if n > max_size:
        raise ProtocolError(f"frame of {n} bytes announced, over the limit of {max_size}")
    return recv_exact(sock, n)


def run_agent(host: str, port: int, team: str, unum: int, robot_type: int, factory: Callable,
              seed: int = 0, timeout: float = 30.0, max_cycles: int | None = None,
              digits: int | None = 5) -> ClientResult:
    """Play one robot of team `team` on the server at host:port (see the module's docstring)."""
    res = ClientResult()
    with socket.create_connection((host, port), timeout=timeout) as sock:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.sendall(encode_frame(format_scene(robot_type)) + encode_frame(format_init(unum, team)))
        parser = PerceptParser(team, robot_type, unum)
        agent = None
        side_known = False
        while max_cycles is None or res.cycles < max_cycles:
            try:
                frame = recv_frame(sock)
            except (TimeoutError, ConnectionError, OSError) as exc:
                res.reason = f"connection: {exc}"
                break
            res.messages += 1
            p = parser.parse(frame)
            side_known = side_known or b"(team " in frame[:200]
            res.side, res.unum, res.last_time, res.last_mode = p.side, p.unum, p.time, p.play_mode
            if p.play_mode == PlayMode.GAME_OVER.value:
                res.reason = "game over"
                break
            if b"(HJ " not in frame:
                continue  # no body yet (a handshake message)
            if agent is None:
                if not side_known:
                    log.warning("percept before the server told our side; assuming %s", p.side)
                agent = factory(p.side, p.unum, robot_type, seed)
            action = agent.act(p)
            sock.sendall(encode_frame(format_action(action, robot_type, syn=True, digits=digits)))
            res.cycles += 1
        else:
            res.reason = "max cycles"
    return res

"""Our world and referee behind the league's agent protocol (TCP, rcssserver3d's framing).

Agents connect, say `(scene rsg/agent/nao/nao_hetero.rsg TYPE)` and
`(init (unum N)(teamname NAME))`; the first team to init plays left, the second
right (a third is refused), unum 0 takes the lowest free number. When `players`
agents have joined (or `wait` seconds after the first one did) the line-up is
fixed, the listening socket closes, and a `server.match.Match` plays with one
`RemoteAgent` per connection. Uniform numbers missing below a team's highest are
robots without an agent (treated as crashed from the start).

Each cycle the server sends every agent its percept and collects the answers:
in sync mode (rcssserver3d's agentSyncMode) the world steps as soon as every
connected agent has sent `(syn)`, or after `timeout` seconds; in real-time mode
it steps every 20 ms of wall time. Effectors an agent does not send keep their
last velocity (SimSpark's motors do), so an agent that misses a cycle keeps
moving as before; the miss is logged. An agent that disconnects, sends an
oversized frame or stops reading its percepts has crashed: its robot gets zero
joint velocities from then on and the match records `agent_crashed`. Malformed
messages and unknown commands are logged for that agent and otherwise ignored.
Memory per connection is bounded: one incoming frame (`MAX_AGENT_MESSAGE`) and
`MAX_OUTGOING` bytes of unsent percepts.

With `monitor_port` the server also opens the league's monitor port
(`server.monitor.MonitorServer`): monitors may connect from the start and get
the scene after every `monitor_interval` cycles of the match.
"""

from __future__ import annotations

import logging
import selectors
import socket
import time as wallclock

import numpy as np

from models import nao
from models.messages import Action, Percept
from models.rules import CYCLE, HALF_TIME, PlayMode, Side, robot_type_join_problem
from models.scene import Lineup
from server.connection import Connection
from server.match import Match, MatchResult
from server.monitor import MonitorServer
from server.protocol import (
    MAX_AGENT_MESSAGE,
    AgentMessage,
    ProtocolError,
    encode_frame,
    format_percept,
    parse_agent_message,
    velocities,
)

log = logging.getLogger(__name__)

MAX_OUTGOING = 1 << 18  # bytes of percepts queued for an agent that does not read them


class RemoteAgent(Connection):
    """One agent connection: the `act(percept) -> Action` of a match's agent."""

    def __init__(self, sock: socket.socket, addr) -> None:
        super().__init__(sock, addr, MAX_AGENT_MESSAGE)
        self.robot_type: int | None = None
        self.unum = 0
        self.team: str | None = None
        self.side: str | None = None
        self.opponent = "opponent"
        self.velocities: np.ndarray | None = None
        self.pending: list[AgentMessage] = []
        self.synced = False
        self.first = True
        self.missed = 0
        self.digits: int | None = 2
        self.timeout = 1.0

    @property
    def name(self) -> str:
        return f"{self.team or '?'}#{self.unum} ({self.addr[0]}:{self.addr[1]})"

    # --------------------------------------------------------------- socket i/o

    def send(self, text: str) -> None:
        """Queue one frame and write what the socket takes now."""
        if self.closed:
            return
        self.out += encode_frame(text)
        if len(self.out) > MAX_OUTGOING:
            self.close(f"not reading its percepts ({len(self.out)} bytes unsent)")
            return
        self.flush()

    def receive(self) -> None:
        """Read what is there; complete frames become `pending` messages."""
        for f in self.read_frames():
            try:
                msg = parse_agent_message(f)
            except ProtocolError as exc:
                self.error(f"malformed message: {exc}")
                continue
            for e in msg.errors:
                self.error(e)
            self.pending.append(msg)
            self.synced = self.synced or msg.syn

    # -------------------------------------------------------------- the match

    def percept_text(self, p: Percept) -> str:
        text = format_percept(p, self.team or "left", self.opponent, first=self.first, digits=self.digits)
        self.first = False
        return text

    def action(self) -> Action:
        """The action of the messages received since the last cycle (the last velocities
        when there were none)."""
        v, say, beam = self.velocities, None, None
        for msg in self.pending:
            v = velocities(msg, self.robot_type, v)
            say = msg.say if msg.say is not None else say
            beam = msg.beam if msg.beam is not None else beam
        self.pending.clear()
        self.synced = False
        self.velocities = v
        return Action(v.copy(), say=say, beam=beam)

    def act(self, percept: Percept) -> Action:
        """Send the percept and wait (up to `timeout`) for the agent's (syn)."""
        self.send(self.percept_text(percept))
        wait_for([self], self.timeout, sync=True)
        if self.closed:
            raise ConnectionError(self.closed)
        return self.action()


def wait_for(agents: list[RemoteAgent], timeout: float, sync: bool) -> None:
    """Read the agents' answers until every open one has sent (syn) (sync) or until
    `timeout` seconds have passed (always, in real-time mode)."""
    deadline = wallclock.monotonic() + timeout
    sel = selectors.DefaultSelector()
    try:
        while True:
            live = [a for a in agents if not a.closed]
            if not live or (sync and all(a.synced for a in live)):
                return
            left = deadline - wallclock.monotonic()
            if left <= 0:
                return
            for a in live:
                ev = selectors.EVENT_READ | (selectors.EVENT_WRITE if a.out else 0)
                sel.register(a.sock, ev, a)
            for key, ev in sel.select(left):
                a = key.data
                if ev & selectors.EVENT_WRITE:
                    a.flush()
                if ev & selectors.EVENT_READ:
                    a.receive()
            for a in live:
                try:
                    sel.unregister(a.sock)
                except (KeyError, ValueError):
                    pass
    finally:
        sel.close()


class NetMatch(Match):
    """A Match whose agents are remote: every percept goes out before any answer is awaited."""

    sync = True
    timeout = 1.0
    monitor: MonitorServer | None = None  # the monitor port, updated after every cycle

    def step(self) -> None:
        super().step()
        if self.monitor is not None:
            self.monitor.update(self)

    def _act(self, percepts: list[Percept]) -> list[Action]:
        agents: list[RemoteAgent | None] = []
        for i, (agent, p) in enumerate(zip(self.agents, percepts)):
            if i in self.crashed or not isinstance(agent, RemoteAgent):
                agents.append(None)
                continue
            agent.send(agent.percept_text(p))
            agents.append(agent)
        live = [a for a in agents if a is not None]
        wait_for(live, self.timeout if self.sync else CYCLE, self.sync)
        actions = []
        for i, a in enumerate(agents):
            if a is None:
                actions.append(self._idle[i])
                continue
            if a.closed:
                self._crash(i, f"connection: {a.closed}")
                actions.append(self._idle[i])
                continue
            if not a.pending:
                a.missed += 1
                if a.missed in (1, 10, 100) or a.missed % 1000 == 0:
                    log.warning("%s: no answer in cycle %d (%d missed)", a.name, self.cycle, a.missed)
            actions.append(a.action())
        return actions


class NetServer:
    """The league's agent port in front of a Match (see the module's docstring)."""

    def __init__(self, host: str = "127.0.0.1", port: int = 3100, sync: bool = True,
                 half_time: float = HALF_TIME, seed: int = 0, players: int = 22,
                 wait: float | None = None, timeout: float = 1.0, join_timeout: float | None = None,
                 digits: int | None = 2, record: bool = False, monitor_port: int | None = None,
                 monitor_interval: int = 1) -> None:
        if not 1 <= players <= 22:
            raise ValueError(f"players must be 1 to 22, got {players}")
        self.sync, self.half_time, self.seed = sync, half_time, seed
        self.players, self.wait, self.timeout = players, wait, timeout
        self.join_timeout, self.digits, self.record = join_timeout, digits, record
        self.listener = socket.create_server((host, port))
        self.listener.setblocking(False)
        self.address = self.listener.getsockname()[:2]
        try:
            self.monitor = (MonitorServer(host, monitor_port, monitor_interval)
                            if monitor_port is not None else None)
        except BaseException:
            self.listener.close()
            raise
        self.lobby: list[RemoteAgent] = []
        self.teams: list[str] = []  # left, right
        self.match: NetMatch | None = None

    # ------------------------------------------------------------------- lobby

    def _joined(self) -> list[RemoteAgent]:
        return [a for a in self.lobby if a.side is not None and not a.closed]

    def _handshake(self, a: RemoteAgent) -> None:
        for msg in a.pending:
            if msg.scene and a.robot_type is None:
                a.robot_type = msg.scene[1]
                a.velocities = np.zeros(len(nao.joints(a.robot_type)))
                a.send(f"(time (now 0.00))(GS (t 0.00) (pm {PlayMode.BEFORE_KICK_OFF.value}))")
            if msg.init and a.side is None:
                self._init(a, *msg.init)
        a.pending.clear()
        a.synced = False

    def _init(self, a: RemoteAgent, unum: int, team: str) -> None:
        if a.robot_type is None:
            a.close("init before scene")
            return
        if team not in self.teams:
            if len(self.teams) == 2:
                a.close(f"a third team {team!r}; playing: {', '.join(self.teams)}")
                return
            self.teams.append(team)
        side = Side.LEFT if self.teams[0] == team else Side.RIGHT
        taken = {b.unum for b in self._joined() if b.side == side}
        if unum == 0:
            unum = min(set(range(1, 12)) - taken, default=0)
        if unum == 0 or unum in taken:
            a.close(f"unum {unum or 'any'} of {team} is taken")
            return
        problem = robot_type_join_problem([b.robot_type for b in self._joined() if b.side == side],
                                          a.robot_type)
        if problem is not None:
            a.close(f"{team} may not take a robot of type {a.robot_type}: {problem}")
            return
        a.team, a.unum, a.side = team, unum, side
        a.send(f"(time (now 0.00))(GS (unum {unum}) (team {'left' if side == 'L' else 'right'})"
               f" (t 0.00) (pm {PlayMode.BEFORE_KICK_OFF.value}))")
        log.info("%s joined as %s%d (type %d)", a.name, side, unum, a.robot_type)

    def join(self) -> None:
        """Accept agents until the line-up is complete (see the module's docstring)."""
        sel = selectors.DefaultSelector()
        sel.register(self.listener, selectors.EVENT_READ, None)
        start = wallclock.monotonic()
        first = None
        try:
            while True:
                joined = self._joined()
                now = wallclock.monotonic()
                if joined and first is None:
                    first = now
                if len(joined) >= self.players:
                    break
                if first is not None and self.wait is not None and now - first >= self.wait:
                    break
                if self.join_timeout is not None and now - start >= self.join_timeout:
                    raise TimeoutError(f"{len(joined)} of {self.players} agents joined in "
                                       f"{self.join_timeout:g} s")
                if self.monitor is not None:
                    self.monitor.poll()  # monitors may connect early; they get the scene at kickoff
                for key, _ in sel.select(0.05):
                    if key.data is None:
                        try:
                            sock, addr = self.listener.accept()
                        except (BlockingIOError, InterruptedError):
                            continue
                        a = RemoteAgent(sock, addr)
                        self.lobby.append(a)
                        sel.register(sock, selectors.EVENT_READ, a)
                        continue
                    a = key.data
                    a.receive()
                    self._handshake(a)
                    if a.closed:
                        log.warning("%s left the lobby: %s", a.name, a.closed)
                        sel.unregister(a.sock)
                        self.lobby.remove(a)
        finally:
            sel.close()
            self.listener.close()
        for a in self.lobby:  # latecomers that never said init
            if a.side is None:
                a.close("the match started before its init")

    def build(self) -> NetMatch:
        """The match of the joined agents."""
        joined = self._joined()
        by_seat = {(a.side, a.unum): a for a in joined}
        sizes = {s: max([a.unum for a in joined if a.side == s], default=0) for s in Side}
        if not sizes[Side.LEFT] or not sizes[Side.RIGHT]:
            log.warning("only one team joined; the other side gets one robot without an agent")
        types = {s: tuple(by_seat[(s, u)].robot_type if (s, u) in by_seat else 0
                          for u in range(1, max(sizes[s], 1) + 1)) for s in Side}
        names = (self.teams + ["left", "right"])[:2] if len(self.teams) < 2 else self.teams
        for a in joined:
            a.opponent = names[1] if a.side == Side.LEFT else names[0]
            a.digits = self.digits
            a.timeout = self.timeout
            a.pending.clear()  # anything said in the lobby
            a.synced = False
            a.first = True

        def factory(side, unum, robot_type, seed):
            return by_seat.get((side, unum))

        NetMatch.sync, NetMatch.timeout = self.sync, self.timeout
        m = NetMatch(factory, factory, Lineup(types[Side.LEFT], types[Side.RIGHT]),
                     half_time=self.half_time, seed=self.seed, record=self.record,
                     team_names=(names[0], names[1]))
        m.sync, m.timeout = self.sync, self.timeout
        m.monitor = self.monitor
        for i, agent in enumerate(m.agents):
            if agent is None:
                m._crash(i, "no agent connected")
        self.match = m
        return m

    def run(self, max_cycles: int | None = None, progress: bool = False) -> MatchResult:
        """Join, play, tell the agents the final state, close."""
        if self.match is None:
            self.join()
            self.build()
        m = self.match
        try:
            result = m.run(progress=progress, max_cycles=max_cycles)
            for i, (a, p) in enumerate(zip(m.agents, m.percepts())):
                if isinstance(a, RemoteAgent) and i not in m.crashed:
                    a.send(a.percept_text(p))
            wait_for([a for a in m.agents if isinstance(a, RemoteAgent)], 0.2, sync=False)
        finally:
            for a in self.lobby:
                a.close("match over")
            if self.monitor is not None:
                self.monitor.close()
        return result

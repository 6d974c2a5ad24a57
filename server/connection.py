"""A non-blocking TCP connection speaking the league's length-framed messages.

Shared by the agent port (`server.netserver.RemoteAgent`) and the monitor port
(`server.monitor.MonitorClient`): a bounded outgoing buffer written as the
socket takes it, complete incoming frames, rate-limited error logging, and one
reason kept when the connection closes. Nothing here blocks.
"""

from __future__ import annotations

import logging
import socket

from server.protocol import FrameReader, ProtocolError

log = logging.getLogger(__name__)

MAX_ERRORS_LOGGED = 20  # per connection; later ones are counted only


class Connection:
    """One framed, non-blocking connection; `closed` says why it ended (None while open)."""

    def __init__(self, sock: socket.socket, addr, max_message: int) -> None:
        self.sock = sock
        self.addr = addr
        sock.setblocking(False)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        self.reader = FrameReader(max_message)
        self.out = bytearray()
        self.closed: str | None = None
        self.errors = 0

    @property
    def name(self) -> str:
        return f"{self.addr[0]}:{self.addr[1]}"

    def close(self, why: str) -> None:
        if self.closed is None:
            self.closed = why
            try:
                self.sock.close()
            except OSError:
                pass

    def flush(self) -> None:
        """Write what the socket takes now of the queued bytes."""
        if self.closed or not self.out:
            return
        try:
            n = self.sock.send(self.out)
            del self.out[:n]
        except (BlockingIOError, InterruptedError):
            pass
        except OSError as exc:
            self.close(f"send failed: {exc}")

    def read_frames(self) -> list[str]:
        """The complete frames that arrived; a closed peer, a socket error or a bad frame
        closes the connection (and gives no frames)."""
        if self.closed:
            return []
        try:
            data = self.sock.recv(65536)
        except (BlockingIOError, InterruptedError):
            return []
        except OSError as exc:
            self.close(f"receive failed: {exc}")
            return []
        if not data:
            self.close("disconnected")
            return []
        try:
            return self.reader.feed(data)
        except ProtocolError as exc:
            self.close(str(exc))
            return []

    def error(self, text: str) -> None:
        """Log a bad message from the peer (the first MAX_ERRORS_LOGGED, then a note)."""
        self.errors += 1
        if self.errors <= MAX_ERRORS_LOGGED:
            log.warning("%s: %s", self.name, text)
        elif self.errors == MAX_ERRORS_LOGGED + 1:
            log.warning("%s: more errors, no longer logged", self.name)

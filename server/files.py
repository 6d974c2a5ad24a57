"""Atomic file output: results, logs, checkpoints and videos are never half-written.

Everything is written to a temporary file beside the target and renamed over it
when complete; a failure leaves the old file (or none) and no temporary behind.
The finished file gets the usual permissions (0666 less the umask), not the
temporary file's private 0600.
"""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_path(path: str | os.PathLike, fsync: bool = False) -> Iterator[Path]:
    """Yield a temporary path beside `path` (same suffix) to write; on success it
    replaces `path`, on an exception it is removed."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=f".tmp{path.suffix}")
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        if fsync:
            with open(tmp, "rb") as fh:
                os.fsync(fh.fileno())
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def write_bytes(path: str | os.PathLike, data: bytes, fsync: bool = False) -> None:
    """Write `data` to `path` atomically."""
    with atomic_path(path, fsync) as tmp:
        tmp.write_bytes(data)


def write_text(path: str | os.PathLike, text: str, fsync: bool = False) -> None:
    """Write `text` (UTF-8) to `path` atomically."""
    write_bytes(path, text.encode("utf-8"), fsync)


def write_json(path: str | os.PathLike, obj: object, fsync: bool = False) -> None:
    """Write `obj` as indented JSON (with a final newline) to `path` atomically."""
    write_text(path, json.dumps(obj, indent=2) + "\n", fsync)

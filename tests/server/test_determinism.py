"""The same seed gives the same match, bit for bit; the match log round-trips."""

import numpy as np
import pytest

from agent.posture import PostureAgent
from models.scene import Lineup
from server.log import LogError, read_log, write_log
from server.match import Match


def short_match(seed):
    m = Match(PostureAgent, PostureAgent, Lineup((0, 1, 4), (2, 3)), half_time=1.0, seed=seed,
              record=True)
    m.world.place_ball((0.3, 0.0))
    result = m.run()
    return m.match_log(), result


def test_same_seed_same_log(tmp_path):
    a, ra = short_match(3)
    b, rb = short_match(3)
    c, _ = short_match(4)
    assert a.qpos.shape == b.qpos.shape and len(a) > 150
    assert np.array_equal(a.qpos, b.qpos)
    assert ra.events and [e for e in ra.events] == [e for e in rb.events]
    assert not np.array_equal(a.qpos, c.qpos)  # the beam noise differs
    path = tmp_path / "m.npz"
    write_log(a, path)
    back = read_log(path)
    assert np.abs(back.qpos - a.qpos).max() <= 0.51e-5 + 1e-6 * np.abs(a.qpos).max()
    assert back.players == a.players and back.events == a.events and back.xml == a.xml


def test_corrupt_or_truncated_log_is_refused(tmp_path):
    a, _ = short_match(0)
    path = tmp_path / "m.npz"
    write_log(a, path)
    data = path.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(data[: len(data) // 2])
    with pytest.raises(LogError, match="cut.npz"):
        read_log(cut)
    junk = tmp_path / "junk.npz"
    junk.write_bytes(b"not a log at all")
    with pytest.raises(LogError, match="junk.npz"):
        read_log(junk)
    with pytest.raises(LogError, match="no such"):
        read_log(tmp_path / "missing.npz")

"""The posture agent keeps every robot type upright through the loop's motors."""

import pytest

from tests.server.helpers import run, standing_match


@pytest.mark.parametrize("t", range(5))
def test_posture_agent_stands_10_s(t):
    m = standing_match((t,), (t,))
    start = m.world.torso_positions().copy()
    run(m, 10.0)
    up = m.world.torso_up()
    pos = m.world.torso_positions()
    assert (up > 0.95).all(), up
    assert (pos[:, 2] > 0.8 * m.world.heights).all()
    # Standing still: neither drifting nor sinking.
    assert abs(pos[:, :2] - start[:, :2]).max() < 0.05
    assert m.referee.falls == {"L": 0, "R": 0}

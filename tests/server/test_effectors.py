"""Effectors: joint velocities are clamped at each joint's maximum speed; a malformed
action crashes its agent only, whose joints then get zero (tests/server/test_crashes.py)."""

import numpy as np
import pytest

from models.messages import Action
from tests.server.helpers import standing_match


@pytest.mark.parametrize("bad", [np.zeros(3), np.full(22, np.nan), None, "fast", np.zeros((22, 1))])
def test_malformed_velocities_refused_for_that_agent_only(bad):
    m = standing_match(left=(0, 0), right=(0,))
    n = [len(p.joint_qpos) for p in m.world.players]
    actions = [Action(bad), Action(np.full(n[1], 1.0)), Action(np.full(n[2], -100.0))]
    ctrl, _, warnings = m._apply(actions)
    assert not warnings and list(m.crashed) == [0] and "finite numbers" in m.crashed[0]
    acts = [p.actuators for p in m.world.players]
    assert np.all(ctrl[acts[0]] == 0.0)
    assert np.all(ctrl[acts[1]] == 1.0)
    assert np.allclose(ctrl[acts[2]], -m.max_speed[2])  # clamped at the maximum speed
    m.step()  # the loop carries on


def test_good_velocities_pass_clamped():
    m = standing_match(left=(2,), right=(4,))
    n = [len(p.joint_qpos) for p in m.world.players]
    v = [np.linspace(-20.0, 20.0, k) for k in n]
    ctrl, said, warnings = m._apply([Action(v[0]), Action(list(v[1]))])
    assert not warnings and not said
    for p, vi, top in zip(m.world.players, v, m.max_speed):
        assert np.array_equal(ctrl[p.actuators], np.clip(vi, -top, top))

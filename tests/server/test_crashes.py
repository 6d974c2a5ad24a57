"""A crashed agent (raises in act, or answers with a malformed action) is treated as
the league treats one: its robot gets zero joint velocities from then on, an
"agent_crashed" event names it, and the match goes on. Diverging physics ends the
match with PhysicsDiverged, never a silent reset."""

import numpy as np
import pytest

from agent.posture import PostureAgent
from models.messages import Action
from models.scene import Lineup
from server.match import Match, PhysicsDiverged
from tests.server.helpers import standing_match

CRASH_CYCLE = 5


class Faulty(PostureAgent):
    """A posture agent that misbehaves from cycle CRASH_CYCLE on, as `how` says."""

    how = "raise"

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.cycles = 0
        self.percepts = 0

    def act(self, percept):
        self.cycles += 1
        a = super().act(percept)
        if self.cycles < CRASH_CYCLE:
            return a
        if self.how == "raise":
            raise RuntimeError("first line\nboom at cycle 5")
        if self.how == "nan":
            return Action(np.full(len(a.joint_velocities), np.nan))
        if self.how == "short":
            return Action(a.joint_velocities[:3])
        if self.how == "not an action":
            return list(a.joint_velocities)
        raise AssertionError(self.how)


class Counting(PostureAgent):
    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.percepts = 0

    def act(self, percept):
        self.percepts += 1
        return super().act(percept)


@pytest.mark.parametrize("how", ["raise", "nan", "short", "not an action"])
def test_crashed_agent_idles_and_match_goes_on(how):
    def left(side, unum, robot_type, seed):
        a = Faulty(side, unum, robot_type, seed)
        a.how = how
        return a

    m = Match(left, Counting, Lineup((0,), (0, 0)), half_time=0.2, seed=3)
    result = m.run().to_dict()
    assert result["game_time"] == pytest.approx(0.4, abs=0.03)  # finished
    crashes = [e for e in result["events"] if e["kind"] == "agent_crashed"]
    assert len(crashes) == 1
    e = crashes[0]
    assert (e["team"], e["player"]) == ("L", 1) and e["time"] >= 0.0
    if how == "raise":
        assert e["detail"] == "act raised RuntimeError: boom at cycle 5"
    else:
        assert e["detail"]
    assert m.agents[0].cycles == CRASH_CYCLE  # never asked again
    assert all(a.percepts == m.cycle for a in m.agents[1:])  # the others still play
    ctrl, _, _ = m._apply(m._act(m.percepts()))
    assert np.all(ctrl[m.world.players[0].actuators] == 0.0)


def test_bad_say_is_dropped_with_a_warning_not_a_crash():
    m = standing_match(left=(0,), right=(0,))
    n = [len(p.joint_qpos) for p in m.world.players]
    _, said, warnings = m._apply([Action(np.zeros(n[0]), say="{}" * 20), Action(np.zeros(n[1]), say="ok")])
    assert said == {1: "ok"} and list(warnings) == [0] and not m.crashed


def test_diverging_physics_raises(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # MuJoCo appends its warning to ./MUJOCO_LOG.TXT
    m = standing_match(left=(0,), right=(0,))
    m.world.data.qvel[m.world.players[1].joint_qvel[3]] = np.nan
    with pytest.raises(PhysicsDiverged, match="R1"):
        m.step()

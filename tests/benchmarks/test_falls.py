"""benchmarks.falls: each counted fall is reported with the player's activity and its neighbours."""

from __future__ import annotations

import json
import math

import mujoco
import numpy as np
import pytest

from benchmarks import falls
from cli.teams import factory
from models.scene import Lineup
from server.match import Match
from server.world import World


class _Tripping(Match):
    """A match in which the trainer lays two standing robots down 2 s after the kickoff:
    L2 next to R2, and another of ours (`alone`) far from everyone."""

    alone: int | None = None

    def step(self):
        super().step()
        if self.referee.game_time == pytest.approx(2.0, abs=1e-6):
            w, fallen = self.world, self.referee.fallen
            self.alone = next(w.player("L", u) for u in range(3, 12) if not fallen[w.player("L", u)])
            w.place_robot(w.player("R", 2), 1.0, 5.0, math.pi)
            w.place_robot(w.player("L", 2), 1.4, 5.0, 0.0, lying="front")
            w.place_robot(self.alone, -5.0, -7.0, 0.0, lying="back")


def test_falls_are_reported_with_activity_and_neighbours():
    m = _Tripping(factory("villa"), factory("villa"), Lineup.default(), half_time=300, seed=3)
    rows = falls.fall_rows(m, 3.0)
    laid = {r["player"]: r for r in rows if r["time"] == pytest.approx(2.0, abs=0.05)}
    near, alone = laid[m.world.player("L", 2)], laid[m.alone]
    assert near["nearest_robot_m"] < falls.NEAR <= alone["nearest_robot_m"]
    assert near["activity"] in {"walkto", "stand", "kick", "dribble"} and not near["after_getup"]
    assert all(set(r["touched"]) <= set(falls.TOUCH) for r in rows)
    assert all(r["walk"] in falls.WALKS for r in rows)
    s = falls.summary([r for r in rows if r["side"] == "L"], {0: 3, 1: 2, 2: 2, 3: 2, 4: 2}, 3.0 / 60)
    assert s["falls"] >= 2 and 0 < s["near_robot"] < 1
    assert set(s["touched"]) == {*falls.TOUCH, "nothing"} and s["touched"]["nothing"] > 0  # `alone`
    assert s["open_walk"] and sum(s["open_walk"].values()) <= 1.0 + 1e-9  # `alone` fell in the open


def test_the_walk_direction_is_the_largest_share_of_the_steps_maximum():
    from types import SimpleNamespace

    from skills.walk import WalkParams

    def player(walking: bool, step: tuple[float, float, float]):
        walk = SimpleNamespace(walking=walking, params=WalkParams(), step=np.array(step))
        return SimpleNamespace(body=SimpleNamespace(motion=SimpleNamespace(walk=walk)))

    p = WalkParams()  # max steps 0.05 m, 0.04 m, 1.22 rad
    assert falls.walk_direction(player(True, (0.04, 0.01, 0.1))) == "forward"
    assert falls.walk_direction(player(True, (-0.02, 0.005, 0.1))) == "backward"
    assert falls.walk_direction(player(True, (0.02, -0.03, 0.1))) == "sideways"
    assert falls.walk_direction(player(True, (0.0, 0.0, -0.5 * p.max_step_size_angle))) == "turning"
    assert falls.walk_direction(player(True, (0.005, 0.004, 0.1))) == "in place"
    assert falls.walk_direction(player(False, (0.04, 0.0, 0.0))) == "still"
    assert falls.walk_direction(SimpleNamespace()) == ""


def test_cli(capsys):
    assert falls.main(["--seconds", "0.5", "--away", "posture"]) == 0
    *games, last = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(games) == 1 and last["teams"]["R"]["team"] == "posture"
    with pytest.raises(SystemExit):
        falls.main(["--seconds", "400"])
    assert "--seconds must be in (0, 300]" in capsys.readouterr().err


def test_touches_name_what_touched_each_player():
    """Apart, nothing touches the robots but the floor; the ball at one's foot touches
    only that one; two robots overlapping touch each other's legs, arms and trunk."""
    w = World(Lineup((4,), (0,)))
    parts = falls.geom_parts(w)
    w.place_robot(0, 0.0, 0.0, 0.0)
    w.place_robot(1, 1.5, 0.0, math.pi)
    w.place_ball((5.0, 5.0))
    mujoco.mj_forward(w.model, w.data)
    assert falls.touches(w, parts).tolist() == [0, 0]
    foot = w.data.xpos[w.model.body("L1/rfoot").id]
    w.place_ball((float(foot[0]) + 0.12, float(foot[1])), 0.04)
    mujoco.mj_forward(w.model, w.data)
    assert falls.touches(w, parts).tolist() == [falls.TOUCH["ball"], 0]
    w.place_robot(1, 0.1, 0.0, math.pi)
    w.place_ball((5.0, 5.0))
    mujoco.mj_forward(w.model, w.data)
    both = falls.TOUCH["legs"] | falls.TOUCH["arms"] | falls.TOUCH["trunk"]
    assert (falls.touches(w, parts) & both).tolist() == [both, both]
    assert not np.any(falls.touches(w, parts) & falls.TOUCH["ball"])

"""The dribble_walk task: the team's dribble scored by progress, with the ball kept near."""

from __future__ import annotations

import dataclasses

import pytest

from agent.player import Player
from agent.teamconfig import VILLA
from optimization.dribble_walk import HOLD
from optimization.paramvec import load_values
from optimization.task import make_task


def test_a_trial_scores_progress_less_the_seconds_the_ball_was_away():
    task = make_task("dribble_walk", seconds=8.0)
    values = load_values(task.sets, 0)
    r = task.trial(values, 2)
    assert r.info["falls"] == 0
    assert r.info["progress"] > 0.5  # it reached the ball and pushed it toward the target
    want = r.info["progress"] - task.away_cost * r.info["away_s"]
    assert r.fitness == pytest.approx(want, abs=0.01)  # info is rounded
    assert (r.info["away_s"] > 0) == (r.info["gap"] > HOLD)


def _stand(p):
    """The walk set's stand, which the dribble sets keep from go-to-target's."""
    return [getattr(p, n) for n in ("walk_height", "default_com_pos_x", "fwd_offset", "pid_tilt", "pid_roll")]


def test_the_learned_set_is_the_one_that_walks_through_the_ball():
    """A dribble set that can hardly step forward makes less progress than the shipped
    one: the task's candidate is what the body dribbles with."""
    task = make_task("dribble_walk", seconds=8.0)
    values = load_values(task.sets, 0)
    tiny = {**values, "position_to_dribble": {**values["position_to_dribble"], "max_step_size_x": 8.0}}
    assert task.trial(tiny, 2).info["progress"] < task.trial(values, 2).info["progress"] - 0.5


def test_an_unknown_dribble_set_is_a_clear_error():
    with pytest.raises(ValueError, match="unknown dribble walk set 'dribbling'"):
        Player("L", 2, 0, config=dataclasses.replace(VILLA, dribble_set="dribbling"))


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="seconds > 0"):
        make_task("dribble_walk", seconds=0.0)


def test_the_dribble_walk_variant_dribbles_with_a_learned_set_from_the_same_stand():
    from agent.teamconfig import variant

    for t in range(5):
        body = Player("L", 2, t, config=variant("DribbleWalk")).body
        sets = body.motion.walk.sets
        assert body.dribble_set == "position_to_dribble"
        # type 3's run found nothing better than go-to-target's values, so it keeps them
        assert (sets["position_to_dribble"] == sets["go_to_target"]) == (t == 3)
        assert _stand(sets["position_to_dribble"]) == _stand(sets["go_to_target"])


def test_the_fast_dribble_variant_dribbles_with_sets_learned_from_the_fast_stands():
    from agent.teamconfig import VILLA, variant

    for t in range(5):
        body = Player("L", 2, t, config=variant("FastDribble")).body
        villa = Player("L", 2, t, config=VILLA).body.motion.walk.sets
        sets = body.motion.walk.sets
        assert body.dribble_set == "position_to_dribble"
        assert sets["go_to_target"] == villa["go_to_target"]  # only the dribble set is new
        # type 3's run found nothing better than go-to-target's values, so it keeps them
        assert (sets["position_to_dribble"] == sets["go_to_target"]) == (t == 3)
        assert _stand(sets["position_to_dribble"]) == _stand(sets["go_to_target"])

"""The position_walk task: the team's positioning walk to moving targets, scored by the
distance gained toward them less the falls."""

from __future__ import annotations

from pathlib import Path

import pytest

from optimization.layered import read_task_file
from optimization.paramvec import load_values, param_set
from optimization.position_walk import GAIT, STAND
from optimization.task import make_task

TASK_FILE = Path(__file__).parents[2] / "optimization" / "tasks" / "position_walk.task"
FAST = Path(__file__).parents[2] / "skills" / "data" / "walk_fast_type{t}.txt"


def test_a_trial_scores_the_distance_gained_less_the_falls():
    task = make_task("position_walk", 2, seconds=12.0)
    r = task.trial(load_values(task.sets, 2, [str(FAST).format(t=2)]), 4)
    assert r.info["hops"] >= 4  # a new target every 1.5-3 s
    assert r.info["gained"] > 0.5  # it walked toward its targets (which drift)
    want = r.info["gained"] - task.fall_penalty * r.info["falls"]
    assert r.fitness == pytest.approx(want, abs=0.01)  # info is rounded


def test_the_learned_set_is_the_one_the_player_walks_to_positions_with():
    """A go-to-target set that can hardly step gains much less: the task's candidate is
    what the body positions itself with."""
    task = make_task("position_walk", 2, seconds=12.0)
    values = load_values(task.sets, 2, [str(FAST).format(t=2)])
    tiny = {"go_to_target": {**values["go_to_target"], "max_step_size_x": 8.0, "max_step_size_y": 8.0}}
    assert task.trial(tiny, 4).info["gained"] < task.trial(values, 4).info["gained"] - 1.0


def test_the_task_learns_the_gait_and_leaves_the_stand():
    gtt = param_set("go_to_target")
    for name in (*GAIT, *STAND):
        gtt.spec(name)  # each is an optimizable go-to-target parameter
    assert not set(GAIT) & set(STAND)
    assert make_task("position_walk").optimize == {"go_to_target": GAIT}
    (layer,) = read_task_file(TASK_FILE)
    assert layer.optimize == {"go_to_target": GAIT}


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="seconds > 0"):
        make_task("position_walk", seconds=0.0)
    with pytest.raises(ValueError, match="fall_penalty >= 0"):
        make_task("position_walk", fall_penalty=-1.0)

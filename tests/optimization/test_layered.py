"""Layered learning as task files: optimized, frozen, seeded and overlapping sets."""

import numpy as np
import pytest

from optimization.layered import TASK_DIR, find_task, parse_task_file, read_task_file
from optimization.paramvec import write_param_file
from skills.params import ParamError


def test_shipped_task_files_parse():
    for path in sorted(TASK_DIR.glob("*.task")):
        assert read_task_file(path), path
    layers = read_task_file(find_task("walk"))
    assert [ly.name for ly in layers] == ["go_to_target", "sprint", "position_to_dribble"]
    sprint = layers[1]
    assert sprint.optimize == {"sprint": None} and sprint.freeze == ("go_to_target",)
    assert sprint.seed_from == {"sprint": "go_to_target"} and sprint.inputs == ("go_to_target",)
    assert sprint.settings == {"population": 150, "generations": 300, "trials": 2}


def test_sequence_feeds_results_seeds_and_overlaps(tmp_path):
    layers = parse_task_file("""
layer a
  task walk_forward seconds=1
  optimize go_to_target phase_length walk_height
layer b
  task sprint
  input a
  seed sprint go_to_target
  optimize sprint max_step_size_x
layer c
  task sprint
  input a b
  overlap go_to_target phase_length   # the seam
  overlap sprint
""")
    a = layers[0].problem()
    assert a.task.name == "walk_forward" and a.task.phases[1].duration == 1.0
    best = a.space.values(np.array([1.0, 0.0]))  # pretend layer a learned this
    write_param_file(tmp_path / "a.txt", best)
    b = layers[1].problem(results={"a": tmp_path / "a.txt"})
    learned = best["go_to_target"]["phase_length"]
    assert b.space.base["go_to_target"]["phase_length"] == pytest.approx(learned, rel=1e-5)  # frozen input
    assert b.space.base["sprint"]["phase_length"] == pytest.approx(learned, rel=1e-5)  # seeded
    assert b.space.keys == (("sprint", "max_step_size_x"),)
    write_param_file(tmp_path / "b.txt", b.space.values(np.array([1.0])))
    c = layers[2].problem(results={"a": tmp_path / "a.txt", "b": tmp_path / "b.txt"})
    keys = set(c.space.keys)
    assert ("go_to_target", "phase_length") in keys and ("go_to_target", "walk_height") not in keys
    assert ("sprint", "max_step_size_x") in keys and len(keys) == 28


@pytest.mark.parametrize("text,needle", [
    ("task go_to_target\n", "<string>:1: expected 'layer NAME' before 'task'"),
    ("layer a\n task walk\n", "<string>:2: unknown task"),
    ("layer a\n task sprint\n optimize sprnt\n", "<string>:3: unknown parameter set"),
    ("layer a\n task sprint\n optimize sprint pid_x\n", "<string>:3: set sprint has no parameter"),
    ("layer a\n task sprint\n input b\n", "<string>:3: input must be an earlier layer"),
    ("layer a\n task sprint\n overlap go_to_target\n", "<string>:3: overlap needs an input layer"),
    ("layer a\n task sprint\n freeze sprint\n optimize sprint\n", "<string>:4: set both frozen and learned"),
    ("layer a\n task sprint\n generations many\n", "<string>:3: generations must be a number"),
    ("layer a\n task walk_forward speed=3\n", "<string>:1: layer a: task walk_forward has no option"),
    ("layer a\n", "<string>:1: layer names no task"),
])
def test_errors_name_the_line(text, needle):
    with pytest.raises(ParamError) as err:
        parse_task_file(text)
    assert needle in str(err.value)

"""Getup optimization tasks: parameter sets, fitness that tells good from broken, seeds, the CLI."""

import pytest

from cli.main import main
from models import nao
from optimization.getup import GetupTask
from optimization.paramvec import PARAM_SETS, ParamSpace, load_values, write_param_file
from optimization.task import make_task
from skills.falls import load_getup_skills
from skills.params import UNITS


@pytest.mark.parametrize("name, prefix", [("getup_front", "front_"), ("getup_back", "back_")])
def test_parameter_sets_cover_their_skill_and_load_the_shipped_values(name, prefix):
    d = PARAM_SETS[name]
    assert d.prefix == prefix
    assert {s.name for s in d.specs} == set(d.schema) and len(d.schema) == 40  # 5 poses x 8 slots
    values = load_values([name], 0)[name]
    assert set(values) == set(d.schema)
    for s in d.specs:  # the shipped values lie inside the bounds, scales are positive
        assert s.lower <= values[s.name] <= s.upper and s.sigma > 0
    assert d.spec("k1_wait").sigma < 1.0 and d.spec("k1_hip").sigma >= 1.0  # s vs degrees
    space = ParamSpace.build(load_values([name], 0), make_task(name).optimize)
    assert space.dim == 40


def test_a_learned_file_loads_as_getup_parameters(tmp_path):
    values = load_values(["getup_front"], 0)
    values["getup_front"]["k2_hip"] = 77.0
    path = tmp_path / "best.txt"
    write_param_file(path, values, "learned")
    skills = load_getup_skills([path])
    hips = [k.set.get("llj3") for k in skills["GETUP_FRONT"].keyframes]  # k2 follows the lie-flat states
    assert hips[3] == pytest.approx(77.0 * UNITS["deg"]) and hips.count(hips[3]) == 1


def test_a_robot_types_own_file_overrides_the_shared_values_for_that_type_only():
    from skills.falls import getup_param_paths
    from skills.params import read_entries
    from skills.skill import skill_path

    shared = load_values(["getup_front", "getup_back"], 1)  # type 1 has no file of its own
    typed = [t for t in range(5) if len(getup_param_paths(t)) == 2]
    assert typed, "no robot type ships getup_type<T>.params"
    for t in typed:
        own = load_values(["getup_front", "getup_back"], t)  # the optimizer starts from these
        file_names = set(read_entries(getup_param_paths(t)[1]))
        for name, prefix in (("getup_front", "front_"), ("getup_back", "back_")):
            for n, v in own[name].items():
                if prefix + n in file_names:  # what the type's file sets, it overrides
                    continue
                assert v == shared[name][n]  # the rest is shared
        assert any(own[s] != shared[s] for s in own)
        skills = load_getup_skills(robot_type=t)  # what Getup(t) plays
        assert any(skills[k].keyframes != load_getup_skills(robot_type=1)[k].keyframes
                   for k in ("GETUP_FRONT", "GETUP_BACK"))
    assert getup_param_paths(1) == [skill_path("getup.params")]


def broken(name: str) -> dict:
    """Every pose angle 0 and every wait at its lower bound: the robot never gets up."""
    vals = load_values([name], 0)
    vals[name] = {n: (0.02 if PARAM_SETS[name].schema[n] == "s" else 0.0) for n in vals[name]}
    return vals


@pytest.mark.parametrize("name", ["getup_front", "getup_back"])
def test_default_parameters_score_better_than_broken_ones(name):
    task = make_task(name, controller="pid")
    good = [task.trial(load_values([name], 0), seed).fitness for seed in range(2)]
    bad = [task.trial(broken(name), seed).fitness for seed in range(2)]
    assert all(-task.seconds <= f <= 0.0 for f in good + bad)
    assert min(bad) < -3.5  # lying all the time (a few cycles of the drop may count as up)
    assert max(good) > -3.0 and min(good) > max(bad) + 0.5
    if name == "getup_back":  # a trial that does not end standing loses fail_penalty s more
        harsh = make_task(name, controller="pid", fail_penalty=5.0)
        lying = task.trial(broken(name), 0).fitness
        assert harsh.trial(broken(name), 0).fitness == pytest.approx(lying - 5.0)
        assert harsh.trial(load_values([name], 0), 0).fitness == good[0]  # seed 0 stands at the end


def test_a_walk_start_lies_with_the_walks_bent_legs(monkeypatch):
    """start="walk": the robot lies as a walking robot lands, its joints about the walk's
    stand pose (knees bent), and the shipped front getup stands from there; "flat" lies
    with its joints about 0."""
    from server.world import World
    from skills.walk import WalkEngine

    placed = []
    place = World.place_robot
    monkeypatch.setattr(World, "place_robot", lambda self, i, *a, joints=None, **k: (
        placed.append(joints), place(self, i, *a, joints=joints, **k))[1])
    knee = nao.joint_names(0).index("llj4")
    stand_knee = WalkEngine(0).update(0.0, 0.0, 0.0).targets[knee]
    assert stand_knee < -0.5  # the walk stands on bent knees
    vals = load_values(["getup_front"], 0)
    walk = GetupTask("getup_front", robot_type=0, start="walk", fail_penalty=3.0)
    results = [walk.trial(vals, seed) for seed in range(3)]
    assert all(abs(q[knee] - stand_knee) < 0.2 for q in placed if q is not None)
    assert sum(r.info["standing_at_end"] for r in results) >= 2
    placed.clear()
    GetupTask("getup_front", robot_type=0).trial(vals, 0)
    assert all(abs(q[knee]) < 0.6 for q in placed if q is not None)
    placed.clear()
    mixed = GetupTask("getup_front", robot_type=0, start="mixed", seconds=0.1, settle=0.02)
    starts = [mixed.trial(vals, seed).info["start"] for seed in range(8)]
    assert set(starts) == {"flat", "walk"}  # both starts drawn over 8 seeds
    for s, q in zip(starts, [q for q in placed if q is not None]):
        assert (abs(q[knee] - stand_knee) < 0.2) == (s == "walk")
    with pytest.raises(ValueError, match="start must be one of flat, walk, mixed"):
        GetupTask("getup_front", start="sitting")


def test_a_trial_is_reproducible_from_its_seed():
    task = make_task("getup_back", all_types=1)
    vals = load_values(["getup_back"], 0)
    first = task.trial(vals, 11)
    task.trial(vals, 12)  # something else ran in between
    again = task.trial(vals, 11)
    assert first == again
    assert first.info["robot_type"] in range(5)


def test_bad_task_options_raise():
    with pytest.raises(ValueError, match="controller"):
        GetupTask("getup_front", controller="magic")
    with pytest.raises(ValueError, match="getup task"):
        GetupTask("getup_sideways")
    with pytest.raises(ValueError, match="fail_penalty"):
        GetupTask("getup_back", fail_penalty=-1.0)


def test_cli_runs_a_short_getup_job(tmp_path, capsys):
    out = tmp_path / "job"
    assert main(["optimize", "getup_front", "--option", "seconds=2", "--population", "4",
                 "--generations", "1", "--workers", "0", "--seed", "1", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert sum(ln.startswith("gen ") for ln in err.splitlines()) == 1
    best = (out / "best.txt").read_text()
    assert "front_k1_arm" in best and "back_k1_arm" not in best
    load_getup_skills([out / "best.txt"])  # the result is a getup parameter file

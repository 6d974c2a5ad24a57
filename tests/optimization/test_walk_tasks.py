"""Walk tasks in MuJoCo: phases, falls, determinism, and CMA-ES improving a short walk."""

import math

import numpy as np
import pytest

from optimization.executor import ExecutorFactory
from optimization.job import Job, JobSettings, Problem, trial_seed
from optimization.paramvec import ParamSpace, load_values
from optimization.phases import FALL_PENALTY, StopPhase, TrainerRecovery, WaypointPhase, new_sim, run_phases
from optimization.task import make_task, walk_sets


def sim(**kw):
    return new_sim(0, walk_sets(load_values(["go_to_target"], 0)), (-6.0, 0.0, 0.0),
                   np.random.default_rng(0), **kw)


def test_waypoint_reached_early_is_extrapolated_and_stop_penalizes_motion():
    s = sim()
    res = run_phases(s, [WaypointPhase(0.3, 0.0, 6.0), StopPhase(1.0)], TrainerRecovery())
    wp, stop = res
    assert wp.info["reached"] and not wp.fell and wp.seconds < 6.0
    assert wp.utility > 0.3 - 0.25  # gained at least start distance minus the reach radius ...
    assert wp.utility > 1.5 * (0.3 - 0.25)  # ... and extrapolated over the unused time
    assert -0.1 < stop.utility <= 0.0 and stop.seconds == pytest.approx(1.0)


class Topple:
    """A phase that knocks the robot over (trainer command) and then stands."""

    duration = 1.0

    def start(self, s):
        x, y, h = s.pose()
        s.world.place_robot(0, x, y, h, lying="front")

    def act(self, s, percept):
        return s.agent.walk(percept, 0.0, 0.0, 0.0)

    def after_step(self, s):
        pass

    def done(self, s):
        return False

    def utility(self, s, elapsed):
        return 0.0, {}


def test_a_fall_costs_the_penalty_and_the_robot_is_up_for_the_next_phase():
    s = sim()
    res = run_phases(s, [Topple(), StopPhase(0.5)], TrainerRecovery())
    assert res[0].fell and res[0].utility == -FALL_PENALTY and s.falls == 1
    assert not res[1].fell and not s.fallen()


def test_fall_penalty_option_is_what_a_fall_costs():
    s = sim()
    res = run_phases(s, [Topple(), StopPhase(0.5)], TrainerRecovery(), fall_penalty=15.0)
    assert res[0].fell and res[0].utility == -15.0
    heavy = make_task("go_to_target", fall_penalty=15.0)
    assert heavy.fall_penalty == 15.0 and heavy.worst == 3 * make_task("go_to_target").worst


def test_trials_are_deterministic_whatever_ran_before():
    task = make_task("walk_forward", seconds=0.6, stand=0.2)
    values = load_values(task.sets, 0)
    a = task.trial(values, 7).fitness
    task.trial(values, 8)
    assert task.trial(values, 7).fitness == a


def test_go_to_target_course_is_about_30_seconds_and_sprint_uses_both_sets():
    assert 28.0 <= make_task("go_to_target").seconds <= 32.0
    task = make_task("sprint", scale_time=0.1)
    r = task.trial(load_values(task.sets, 0), 1)
    assert math.isfinite(r.fitness) and set(r.info["set_cycles"]) <= {"go_to_target", "sprint"}
    assert r.info["set_cycles"].get("sprint", 0) > 0


def test_go_to_target_stress_phases_swing_the_turn_turn_in_place_and_step_back_and_aside():
    from optimization.phases import ZIGZAG_TURN, MovePhase
    from optimization.task import step_phases, turn_phases, zigzag_phases

    course = make_task("go_to_target")
    task = make_task("go_to_target", zigzag=4, turn=2, steps=2)
    added = task.phases[len(course.phases):]
    assert task.seconds == pytest.approx(course.seconds + 4.5 + 2.5 + 5.5)
    moves = [p for p in added if isinstance(p, MovePhase)]
    assert [m.turn for m in moves[:4]] == [ZIGZAG_TURN, -ZIGZAG_TURN, ZIGZAG_TURN, -ZIGZAG_TURN]
    with pytest.raises(ValueError, match="must not be negative"):
        make_task("go_to_target", turn=-1)
    # In physics, with type 1's shipped set: the zigzag goes forward, turning in place goes
    # nowhere, the steps go back and aside (each phase's utility: metres in its direction).
    # (Type 0's shipped set falls stepping right straight after stepping left.)
    s = new_sim(1, walk_sets(load_values(["go_to_target"], 1)), (-6.0, 0.0, 0.0), np.random.default_rng(0))
    res = run_phases(s, [*zigzag_phases(2), *turn_phases(2), *step_phases(2)], TrainerRecovery())
    assert s.falls == 0
    zig, turn, back, left, right = res[1:3], res[4:6], res[7], res[9], res[11]
    assert sum(r.utility for r in zig) > 0.3
    assert all(abs(r.utility) < 0.1 for r in turn)
    assert 0.1 < back.utility and 0.05 < left.utility and 0.05 < right.utility


def test_cmaes_improves_a_short_real_walk(tmp_path):
    task = make_task("walk_forward", seconds=1.5, stand=0.3)
    base = load_values(task.sets, 0)
    # The hand-tuned start, on the very trials (seeds) the job's three generations use.
    start = max(task.trial(base, trial_seed(2, g, 0)).fitness for g in range(3))
    space = ParamSpace.build(base, {"go_to_target": ("max_step_size_x", "pid_step_size_x", "phase_length",
                                                     "step_height", "fwd_offset")})
    r = Job(Problem(task, space, "short walk"), JobSettings(population=6, generations=3, sigma=1.5, seed=2),
            tmp_path, ExecutorFactory(workers=2), progress=None, plot=False).run()
    assert r.best_fitness > start + 0.02, (start, [h["best"] for h in r.history])
    assert r.best_values["go_to_target"] != base["go_to_target"]


def test_position_to_dribble_sees_the_ball_and_uses_the_dribble_set():
    task = make_task("position_to_dribble", seconds=3.0)
    values = load_values(task.sets, 0)
    r = task.trial(values, 3)
    assert math.isfinite(r.fitness) and r.fitness >= task.worst
    assert r.info["set_cycles"].get("position_to_dribble", 0) > 0  # it found the ball and came near
    assert task.trial(values, 3).fitness == r.fitness

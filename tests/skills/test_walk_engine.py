"""The walk engine's trajectories, step filter, inputs and parameter sets (no physics)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from skills.params import ParamError
from skills.walk import (
    BALANCE_STEP_IN,
    BALANCE_STEP_OUT,
    WALK_SETS,
    WalkEngine,
    WalkParams,
    default_param_files,
    direction_to_xy,
    load_walk_sets,
)


@pytest.fixture(scope="module")
def engine():
    return WalkEngine(0)


def test_shipped_sets_load_for_every_type():
    for t in range(5):
        sets = load_walk_sets(default_param_files(t))
        assert set(sets) == set(WALK_SETS)
        p = sets["go_to_target"]
        assert 0.01 < p.max_step_size_x < 0.2 and 0.05 < p.phase_length < 1.0
        assert 0.1 < p.walk_height < 0.3  # mm converted to m once, at load


def test_unknown_walk_parameter_names_its_line(tmp_path):
    f = tmp_path / "bad.txt"
    f.write_text("max_step_size_x\t60\nmax_step_sise_y\t40\n")
    with pytest.raises(ParamError, match=r"bad.txt:2:.*max_step_sise_y"):
        load_walk_sets([f])


def test_prefixed_set_overrides_only_its_names(tmp_path):
    f = tmp_path / "w.txt"
    f.write_text("max_step_size_x\t60\nsprint_max_step_size_x\t90\n")
    sets = load_walk_sets([f])
    assert sets["go_to_target"].max_step_size_x == pytest.approx(0.06)
    assert sets["sprint"].max_step_size_x == pytest.approx(0.09)
    assert sets["sprint"].phase_length == sets["go_to_target"].phase_length


@pytest.mark.parametrize("direction", np.linspace(-math.pi, math.pi, 25))
def test_direction_to_xy(direction):
    x, y = direction_to_xy(direction, 0.08, 0.04)
    assert max(abs(x), abs(y)) == pytest.approx(1.0)
    # The resulting velocity points where asked.
    assert math.atan2(y * 0.04, x * 0.08) == pytest.approx(direction, abs=1e-9) or \
        abs(abs(direction) - math.pi) < 1e-9


def test_step_filter_is_proportional_and_clamped():
    e = WalkEngine(0, {"go_to_target": WalkParams(pid_step_size_x=0.5, max_step_size_x=0.05)})
    e.update(1.0, 0.0, 0.0)
    assert e.step[0] == pytest.approx(0.025)
    for _ in range(50):
        e.update(5.0, 0.0, 0.0)  # inputs beyond 1 are clipped
    assert e.step[0] == pytest.approx(0.05)


def test_feet_move_continuously_and_never_cross(engine):
    """Leg targets change no faster across a swap of stance and swing feet (where the
    matched pendulum phases meet) than within a step."""
    e = engine
    e.reset()
    prev, swing = None, None
    at_swap, within = [], []
    for _ in range(200):
        out = e.update(0.8, 0.6, 0.3)
        feet = e.foot_targets()
        assert feet["l"][0][1] - feet["r"][0][1] > 0.08  # ankles stay apart
        legs = out.targets[np.r_[e.legs["l"], e.legs["r"]]]
        if prev is not None:
            (at_swap if e.swing != swing else within).append(np.abs(legs - prev).max())
        prev, swing = legs, e.swing
    assert not out.standing
    assert at_swap and max(at_swap) <= 1.2 * max(within)


def test_odometry_matches_steps_and_stops():
    e = WalkEngine(0, {"go_to_target": WalkParams(pid_step_size_x=1.0)})
    total = 0.0
    for _ in range(100):
        total += e.update(1.0, 0.0, 0.0).odometry[0]
    speed = total / 2.0
    p = e.params
    assert speed == pytest.approx(p.max_step_size_x / p.phase_length, rel=0.15)
    outs = [e.update(0.0, 0.0, 0.0) for _ in range(40)]
    assert not outs[10].standing and outs[-1].standing  # jogs in place 0.5 s, then stands
    assert outs[-1].odometry == (0.0, 0.0, 0.0)


def test_standing_odometry_counts_the_gyro_turn():
    # After a turn in place the torso can still turn while standing (feet left at
    # different yaws settle): the heading odometry keeps integrating the gyro then.
    e = WalkEngine(0)
    gyro = np.array([0.0, 0.0, 0.5])  # rad/s about the torso's z axis
    outs = [e.update(0.0, 0.0, 0.0, gyro=gyro) for _ in range(40)]
    assert outs[-1].standing
    assert outs[-1].odometry == pytest.approx((0.0, 0.0, 0.5 * e.dt))
    assert e.update(0.0, 0.0, 0.0).odometry == (0.0, 0.0, 0.0)  # no gyro: nothing to count


def test_forward_steps_add_pitch_damping_turning_in_place_does_not():
    # gyro_pitch_walk adds ankle pitch damping in proportion to the forward step;
    # the stance foot's pitch target shows it (no tilt, no swing offset on it).
    p = WalkParams(gyro_pitch=0.01, gyro_pitch_walk=0.02, pid_step_size_x=1.0, pid_step_size_rot=1.0,
                   pid_tilt=0.0)
    gyro = np.array([0.0, 1.0, 0.0])  # rad/s pitching
    for cmd, expected in (((1.0, 0.0, 0.0), 0.03), ((0.5, 0.0, 0.0), 0.02), ((0.0, 0.0, 1.0), 0.01)):
        e = WalkEngine(0, {"go_to_target": p})
        for _ in range(5):
            e.update(*cmd, gyro=gyro)
        stance = "r" if e.swing == "l" else "l"
        assert e.foot_targets()[stance][1][1] == pytest.approx(expected), cmd


def test_unknown_set_is_a_clear_error(engine):
    with pytest.raises(KeyError, match="unknown walk set"):
        engine.update(0, 0, 0, "moonwalk")


def _same(a, b) -> bool:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.mark.parametrize("robot_type, balance, back_still, slow_lift",
                         [(0, False, -1.0, -1.0), (4, False, -1.0, -1.0), (2, True, -1.0, -1.0),
                          (1, False, 0.05, 0.02)])
def test_compiled_walk_matches_the_python_reference_bit_for_bit(robot_type, balance, back_still, slow_lift):
    """The compiled cycle (`skills._kernels.walk_update`) against the plain Python engine
    it replaced: starts, stops, every direction, set changes, gyro and CoM feedback (and
    balance steps, an early backward swing and a lift growing with the step)."""
    from tests.skills.walk_reference import WalkEngineRef

    sets = load_walk_sets(default_param_files(robot_type))
    if balance:
        sets = {k: replace(p, balance_step_x=1.5, balance_step_y=0.8, balance_deadband=0.02, balance_fade=0.4)
                for k, p in sets.items()}
    sets = {k: replace(p, backward_fraction_still=back_still, slow_step_height=slow_lift)
            for k, p in sets.items()}
    e, ref = WalkEngine(robot_type, sets), WalkEngineRef(robot_type, sets)
    rng = np.random.default_rng(robot_type)
    sets = list(WALK_SETS)
    joints = None
    for i in range(700):
        if i == 350:
            e.reset()
            ref.reset()
        phase = (i // 60) % 6
        cmd = (0.0, 0.0, 0.0) if phase == 5 else tuple(rng.uniform(-1.3, 1.3, 3))
        kw = {"set_name": sets[(i // 90) % len(sets)], "tilt": float(rng.normal(0, 0.05)),
              "roll": float(rng.normal(0, 0.05))}
        if i % 7:
            kw["gyro"] = rng.normal(0, 0.5, 3)
        if joints is not None and i % 5:
            kw["joints"] = joints
        out, want = e.update(*cmd, **kw), ref.update(*cmd, **kw)
        assert _same(out.targets, want.targets), i
        assert out.odometry == tuple(float(v) for v in want.odometry) and out.standing == want.standing, i
        assert _same(e.expected_com, ref.expected_com) and _same(e.step, ref.step), i
        assert (e.swing, e.phi, e.phi_start, e.latched) == (ref.swing, ref.phi, ref.phi_start, ref.latched), i
        for standing in (False, True):
            got, exp = e.foot_targets(standing), ref.foot_targets(standing)
            assert list(got) == list(exp), i
            assert all(_same(got[s][k], exp[s][k]) for s in "lr" for k in (0, 1)), i
        joints = np.where(np.isnan(want.targets), 0.0, want.targets) + rng.normal(0, 0.06, len(want.targets))


def test_a_new_walk_set_takes_over_as_a_step_begins():
    """Mid-swing a change of set waits for the next step (changing mid-swing tripped
    the robot: the sprint course's falls, optimization.task.sprint)."""
    e = WalkEngine(0)
    for _ in range(30):
        e.update(1.0, 0.0, 0.0)
    while e.step_begins():  # into a step's swing
        e.update(1.0, 0.0, 0.0)
    gtt, sprint = e.sets["go_to_target"], e.sets["sprint"]
    assert e.walking and e.params is gtt
    cycles = 0
    while not e.step_begins():
        e.update(1.0, 0.0, 0.0, set_name="sprint")
        assert e.params is gtt
        cycles += 1
    assert cycles >= 1
    e.update(1.0, 0.0, 0.0, set_name="sprint")
    assert e.params is sprint
    e.reset()  # standing: at once
    e.update(0.0, 0.0, 0.0, set_name="go_to_target")
    assert e.params is gtt


def _swing_end(params: WalkParams, tilt: float, roll: float) -> dict[str, np.ndarray]:
    """Each foot's ankle target (m, torso frame) at the end of a swing of a forward walk
    whose torso leans by tilt and roll (rad) throughout; the swinging foot is first."""
    e = WalkEngine(0, {name: params for name in WALK_SETS})
    for _ in range(40):
        e.update(1.0, 0.0, 0.0, tilt=tilt, roll=roll)
    while not e.step_begins():
        e.update(1.0, 0.0, 0.0, tilt=tilt, roll=roll)
    while e.step_begins():
        e.update(1.0, 0.0, 0.0, tilt=tilt, roll=roll)
    while True:  # the last cycle of this swing
        feet = e.foot_targets()
        e.update(1.0, 0.0, 0.0, tilt=tilt, roll=roll)
        if e.step_begins():
            return {side: pos for side, (pos, _) in feet.items()}


def test_balance_steps_put_the_swing_foot_where_the_torso_leans():
    """Leaning back the swing foot lands behind where it would upright, leaning forward
    ahead; leaning sideways it steps out on the lean's side, little inward; within the
    deadband, and with zero gains, nothing changes. (A step's last cycle is just short of
    the swing's end: the offsets are within 15% of the full ones.)"""
    base = load_walk_sets(default_param_files(0))["go_to_target"]
    bal = replace(base, balance_step_x=0.5, balance_step_y=0.5, balance_deadband=0.03)
    upright = _swing_end(bal, 0.0, 0.0)
    assert all(np.allclose(upright[s], _swing_end(base, 0.0, 0.0)[s]) for s in "lr")
    assert all(np.allclose(upright[s], _swing_end(bal, 0.02, -0.02)[s]) for s in "lr")
    for tilt, roll in ((-0.13, 0.0), (0.13, 0.0), (0.0, 0.13), (0.0, -0.13), (0.0, 0.5)):
        leaning = _swing_end(bal, tilt, roll)
        swing = next(iter(leaning))
        dx, dy = leaning[swing][:2] - upright[swing][:2]
        assert np.allclose(leaning[swing][2], upright[swing][2])
        want = 0.5 * (tilt - math.copysign(0.03, tilt)) if tilt else 0.0
        assert dx == pytest.approx(want, rel=0.15, abs=1e-9)
        if roll:
            outward = dy if swing == "l" else -dy
            leans_out = (roll < 0) == (swing == "l")  # roll > 0: the torso leans right
            want = min(0.5 * (abs(roll) - 0.03), BALANCE_STEP_OUT if leans_out else BALANCE_STEP_IN)
            assert outward == pytest.approx(want if leans_out else -want, rel=0.15), (tilt, roll, swing)


def test_a_balance_step_carries_over_into_the_stance_without_a_jump():
    """The foot that stepped toward the lean keeps its offset as it lands, then the torso
    moves over it during the step: no foot target jumps more from one cycle to the next
    than without balance steps (a snap back of the 5 cm step would)."""
    base = load_walk_sets(default_param_files(0))["go_to_target"]

    def largest_jump(params: WalkParams) -> float:
        e = WalkEngine(0, {name: params for name in WALK_SETS})
        last, jump = None, 0.0
        for _ in range(150):
            e.update(1.0, 0.0, 0.0, tilt=-0.13, roll=0.13)
            feet = np.concatenate([e.foot_targets()[s][0] for s in "lr"])
            if last is not None:
                jump = max(jump, float(np.abs(feet - last).max()))
            last = feet
        return jump

    balanced = replace(base, balance_step_x=0.5, balance_step_y=0.5, balance_deadband=0.03)
    assert largest_jump(balanced) < largest_jump(base) + 0.01


def _peak_lift(params: WalkParams, x: float) -> float:
    """Highest swing ankle over a step of a walk at input x (m above the stance ankle)."""
    e = WalkEngine(0, {"go_to_target": params})
    for _ in range(300):  # the step size settles (pid_step_size_x 0.023 a cycle)
        e.update(x, 0.0, 0.0)
    lift = 0.0
    for _ in range(12):
        e.update(x, 0.0, 0.0)
        feet = e.foot_targets()
        stance = "r" if e.swing == "l" else "l"
        lift = max(lift, float(feet[e.swing][0][2] - feet[stance][0][2]))
    return lift


def test_a_slow_lift_grows_with_the_step():
    base = load_walk_sets(default_param_files(0))["go_to_target"]
    slow = replace(base, slow_step_height=0.5 * base.step_height)
    # in place half the lift (the sampled peak of the cosine is the same share of either height)
    assert _peak_lift(slow, 0.0001) == pytest.approx(0.5 * _peak_lift(base, 0.0001), rel=0.01)
    assert _peak_lift(slow, 1.0) == pytest.approx(_peak_lift(base, 1.0), rel=0.01)  # a full step
    assert 0.6 < _peak_lift(slow, 0.5) / _peak_lift(base, 0.5) < 0.9
    # backward steps count against their own bound (backward_factor of the forward one)
    assert _peak_lift(slow, -1.0) == pytest.approx(_peak_lift(base, -1.0), rel=0.01)

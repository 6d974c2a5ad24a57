"""The torso tilt estimate (skills/imu.py)."""

import math

import numpy as np
import pytest

from skills.imu import GRAVITY, TiltEstimator
from tests.skills.imu_traces import LANDING, WALK_A, WALK_B


def _roll_over(est: TiltEstimator, rate: float, seconds: float, dt: float = 0.02) -> list[float]:
    """Roll the torso about its x axis at `rate` rad/s from upright; the estimate's roll each cycle."""
    rolls = []
    for k in range(int(round(seconds / dt)) + 1):
        r = rate * k * dt
        est.update(np.array([rate, 0.0, 0.0]), GRAVITY * np.array([0.0, math.sin(r), math.cos(r)]), dt)
        rolls.append(est.roll)
    return rolls


def test_roll_stays_wrapped_after_a_full_roll_over():
    # A robot rolling over on the ground passes roll = pi; back upright, the estimate
    # must read about 0, not 2 pi (which the fall check took for a lean).
    est = TiltEstimator()
    rolls = _roll_over(est, 1.0, 2.0 * math.pi)
    assert max(abs(r) for r in rolls) <= math.pi + 1e-9
    for _ in range(100):  # upright and still: it settles at 0
        est.update(np.zeros(3), np.array([0.0, 0.0, GRAVITY]), 0.02)
    assert abs(est.roll) < math.radians(1.0)


def test_roll_follows_a_lean():
    est = TiltEstimator()
    _roll_over(est, 0.5, 1.0)
    for _ in range(100):  # held at 0.5 rad
        est.update(np.zeros(3), GRAVITY * np.array([0.0, math.sin(0.5), math.cos(0.5)]), 0.02)
    assert abs(est.roll - 0.5) < math.radians(1.0)


def test_foot_strikes_while_walking_are_not_a_fall():
    # Recorded on an upright walking robot: the smoothed accelerometer alone passed the
    # fall angle (the robot froze mid-step and toppled); the fused tilt says upright.
    for accel, gyro in (WALK_A, WALK_B):
        est = TiltEstimator()
        est.update(np.zeros(3), np.array([0.0, 0.0, GRAVITY]), 0.02)
        for a, g in zip(accel * 2, gyro * 2):
            est.update(np.array(g), np.array(a), 0.02)
            assert not est.fallen
            assert est.fused_tilt < math.radians(30.0)


def test_a_real_fall_is_seen():
    est = TiltEstimator()
    _roll_over(est, 2.0, 0.8)  # to 92 deg in 0.8 s
    lying = GRAVITY * np.array([0.0, 1.0, 0.0])
    seen = []
    for _ in range(25):  # lying on its side, still
        est.update(np.zeros(3), lying, 0.02)
        seen.append(est.fallen)
    assert seen.index(True) < 10 and all(seen[10:])


def test_the_landing_after_a_beam_does_not_tip_the_estimate():
    # Recorded just after a beam (free fall, then landing jolts; the torso within 2 deg of
    # vertical): started from its first reading, the estimate read the roll as -90 deg.
    est = TiltEstimator()
    for a, g in zip(*LANDING):
        est.update(np.array(g), np.array(a), 0.02)
        assert est.fused_tilt < math.radians(10.0) and not est.fallen


def test_turning_while_leaning_forward_does_not_read_as_a_roll():
    # Torso pitched 0.3 rad forward and turning about the vertical at 2 rad/s: the gyro
    # reads the turn partly on its x axis. Taken as a roll rate (small angles), the
    # estimate leaned about 13 deg sideways against the accelerometer's pull; `exact`
    # turns the estimate by the whole gyro.
    pitch, rate = 0.3, 2.0
    gyro = rate * np.array([-math.sin(pitch), 0.0, math.cos(pitch)])
    accel = GRAVITY * np.array([-math.sin(pitch), 0.0, math.cos(pitch)])
    for exact, off in ((False, True), (True, False)):
        est = TiltEstimator(exact=exact)
        for _ in range(200):
            est.update(gyro, accel, 0.02)
        assert (abs(est.roll) > math.radians(10.0)) == off
        if exact:
            assert abs(est.roll) < math.radians(1.0) and abs(est.pitch - pitch) < math.radians(1.0)


def _check_same(est: TiltEstimator, ref, gyro, accel, dt: float = 0.02) -> None:
    try:
        ref.update(gyro, accel, dt)
    except ValueError:
        with pytest.raises(ValueError, match="math domain error"):
            est.update(gyro, accel, dt)
    else:
        est.update(gyro, accel, dt)
    assert (est.roll, est.pitch, est._a) == (ref.roll, ref.pitch, ref._a) or \
        np.array_equal([est.roll, est.pitch, *est._a], [ref.roll, ref.pitch, *ref._a], equal_nan=True)


@pytest.mark.parametrize("exact", [False, True])
@pytest.mark.parametrize("from_first", [False, True])
def test_compiled_update_matches_the_python_reference_bit_for_bit(exact, from_first):
    """`skills._kernels.tilt_update` against the Python update it replaced: walking traces,
    a landing, roll-overs past pi, fast turns, non-finite readings."""
    from tests.skills.imu_reference import TiltEstimatorRef

    kw = {"blend": 0.05 if exact else 0.01, "exact": exact, "from_first": from_first}
    est, ref = TiltEstimator(**kw), TiltEstimatorRef(**kw)
    for accel, gyro in (WALK_A, WALK_B):
        for a, g in zip(accel, gyro):
            _check_same(est, ref, np.array(g), np.array(a))
    for a, g in zip(*LANDING):
        _check_same(est, ref, np.array(g), np.array(a))
    rng = np.random.default_rng(1)
    for k in range(2000):
        r = 0.01 * k
        accel = GRAVITY * np.array([math.sin(0.3 * r), math.sin(r), math.cos(r)]) + rng.normal(0, 3, 3)
        _check_same(est, ref, rng.normal(0, 4, 3), accel)
    for gyro, accel in (([0, 0, 0], [np.nan, 0, 9.8]), ([0, 0, 0], [np.inf, 0, 9.8]),
                        ([np.nan, 0, 0], [0, 0, 9.8]), ([0, 0, 0], [0, 0, 9.8]),
                        ([0, np.inf, 0], [0, 0, 9.8]), ([np.inf, 0, 0], [0, 0, 9.8])):
        _check_same(est, ref, np.array(gyro, dtype=float), np.array(accel, dtype=float))


def test_remainder_is_python_s():
    from skills._kernels import py_remainder

    rng = np.random.default_rng(2)
    halves = np.arange(-9, 10) * math.pi  # halfway cases: the even multiple
    for x in np.concatenate([rng.uniform(-20, 20, 20000), halves, [0.0, -0.0, 1e300, 5e-324]]):
        got, want = py_remainder(float(x), 2 * math.pi), math.remainder(float(x), 2 * math.pi)
        assert np.float64(got).tobytes() == np.float64(want).tobytes(), x

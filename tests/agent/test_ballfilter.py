"""The ball Kalman filter, alone and on a trainer-rolled ball seen by a standing robot."""

from __future__ import annotations

import math

import numpy as np
import pytest
from filterpy.kalman import KalmanFilter

from agent.ballfilter import ROLLING_DECELERATION, ROLLING_DRAG, BallFilter, _nis, rolling_distance

from .helpers import perceiving_match, place_standing, run


def test_tracks_a_synthetic_rolling_ball():
    rng = np.random.default_rng(0)
    f = BallFilter()
    p, v = np.array([0.0, 0.0]), np.array([2.0, -1.0])
    dt = 0.02


    def roll(p, v, dt):  # the motion model, integrated in 1 ms steps
        for _ in range(round(dt / 0.001)):
            speed = np.hypot(*v)
            if speed < 1e-4:
                return p, 0 * v
            v = v - (ROLLING_DRAG * v + ROLLING_DECELERATION * v / speed) * 0.001
            p = p + v * 0.001
        return p, v

    for k in range(100):
        p, v = roll(p, v, dt)
        f.predict(dt)
        if k % 3 == 0:
            f.update(p + rng.normal(0, 0.03, 2), 0.03, k * dt)
    np.testing.assert_allclose(f.velocity, v, rtol=0.1, atol=0.05)
    rest, _ = roll(p, v, 60.0)
    assert np.hypot(*(f.stop_position() - rest)) < 0.3


def test_a_far_measurement_resets():
    f = BallFilter()
    f.update(np.array([1.0, 1.0]), 0.05, 0.0)
    for _ in range(10):
        f.predict(0.02)
        f.update(np.array([1.0, 1.0]), 0.05, 0.0)
    f.update(np.array([5.0, -3.0]), 0.05, 0.2)
    np.testing.assert_allclose(f.position, [5.0, -3.0], atol=1e-6)


def _filterpy_twin(f: BallFilter, dt: float) -> KalmanFilter:
    """A filterpy KalmanFilter in f's state with the motion model's F, B, Q for dt."""
    kf = KalmanFilter(dim_x=4, dim_z=2)
    kf.H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    kf.x, kf.P = f.x.copy(), f.P.copy()
    decay = math.exp(-f.drag * dt)
    reach = (1.0 - decay) / f.drag
    kf.F = np.array([[1.0, 0.0, reach, 0.0], [0.0, 1.0, 0.0, reach],
                     [0.0, 0.0, decay, 0.0], [0.0, 0.0, 0.0, decay]])
    kf.B = np.array([[0.5 * dt * dt, 0.0], [0.0, 0.5 * dt * dt], [dt, 0.0], [0.0, dt]])
    g = np.array([0.5 * dt * dt, dt])
    qb = np.outer(g, g) * f.sigma_accel ** 2
    kf.Q = np.array([[qb[0, 0], 0, qb[0, 1], 0], [0, qb[0, 0], 0, qb[0, 1]],
                     [qb[1, 0], 0, qb[1, 1], 0], [0, qb[1, 0], 0, qb[1, 1]]])
    return kf


def test_equals_filterpy():
    """The compiled predict and update give filterpy's floats (numpy's BLAS and LAPACK
    products) to rounding, on random states, including covariances whose LU pivots.
    (Bit for bit on the numpy they were written against; a later numpy's BLAS may
    differ in the last bit.)"""
    rng = np.random.default_rng(3)
    for k in range(300):
        f = BallFilter()
        a = rng.normal(size=(4, 4)) * rng.choice([0.01, 0.3, 3.0])
        f.P[:] = a @ a.T + np.diag(rng.random(4)) * 1e-3
        if k % 3 == 0:  # |P01| > |P00|: the 2x2 LU swaps its rows
            f.P[0, 1] = f.P[1, 0] = 1.5 * f.P[0, 0]
        f.x[:] = rng.normal(size=4) * (rng.random() < 0.9)
        dt = float(rng.choice([0.02, 0.020000000000000018, 0.04]))
        kf = _filterpy_twin(f, dt)
        v = f.x[2:4]
        speed = float(np.hypot(*v))
        if speed * math.exp(-f.drag * dt) > f.deceleration * dt:
            u = -f.deceleration * v / speed
        else:
            u = -v * math.exp(-f.drag * dt) / dt
        kf.predict(u=u)
        f.predict(dt)
        np.testing.assert_allclose(f.x, kf.x, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(f.P, kf.P, rtol=1e-12, atol=1e-15)
        z, sigma = f.x[:2] + rng.normal(size=2) * 0.05, 0.05
        r = np.eye(2) * sigma ** 2
        innov = z - kf.x[:2]
        nis = float(innov @ np.linalg.solve(kf.P[:2, :2] + r, innov))
        kf.update(z, R=r)
        f.initialized = True
        f.gate = f.maneuver = math.inf
        f.update(z, sigma, 0.0)
        np.testing.assert_allclose(f.x, kf.x, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(f.P, kf.P, rtol=1e-12, atol=1e-15)
        assert math.isclose(_nis(kf.x_prior, kf.P_prior, z, sigma ** 2), nis, rel_tol=1e-12)


def test_velocity_of_a_trainer_rolled_ball_within_20_percent():
    m = perceiving_match(left=(0,), right=(0,), seed=7)
    w = m.world
    place_standing(m, 0, -6.0, 0.0, 0.0)  # the goalie (unum 1) keeps its eyes on the ball
    place_standing(m, 1, 8.0, 8.0, 0.0)
    w.place_ball((-4.0, -1.5))
    run(m, 3.0)  # time to find itself after the trainer's move and to find the ball
    assert np.hypot(*(m.agents[0].world.ball_filter.position - w.ball_position()[:2])) < 0.1
    w.set_ball_velocity((0.6, 1.5, 0.0))
    run(m, 0.2)  # three vision frames to notice the kick
    errors = []
    seen = []
    for _ in range(10):
        for _ in range(5):
            m.step()
            if m.cycle % 3 == 1:  # just after a vision frame
                seen.append(m.agents[0].world.ball.currently_seen)
        est = m.agents[0].world.ball_filter.velocity
        true = w.ball_velocity()[:2]
        errors.append(np.hypot(*(est - true)) / np.hypot(*true))
    assert max(errors) < 0.2, errors
    assert all(seen)  # the goalie keeps the rolling ball in view
    stop = m.agents[0].world.ball_filter.stop_position()
    run(m, 4.0)
    assert np.hypot(*(stop - w.ball_position()[:2])) < 0.5


@pytest.mark.parametrize("speed", [0.8, 4.0])
def test_the_motion_model_matches_the_simulated_ball(speed):
    """The ball's motion model (drag and rolling friction, the agents' prior and the
    trials' extrapolation) against the MuJoCo ball rolled by the trainer: where it stops."""
    from models.scene import Lineup
    from server.world import World

    w = World(Lineup((0,), ()))
    w.place_ball((-10.0, 0.0))
    w.set_ball_velocity((speed, 0.0, 0.0))
    ctrl = np.zeros(w.model.nu)
    t, predicted = 0.0, None
    while np.hypot(*w.ball_velocity()[:2]) > 0.01 and t < 30.0:
        w.step(ctrl)
        t += 0.02
        if predicted is None and t >= 0.5:  # the trials' truth-side extrapolation, mid-roll
            predicted = w.ball_rest_position()
    travelled = w.ball_position()[0] + 10.0
    assert predicted[0] + 10.0 == pytest.approx(travelled, rel=0.1)
    assert abs(w.ball_position()[1]) < 0.01
    assert travelled == pytest.approx(rolling_distance(speed), rel=0.1)
    f = BallFilter()
    f.reset(np.zeros(2), 0.01, velocity=np.array([speed, 0.0]))
    assert f.stop_position()[0] == pytest.approx(travelled, rel=0.1)

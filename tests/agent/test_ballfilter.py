"""The ball Kalman filter, alone and on a trainer-rolled ball seen by a standing robot."""

from __future__ import annotations

import numpy as np

from agent.ballfilter import ROLLING_DECELERATION, BallFilter

from .helpers import perceiving_match, place_standing, run


def test_tracks_a_synthetic_rolling_ball():
    rng = np.random.default_rng(0)
    f = BallFilter()
    p, v = np.array([0.0, 0.0]), np.array([2.0, -1.0])
    dt = 0.02
    for k in range(100):
        speed = np.hypot(*v)
        v = v - ROLLING_DECELERATION * dt * v / speed
        p = p + v * dt
        f.predict(dt)
        if k % 3 == 0:
            f.update(p + rng.normal(0, 0.03, 2), 0.03, k * dt)
    np.testing.assert_allclose(f.velocity, v, rtol=0.1, atol=0.05)
    stop = p + v * np.hypot(*v) / (2 * ROLLING_DECELERATION)
    assert np.hypot(*(f.stop_position() - stop)) < 0.3


def test_a_far_measurement_resets():
    f = BallFilter()
    f.update(np.array([1.0, 1.0]), 0.05, 0.0)
    for _ in range(10):
        f.predict(0.02)
        f.update(np.array([1.0, 1.0]), 0.05, 0.0)
    f.update(np.array([5.0, -3.0]), 0.05, 0.2)
    np.testing.assert_allclose(f.position, [5.0, -3.0], atol=1e-6)


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

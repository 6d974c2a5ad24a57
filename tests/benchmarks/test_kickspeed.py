"""The swing probe: launch speeds invert the ball's roll, and the foot speed the probe
reads from the joints agrees with the foot's own and stays under the bounds."""

import numpy as np
import pytest

from benchmarks.kickspeed import SwingProbe, launch_speed_for, main
from models.field import rolling_distance
from optimization.kick import kick_trial
from skills.kicks import all_kicks


@pytest.mark.parametrize("distance", [1.0, 5.0, 15.0])
def test_the_launch_speed_rolls_the_ball_that_far(distance):
    v = launch_speed_for(distance)
    assert rolling_distance(v) == pytest.approx(distance, rel=1e-6)
    assert launch_speed_for(distance + 1.0) > v


def test_a_kick_is_measured_and_its_foot_speed_is_under_the_bounds():
    probe = SwingProbe("lfoot")
    r = kick_trial(0, all_kicks(0)["kick_left"], "standing", np.random.default_rng(2), 2, observe=probe)
    assert r["kicked"] and r["toward"] > 2.0, r
    res = probe.result
    assert res is not None
    # the support foot barely moves: the joints' contribution is the foot's speed
    assert res["from_joints"] == pytest.approx(res["speed_before"], rel=0.2, abs=0.1)
    assert 0.5 < max(res["speed_before"], res["speed_after"]) < res["bound_leg"] < res["bound_legs"]
    assert res["launch_speed"] > 1.0  # the ball leaves faster than the kick's 0.5 m/s trigger
    assert rolling_distance(res["launch_speed"]) == pytest.approx(r["distance"], rel=0.5)


def test_bad_options_are_refused(capsys):
    with pytest.raises(SystemExit) as e:
        main(["--kicks", "bicycle_left"])
    assert e.value.code == 2 and "unknown kick 'bicycle_left'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["--far", "-3"])

"""benchmarks.walklimits: steps, speeds and joint limits of a straight walk, measured."""

from __future__ import annotations

import math

import pytest

from benchmarks import walklimits


def test_a_straight_walk_is_measured_against_its_plan_and_its_joints():
    r = walklimits.walk_limits(0, "go_to_target", seconds=3.0)
    assert not r["fell"]
    # a step lasts a whole number of 20 ms cycles
    cycles = math.ceil(r["phase_length_s"] / 0.02 - 1e-9)
    assert r["steps_per_s"] == pytest.approx(1.0 / (0.02 * cycles), abs=0.4)
    assert r["step_length_m"] == pytest.approx(r["speed_m_s"] / r["steps_per_s"], rel=0.15)
    assert 0.15 < r["speed_m_s"] < 0.6 and 0.1 < r["planned_m_s"] <= r["bound_m_s"] + 1e-9
    j = r["joints"]
    assert set(j) == set(walklimits.LEG)
    # the swing's knee is driven hard; the hip roll never reaches its cap walking straight
    assert j["lj4"]["at_speed_cap"] > 0.05 and j["lj4"]["peak_rad_s"] > 3.0
    assert j["lj2"]["at_speed_cap"] == 0.0
    assert 0.0 <= r["double_support"] + r["flight"] <= 1.0
    assert 0.0 < r["stance_slip_m_per_step"] < 0.5 * r["step_length_m"]


def test_cli_rejects_bad_types(capsys):
    with pytest.raises(SystemExit):
        walklimits.main(["--types", "7"])
    assert "robot types are 0-4" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        walklimits.main(["--cap-scale", "0"])
    assert "must be positive" in capsys.readouterr().err


def test_a_higher_speed_cap_is_measured_against_the_raised_cap():
    base = walklimits.walk_limits(0, "go_to_target", seconds=2.0)
    fast = walklimits.walk_limits(0, "go_to_target", seconds=2.0, cap_scale=1.5)
    assert fast["cap_scale"] == 1.5
    # the knee reaches speeds the league's cap forbids, and sits at the raised cap less
    assert fast["joints"]["lj4"]["peak_rad_s"] > 1.05 * base["joints"]["lj4"]["peak_rad_s"]
    assert base["joints"]["lj4"]["peak_rad_s"] < 6.14 * 1.15
    assert fast["joints"]["lj4"]["at_speed_cap"] < base["joints"]["lj4"]["at_speed_cap"]


def test_an_early_backward_swing_walks_backward_faster(tmp_path):
    """Lowering the foot and swinging it back both extend the hip: a backward swing late in
    the step meets the speed cap and lands short; one begun at once does not."""
    early, late_file = tmp_path / "early.txt", tmp_path / "late.txt"
    early.write_text("backward_fraction_still\t0\n")
    late_file.write_text("backward_fraction_still\t-1\n")  # as fraction_still
    late, soon = (walklimits.walk_limits(0, "go_to_target", seconds=3.0, direction="backward",
                                         params=[str(f)]) for f in (late_file, early))
    assert not late["fell"] and not soon["fell"]
    assert late["direction"] == "backward" and late["step_bound_m"] < late["max_step_size_x_m"]
    assert 0.05 < late["speed_m_s"] and soon["speed_m_s"] > 1.5 * late["speed_m_s"]


def test_a_partial_input_plans_a_proportional_step_and_measures_along_the_direction():
    full = walklimits.walk_limits(0, "go_to_target", seconds=3.0)
    part = walklimits.walk_limits(0, "go_to_target", seconds=3.0, amount=0.3)
    assert part["input"] == 0.3 and not part["fell"]
    assert 0.2 * full["planned_m_s"] < part["planned_m_s"] < 0.4 * full["planned_m_s"]
    assert part["bound_m_s"] == full["bound_m_s"]

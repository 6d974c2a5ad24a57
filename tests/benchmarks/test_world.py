"""The world benchmark: its windows add up to the whole run, and bad options are refused."""

import json
import sys

import pytest

from benchmarks import world


def run(monkeypatch, capsys, *argv):
    monkeypatch.setattr(sys, "argv", ["world", *argv])
    world.main()
    return json.loads(capsys.readouterr().out)


def test_repeated_windows_are_reported_with_their_median_and_best(monkeypatch, capsys):
    r = run(monkeypatch, capsys, "--seconds", "0.2", "--repeats", "3")
    assert r["sim_seconds"] == pytest.approx(0.6)
    w = r["windows_physics_plus_server_factor"]
    assert len(w) == 3 and all(f > 0 for f in w)
    assert r["best_window"] == max(w) and min(w) <= r["median_window"] <= max(w)
    # The whole run's factor lies between its slowest and fastest window (rounding aside).
    assert min(w) - 0.02 <= r["physics_plus_server_factor"] <= max(w) + 0.02
    s = r["seconds"]
    assert r["physics_factor"] == pytest.approx(0.6 / s["physics"], rel=0.1)  # seconds are rounded to ms


@pytest.mark.parametrize("argv", [["--repeats", "0"], ["--seconds", "0"], ["--seconds", "x"]])
def test_bad_options_exit_with_status_2(monkeypatch, capsys, argv):
    monkeypatch.setattr(sys, "argv", ["world", *argv])
    with pytest.raises(SystemExit) as exc:
        world.main()
    assert exc.value.code == 2
    assert "error" in capsys.readouterr().err


def test_teams_and_stage_table(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["world", "--seconds", "0.2", "--home", "villa", "--players", "1",
                                      "--stages", "--clock", "cpu"])
    world.main()
    lines = [json.loads(s) for s in capsys.readouterr().out.splitlines()]
    assert [r["benchmark"] for r in lines] == ["world", "world_agent_stages"]
    assert lines[0]["teams"] == {"L": "villa", "R": "posture"} and lines[0]["players"] == 2
    villa = lines[1]["us_per_agent_cycle"]["L"]
    assert villa["agent"] > 0 and {"world_model", "particle_filter", "body", "walk_step"} <= set(villa)
    assert villa["world_model"] <= villa["agent"] * 1.05  # inclusive, within the agent's cycle
    assert "world_model" not in lines[1]["us_per_agent_cycle"]["R"]  # posture has none


def test_unknown_team_exits_with_status_2(monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["world", "--home", "nobody"])
    with pytest.raises(SystemExit) as exc:
        world.main()
    assert exc.value.code == 2 and "unknown team" in capsys.readouterr().err

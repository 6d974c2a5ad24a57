"""benchmarks.agents: a match's percepts replayed into fresh agents give the match's actions."""

from __future__ import annotations

import json

import pytest

from benchmarks import agents


def test_replayed_agents_act_as_in_the_match():
    made, percepts, kickoff, played = agents.record("villa", "villa", 0.6, seed=2)
    assert len(made) == 22 and {m[0] for m in made} == {"L", "R"}
    assert len({m[3] for m in made}) == 22  # each agent its own seed
    cost, replayed = agents.replay("villa", "villa", made, percepts, kickoff)
    assert cost.shape == (30, 22) and (cost > 0).all()
    assert replayed == played  # each agent is a function of its seed and its percepts
    # Made with other seeds, the agents act otherwise: the hash sees their actions.
    other = [(s, u, t, seed + 1) for s, u, t, seed in made]
    assert agents.replay("villa", "villa", other, percepts, kickoff)[1] != played


def test_cli_prints_the_figures(capsys):
    assert agents.main(["--seconds", "0.2", "--repeats", "1", "--away", "posture"]) == 0
    row = json.loads(capsys.readouterr().out)
    assert row["cycles"] == 10 and row["agents"] == 22
    assert row["by_team"]["L"]["team"] == "villa" and row["by_team"]["R"]["team"] == "posture"
    u = row["us_per_agent_cycle"]
    assert 0 < u["median"] <= u["p99"]


def test_cli_errors(capsys):
    with pytest.raises(SystemExit):
        agents.main(["--home", "nobody"])
    assert "nobody" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        agents.main(["--seconds", "0"])
    assert "--seconds must be > 0" in capsys.readouterr().err

"""benchmarks.ablation: rounds that keep every variant level, resume, one pool, the table."""

from __future__ import annotations

import json

import pytest

from benchmarks import ablation
from optimization.executor import InlineExecutor

TINY = dict(half_time=0.2, size=1, seed=5, workers=0)


def _games(path):
    return [json.loads(line) for line in path.read_text().splitlines()]


def test_rounds_keep_variants_level_and_one_pool_serves_them(tmp_path):
    made = []

    def factory():
        made.append(InlineExecutor())
        return made[-1]

    rows = ablation.run(["Static", "NoVoting"], 3, out=tmp_path, per_round=2, progress=None,
                        factory=factory, **TINY)
    assert len(made) == 1
    assert [r["variant"] for r in rows] == ["Static", "NoVoting"]
    assert [r["n"] for r in rows] == [3, 3]
    for name in ("Static", "NoVoting"):
        games = _games(tmp_path / name / "games.jsonl")
        # played round by round: 0 and 1 (one from each side), then 2
        assert [g["game"] for g in games] == [0, 1, 2]
        assert [g["a_side"] for g in games] == ["L", "R", "L"]
        assert [g["seed"] for g in games] == [5, 6, 7]
    written = [json.loads(line) for line in (tmp_path / "ablation.jsonl").read_text().splitlines()]
    assert written == rows
    assert (tmp_path / "ablation.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    md = (tmp_path / "table.md").read_text()
    assert "| Static | 3 |" in md and "| NoVoting | 3 |" in md and "-0.19 (0.07)" in md


def test_resume_plays_only_the_missing_games(tmp_path):
    first = ablation.run(["Static"], 2, out=tmp_path, progress=None, **TINY)
    before = _games(tmp_path / "Static" / "games.jsonl")
    with pytest.raises(ablation.BatchError):  # a second run into the same place must say --resume
        ablation.run(["Static"], 2, out=tmp_path, progress=None, **TINY)
    rows = ablation.run(["Static"], 4, out=tmp_path, resume=True, progress=None, **TINY)
    after = _games(tmp_path / "Static" / "games.jsonl")
    assert after[:2] == before and [g["game"] for g in after] == [0, 1, 2, 3]
    assert first[0]["n"] == 2 and rows[0]["n"] == 4


def test_rank_agreement_is_spearman_over_the_papers_variants():
    def row(name, mean):
        return {"variant": name, "mean": mean}

    same = [row(n, m) for n, (m, _) in ablation.PAPER_TABLE2.items()] + [row("DribbleOnly", 5.0)]
    assert ablation.rank_agreement(same)["spearman_rho"] == 1.0
    assert ablation.rank_agreement(same)["variants"] == len(ablation.PAPER_TABLE2)
    reversed_ = [row(n, -m) for n, (m, _) in ablation.PAPER_TABLE2.items()]
    assert ablation.rank_agreement(reversed_)["spearman_rho"] == -1.0
    assert ablation.rank_agreement(same[:2]) is None
    # with no standard error a redraw changes nothing; with a large one rho could be anything
    assert ablation.rank_agreement(same)["rho_95"] == [1.0, 1.0]
    noisy = [dict(r, se=10.0) for r in same]
    low, high = ablation.rank_agreement(noisy)["rho_95"]
    assert low < 0 < high


def test_table_file_gives_the_rank_correlation_with_the_paper(tmp_path):
    rows = [{"variant": n, "n": 1, "mean": -m, "se": 0.0, "wins": 0, "draws": 1, "losses": 0}
            for n, (m, _) in ablation.PAPER_TABLE2.items()]
    ablation.write_outputs(tmp_path, rows, "head")
    md = (tmp_path / "table.md").read_text()
    assert md.startswith("head\n") and md.rstrip().endswith(
        f"over {len(rows)} variants: rho -1.0, p 0.0 (95% interval -1.0 .. -1.0 over our means "
        "redrawn from their standard errors)")
    ablation.write_outputs(tmp_path, rows[:2], "head")  # too few to rank: no line
    assert "Spearman" not in (tmp_path / "table.md").read_text()


def test_cli_errors(capsys):
    assert ablation.main(["--variants", "Nope"]) == 2
    assert "unknown villa variant 'Nope'" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        ablation.main(["--resume"])
    assert "--resume and --report need the --out" in capsys.readouterr().err


def test_report_tabulates_every_game_in_a_stopped_run(tmp_path, capsys):
    ablation.run(["Static"], 3, out=tmp_path, per_round=2, progress=None, **TINY)
    ablation.run(["NoVoting"], 1, out=tmp_path, progress=None, **TINY)
    assert ablation.main(["--out", str(tmp_path), "--report"]) == 0
    assert "| Static | 3 |" in capsys.readouterr().out
    rows = [json.loads(line) for line in (tmp_path / "ablation.jsonl").read_text().splitlines()]
    # every variant with games, in the table's order, each with its own count
    assert [(r["variant"], r["n"], r["half_time"], r["size"]) for r in rows] == [
        ("Static", 3, 0.2, 1), ("NoVoting", 1, 0.2, 1)]
    assert ablation.main(["--out", str(tmp_path / "none"), "--report"]) == 2

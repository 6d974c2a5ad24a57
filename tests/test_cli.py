"""The soccer command: results, files, and one-line errors with exit code 2."""

import json
import subprocess
import sys

import mujoco
import pytest

from cli.main import main


def soccer(*args):
    return subprocess.run([sys.executable, "-m", "cli.main", *args], capture_output=True, text=True)


def test_short_match_writes_result_and_log(tmp_path):
    out, log = tmp_path / "r.json", tmp_path / "m.npz"
    assert main(["match", "--half-time", "0.5", "--home-size", "2", "--away-size", "1", "--quiet",
                 "--out", str(out), "--log", str(log)]) == 0
    r = json.loads(out.read_text())
    assert set(r["score"]) == {"L", "R"}
    assert r["game_time"] == pytest.approx(1.0, abs=0.03)
    assert {"possession_time", "ball_touches", "falls"} <= set(r["stats"]["L"])
    kinds = {e["kind"] for e in r["events"]}
    assert {"play_mode", "half_time", "game_over"} <= kinds
    assert log.stat().st_size > 1000


def test_model_and_scene_are_loadable(tmp_path):
    assert main(["model", "--type", "4", "--out", str(tmp_path / "r.xml")]) == 0
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "r.xml"))
    assert m.nu == 24
    assert main(["scene", "--home-types", "0,1,2", "--away", "2", "--out", str(tmp_path / "s.xml")]) == 0
    m = mujoco.MjModel.from_xml_path(str(tmp_path / "s.xml"))
    assert m.body("L3/torso") and m.body("R2/torso")


@pytest.mark.parametrize("args,needle", [
    (["model", "--type", "7", "--out", "x.xml"], "robot type must be 0, 1, 2, 3 or 4"),
    (["match", "--home", "nobody"], "unknown team 'nobody'"),
    (["match", "--home-size", "12"], "team size must be 1 to 11"),
    (["match", "--half-time", "-3"], "must be positive"),
    (["scene", "--home-types", "0,9", "--out", "x.xml"], "robot type must be"),
    (["match", "--seed", "abc"], "seed must be a whole number"),
])
def test_bad_input_one_line_exit_2(args, needle):
    proc = soccer(*args)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.mark.parametrize("args,needle", [
    (["match", "--half-time", "inf", "--quiet"], "finite number"),
    (["match", "--half-time", "nan"], "finite number"),
    (["match", "--half-time", "1e9"], "at most 3600"),
    (["match", "--seed", "-1"], "seed must be 0 to"),
    (["match", "--home", "nowhere.at_all:team"], "no module named 'nowhere'"),
    (["batch", "--games", "0", "--out", "x"], "games must be 1 to"),
    (["batch", "--games", "2", "--half-time", "inf", "--out", "x"], "finite number"),
    (["batch", "--games", "2", "--workers", "-1", "--out", "x"], "workers must be"),
    (["batch", "--games", "2", "--home", "nobody", "--out", "x"], "unknown team 'nobody'"),
    (["batch", "--games", "2", "--away", "tests.batch_teams:missing", "--out", "x"], "has no 'missing'"),
    (["batch", "--games", "2", "--home", "tests.batch_teams:all_toes", "--out", "x"], "1 robot types"),
    (["match", "--away", "tests.batch_teams:all_toes", "--quiet"], "at least 3"),
    (["optimize", "sphere", "--sigma", "inf"], "finite number"),
    (["optimize", "sphere", "--population", "10000000"], "must be 1 to"),
])
def test_bad_numbers_and_teams_one_line_exit_2(args, needle):
    test_bad_input_one_line_exit_2(args, needle)


@pytest.mark.parametrize("cmd", [
    ["match", "--half-time", "1", "--quiet", "--out", "{bad}/r.json"],
    ["match", "--half-time", "1", "--quiet", "--log", "{bad}/m.npz"],
    ["batch", "--games", "1", "--half-time", "1", "--out", "{bad}/b"],
    ["optimize", "sphere", "--generations", "1", "--out", "{bad}/o"],
    ["model", "--out", "{bad}/r.xml"],
])
def test_unwritable_output_found_before_the_work(tmp_path, cmd):
    bad = tmp_path / "a_file"  # a file where a directory should be: unwritable even for root
    bad.write_text("")
    proc = soccer(*(a.format(bad=bad) for a in cmd))
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "is not a directory" in lines[0], proc.stderr


def test_batch_runs_resumes_and_refuses(tmp_path):
    out = tmp_path / "b"
    args = ["batch", "--games", "2", "--half-time", "0.3", "--home-size", "1", "--away-size", "2",
            "--workers", "2", "--out", str(out), "--quiet"]
    proc = soccer(*args, "--logs")
    assert proc.returncode == 0, proc.stderr
    assert "goal difference A - B" in proc.stdout and "games/hour" in proc.stdout
    rows = [json.loads(line) for line in (out / "games.jsonl").read_text().splitlines()]
    assert sorted((r["game"], r["a_side"]) for r in rows) == [(0, "L"), (1, "R")]
    assert len(list((out / "logs").glob("game_*.npz"))) == 2
    again = soccer(*args)
    assert again.returncode == 2 and "--resume" in again.stderr
    other = soccer(*[a if a != "0.3" else "0.4" for a in args], "--resume")
    assert other.returncode == 2 and "half_time 0.3 != 0.4" in other.stderr
    done = soccer(*args, "--resume")
    assert done.returncode == 0 and "games/hour" not in done.stdout


def test_missing_plugin_is_an_import_error(monkeypatch):
    from cli import main as cli_main
    monkeypatch.setattr(cli_main, "PLUGINS", (*cli_main.PLUGINS, "cli.no_such_cmd"))
    with pytest.raises(ModuleNotFoundError):
        cli_main.build_parser()

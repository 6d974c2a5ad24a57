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
    (["match", "--seed", "abc"], "invalid int value"),
])
def test_bad_input_one_line_exit_2(args, needle):
    proc = soccer(*args)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], proc.stderr
    assert "Traceback" not in proc.stderr

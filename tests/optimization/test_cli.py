"""`soccer optimize`: a short run's files, resume, and one-line errors with exit code 2."""

import subprocess
import sys

import pytest

from cli.main import main


def test_short_run_writes_every_file(tmp_path, capsys):
    out = tmp_path / "job"
    assert main(["optimize", "rosenbrock", "--option", "dim=2", "--population", "5", "--generations", "3",
                 "--workers", "0", "--seed", "4", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    gens = [ln for ln in err.splitlines() if ln.startswith("gen ")]
    assert len(gens) == 3 and all("best" in g and "mean" in g and "spread" in g for g in gens)
    for name in ("checkpoint.pkl", "history.csv", "best.txt", "fitness.png", "job.json"):
        assert (out / name).stat().st_size > 0, name
    assert (out / "fitness.png").read_bytes()[:4] == b"\x89PNG"
    # Resuming a finished job changes nothing; reusing its directory for a new job is refused.
    best = (out / "best.txt").read_text()
    assert main(["optimize", "--resume", str(out), "--workers", "0", "--quiet"]) == 0
    assert (out / "best.txt").read_text() == best
    assert main(["optimize", "sphere", "--out", str(out)]) == 2


def test_task_file_runs_its_layers_in_order(tmp_path):
    task = tmp_path / "two.task"
    task.write_text("layer first\n task sphere dim=2\n generations 2\n population 4\n"
                    "layer second\n task sphere dim=3\n input first\n overlap analytic x0\n"
                    " optimize analytic x2\n generations 2\n population 4\n")
    assert main(["optimize", str(task), "--workers", "0", "--out", str(tmp_path / "o"), "--quiet"]) == 0
    second = (tmp_path / "o/second/best.txt").read_text()
    assert "analytic_x0" in second and (tmp_path / "o/first/history.csv").exists()


@pytest.mark.parametrize("args,needle", [
    (["optimize", "walk_backward"], "unknown task 'walk_backward'"),
    (["optimize", "sphere", "--population", "0"], "must be 1 to 1000000"),
    (["optimize", "sphere", "--workers", "-1"], "workers must be 0"),
    (["optimize", "sphere", "--workers", "2", "--scheduler", "tcp://x:8786"], "not allowed with argument"),
    (["optimize", "sphere", "--scheduler", "localhost"], "expected an address like tcp://HOST:8786"),
    (["optimize", "sphere", "--option", "dim=many"], "option dim of task sphere must be a int"),
    (["optimize", "go_to_target", "--set", "jump"], "unknown parameter set 'jump'"),
    (["optimize", "go_to_target", "--params", "/nonexistent.txt"], "file /nonexistent.txt not found"),
    (["optimize", "--resume", "/nonexistent"], "no job to resume in /nonexistent"),
    (["optimize", "--resume", "/tmp", "--seed", "3"], "drop --seed"),
    (["optimize"], "TASK is required"),
])
def test_bad_input_one_line_exit_2(args, needle, capsys):
    try:
        code = main(args)
    except SystemExit as exc:  # argparse's errors
        code = exc.code
    assert code == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], lines


def test_bad_input_from_the_shell():
    proc = subprocess.run([sys.executable, "-m", "cli.main", "optimize", "sphere", "--option", "dim=0"],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip() == "soccer optimize: error: dim must be 1 to 16, not 0"


def test_bad_parameter_file_names_its_line(tmp_path, capsys):
    p = tmp_path / "walk.txt"
    p.write_text("walk_height\t180\nstep_hight\t20\n")
    assert main(["optimize", "walk_forward", "--params", str(p), "--out", str(tmp_path / "o")]) == 2
    assert f"{p}:2: unknown parameter 'step_hight'" in capsys.readouterr().err


def test_help_names_every_registered_task():
    from cli.optimize_cmd import HELP
    from optimization.task import TASKS

    listed = HELP.split("registered task (", 1)[1].split(")", 1)[0].replace("\n", " ")
    assert {n.strip() for n in listed.split(",")} == set(TASKS)

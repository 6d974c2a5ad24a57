"""Goalie dives in physics: each lowers the robot, the side dives reach sideways, and it gets up."""

import math

import numpy as np
import pytest

from models import nao
from models.messages import Action
from models.scene import Lineup
from optimization.trials import LIMIT, run_dive
from server.trainer import Trainer
from skills.dive import DIVES, Dive, load_dive_skills
from skills.params import ParamError


@pytest.mark.parametrize("name", DIVES)
def test_dive_lowers_the_robot_reaches_and_gets_up(name):
    r = run_dive(0, name, seed=0)
    assert r.ground is not None and r.ground < 1.2, f"{name}: torso not down within 1.2 s ({r})"
    if name == "DIVE_CENTER":  # spread across the goal, staying where it stood
        assert r.reach_left > 0.2 and r.reach_right < -0.2 and abs(r.torso_lateral) < 0.2, r
    else:  # to its side: the lunge farther than the side-wards split
        side = 1.0 if name.endswith("LEFT") else -1.0
        far, other = (r.reach_left, -r.reach_right) if side > 0 else (-r.reach_right, r.reach_left)
        min_far, min_torso = (0.45, 0.25) if name.startswith("LUNGE") else (0.3, 0.05)
        assert far > min_far and far > other + 0.15, \
            f"{name}: reach {far:.2f} m to its side, {other:.2f} m to the other"
        assert side * r.torso_lateral > min_torso, f"{name}: torso moved {r.torso_lateral:.2f} m sideways"
    assert r.up_after is not None and r.up_after < LIMIT and r.upright_at_end, f"{name}: did not get up ({r})"


def test_mirrored_dives_mirror():
    skills = load_dive_skills()
    for left, right in (("DIVE_LEFT", "DIVE_RIGHT"), ("LUNGE_LEFT", "LUNGE_RIGHT")):
        a, b = skills[left].keyframes[0].set, skills[right].keyframes[0].set
        assert a["llj2"] == pytest.approx(-b["rlj2"]) and a["llj3"] == pytest.approx(b["rlj3"])


def test_a_sitting_robot_lies_back_and_gets_up():
    """Seated upright with its weight off its feet the getups never start: DIVE_LIE_BACK."""
    import mujoco

    trainer = Trainer(Lineup((0,), ()), vision=False)
    w = trainer.world
    q = np.zeros(22)
    names = nao.joint_names(0)
    for j in ("llj3", "rlj3"):
        q[names.index(j)] = math.radians(90.0)  # legs straight out in front
    q[names.index("laj1")] = q[names.index("raj1")] = math.radians(-90.0)
    w.place_robot(0, 0.0, 0.0, 0.0, joints=q, z=0.2)
    w.settle_height(0)
    mujoco.mj_forward(w.model, w.data)
    dive = Dive(0, "DIVE_CENTER")
    dive.phase = "getup"  # as if a dive had just ended here
    dive.times = {"dive": 0.0, "down": 0.0, "relax": 0.0, "getup": 0.0}
    dive._target = q.copy()
    dive._gains(True)
    lay_back = False
    for _ in range(round(LIMIT / 0.02)):
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
        lay_back = lay_back or dive._lying_back
        if dive.done:
            break
    assert lay_back and dive.getup.count >= 1
    assert dive.done and w.torso_up()[0] > 0.9


def test_unknown_dive_and_bad_parameter_file(tmp_path):
    with pytest.raises(ValueError, match="unknown dive"):
        Dive(0, "DIVE_UP")
    bad = tmp_path / "dive.params"
    bad.write_text("dive_c_knee\t-120\nnot_a_dive_parameter\t3\n")
    with pytest.raises(ParamError, match=r"dive\.params:2: unknown parameter 'not_a_dive_parameter'"):
        load_dive_skills([bad])

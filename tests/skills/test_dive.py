"""Goalie dives in physics: each lowers the robot, the side dives reach sideways, and it gets up."""

import math
from dataclasses import dataclass

import numpy as np
import pytest

from models import nao
from models.messages import Action
from models.scene import Lineup
from server.trainer import Trainer
from skills.dive import DIVES, Dive, load_dive_skills
from skills.params import ParamError

LIMIT = 10.0  # s from the dive's start to standing again
LOW = 0.5  # the torso is down below this fraction of the standing height


@dataclass
class DiveRun:
    """Ground truth of one dive (lateral: m along the robot's starting left, from its start)."""

    ground: float | None  # s until the torso was below LOW x standing height
    reach_left: float  # farthest any collision geom got to the left while diving and down
    reach_right: float  # ... to the right (negative)
    torso_lateral: float  # torso displacement to the left when the robot was down
    up_after: float | None  # s until the dive reported done
    upright_at_end: bool  # torso up and high when done, and still so 0.5 s later
    times: dict  # s from the dive's start at which each phase (last) began


def run_dive(robot_type: int, name: str, seed: int) -> DiveRun:
    """A robot stands still (walk stand, seeded heading and joint noise), then plays `name`."""
    rng = np.random.default_rng(seed)
    trainer = Trainer(Lineup((robot_type,), ()), seed=seed, vision=False)
    w = trainer.world
    dive = Dive(robot_type, name)
    q = dive.motion.walk.update(0.0, 0.0, 0.0).targets
    q = np.where(np.isnan(q), 0.0, q) + rng.normal(0.0, 0.01, q.shape)
    dive.motion.reset()
    heading = float(rng.uniform(-math.pi, math.pi))
    w.place_ball((10.0, 8.0))
    w.place_robot(0, 0.0, 0.0, heading, joints=q)
    w.settle_height(0)
    for _ in range(25):
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.motion.walk_step(pc, 0.0, 0.0, 0.0))})
    p = w.players[0]
    geoms = [g for g in range(p.geoms[0], p.geoms[1] + 1) if w.model.geom_contype[g]]
    start = w.torso_positions()[0].copy()
    left = np.array([-math.sin(heading), math.cos(heading)])
    stand = nao.standing_height(robot_type)
    t0 = w.time
    ground, up_after = None, None
    reach_l = reach_r = lateral = 0.0
    while w.time - t0 < LIMIT and up_after is None:
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
        torso = w.torso_positions()[0]
        if ground is None and torso[2] < LOW * stand:
            ground = w.time - t0
        if dive.phase in ("dive", "down"):
            y = (w.data.geom_xpos[geoms, :2] - start[:2]) @ left
            reach_l, reach_r = max(reach_l, float(y.max())), min(reach_r, float(y.min()))
            lateral = float((torso[:2] - start[:2]) @ left)
        if dive.done:
            up_after = w.time - t0

    def upright() -> bool:
        return bool(w.torso_up()[0] > 0.9 and w.torso_positions()[0, 2] > 0.8 * stand)

    ok = up_after is not None and upright()
    for _ in range(25):  # it keeps standing
        pc = trainer.percepts()[0]
        trainer.step({0: Action(dive.step(pc))})
    times = {k: v - t0 for k, v in dive.times.items()}
    return DiveRun(ground, reach_l, reach_r, lateral, up_after, ok and upright(), times)


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

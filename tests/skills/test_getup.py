"""Fall detection and the getup skills, in physics; skill-file errors carry line numbers."""

import math

import numpy as np
import pytest

from models import nao
from models.messages import Action
from models.scene import Lineup
from optimization.getup import lying_joints
from server.sensors import Proprioception
from server.trainer import Trainer
from server.world import World
from skills.control import JointPid
from skills.falls import BACK, FALLING, FRONT, LEFT, RIGHT, UPRIGHT, FallDetector, Getup
from skills.motion import Motion
from skills.params import ParamError
from skills.skill import read_skills, skill_path
from tests.skills.imu_traces import WALK_A, WALK_B


def lone_world(robot_type: int) -> World:
    """One robot of `robot_type` with the ball and the other robot far away."""
    w = World(Lineup((robot_type,), (0,)))
    w.place_ball((10.0, 8.0))
    w.place_robot(1, 12.0, -8.0, 0.0)
    return w


# ----------------------------------------------------------------- fall detection


@pytest.mark.parametrize("accel, state", [
    ((0.0, 0.0, 9.81), UPRIGHT),
    ((-9.81, 0.0, 0.0), FRONT),  # face down: world up is the torso's -x
    ((9.81, 0.0, 0.0), BACK),
    ((0.0, -9.81, 0.0), LEFT),  # left side down: world up is the torso's -y
    ((0.0, 9.81, 0.0), RIGHT),
    ((-3.0, 0.0, 9.3), UPRIGHT),  # leaning 18 degrees
])
def test_detector_classifies_resting_postures(accel, state):
    d = FallDetector()
    for _ in range(20):
        d.update(np.array(accel), np.zeros(3))
    assert d.state == state
    assert d.fallen == (state not in (UPRIGHT, FALLING))


def test_detector_ignores_a_single_spike():
    d = FallDetector()
    d.update(np.array([0.0, 0.0, 9.81]), np.zeros(3))
    assert d.update(np.array([-30.0, 0.0, 0.0]), np.zeros(3)) != FRONT


def test_detector_ignores_foot_strikes_while_walking():
    # Recorded on an upright walking robot: the low-passed accelerometer tipped past 60 deg
    # for five calm-gyro cycles, and the front getup started; at rest it reads gravity alone.
    for accel, gyro in (WALK_A, WALK_B):
        d = FallDetector()
        states = [d.update(np.array(a), np.array(g)) for a, g in zip(accel * 2, gyro * 2)]
        assert not any(s in (FRONT, BACK, LEFT, RIGHT) for s in states)


@pytest.mark.parametrize("lying, state", [("front", FRONT), ("back", BACK), (None, UPRIGHT)])
def test_detector_in_physics(lying, state):
    w = lone_world(0)
    w.place_robot(0, -3.0, 3.0, 0.7, lying=lying)
    if lying:
        w.settle_height(0)
    sense = Proprioception(w)
    pid = JointPid.for_robot(0)
    act = w.players[0].actuators
    ctrl = np.zeros(w.model.nu)
    d = FallDetector()
    for _ in range(50):
        q, gyro, acc, _ = sense.read()[0]
        d.update(acc, gyro)
        ctrl[act] = pid(np.zeros(len(q)), q)
        w.step(ctrl)
    assert d.state == state


def test_detector_sees_a_fall_coming_and_landing():
    w = lone_world(0)
    w.place_robot(0, -3.0, 3.0, 0.0)
    w.settle_height(0)
    p = w.players[0]
    sense = Proprioception(w)
    ctrl = np.zeros(w.model.nu)
    d = FallDetector()
    seen = []
    for k in range(100):
        w.data.xfrc_applied[p.torso, 0] = 15.0 if k < 10 else 0.0  # a push forward (N)
        _, gyro, acc, _ = sense.read()[0]
        seen.append(d.update(acc, gyro))
        w.step(ctrl)
    assert FALLING in seen
    assert seen.index(FALLING) < seen.index(FRONT)
    assert seen[-1] == FRONT and w.torso_up()[0] < 0.3


# -------------------------------------------------------------------- getting up


def get_up(robot_type: int, lying: str, seed: int, limit: float = 3.0) -> float | None:
    """Time (s) until the robot stands (up z > 0.9, height > 0.8 stand) for 1 s, or None."""
    w = lone_world(robot_type)
    rng = np.random.default_rng(seed)
    specs = nao.joints(robot_type)
    q0 = np.clip(rng.normal(0.0, 0.1, len(specs)), [s.lower for s in specs], [s.upper for s in specs])
    w.place_robot(0, -3.0, 3.0, rng.uniform(-math.pi, math.pi), joints=q0, lying=lying)
    w.settle_height(0)
    sense = Proprioception(w)
    act = w.players[0].actuators
    ctrl = np.zeros(w.model.nu)
    pid = JointPid.for_robot(robot_type)
    for _ in range(25):
        q = sense.read()[0][0]
        ctrl[act] = pid(q0, q)
        w.step(ctrl)
    getup = Getup(robot_type)
    stand = nao.standing_height(robot_type)
    t0, since, hold = w.time, None, None
    while w.time - t0 < limit + 1.0:
        q, gyro, acc, _ = sense.read()[0]
        target = getup.step(w.time, q, acc, gyro)
        if target is None:
            target = getup.hold()  # the getup's end pose, balanced
        hold = target.copy() if target is not None else (q.copy() if hold is None else hold)
        ctrl[act] = pid(hold, q)
        w.step(ctrl)
        up = w.torso_up()[0] > 0.9 and w.torso_positions()[0, 2] > 0.8 * stand
        if up and not getup.busy:
            since = w.time if since is None else since
            if w.time - since >= 1.0 - 1e-9:
                return since - t0
        else:
            since = None
            if w.time - t0 > limit:
                return None
    return None


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
@pytest.mark.parametrize("lying", ["front", "back"])
def test_gets_up(robot_type, lying):
    """Two of three seeded tries up within 3 s. The getups stand within 3 s in 95-97% of
    the getup benchmark's tries (700 per side over all types), so one try in 25 fails;
    a getup that works half the time fails this test with probability 1/2."""
    took = [get_up(robot_type, lying, seed=10 * robot_type + k) for k in range(3)]
    up = [t for t in took if t is not None]
    assert len(up) >= 2, f"type {robot_type} got up from the {lying} in {len(up)} of 3 tries"
    assert max(up) < 3.0


def test_the_hold_turns_the_ankles_against_the_torsos_lean():
    """While a getup's end pose holds, the ankle pitches turn by HOLD_ANKLE_GAIN per rad of
    fore-aft lean (from the filtered accelerometer), at most HOLD_ANKLE_MAX; every other
    joint keeps the end pose. (It was made for type 2's back getup ending tipped back
    26 deg on its heels, 5 of 120 seeded starts, while the motors chattered at their force
    limit; with the armature of models/robot.py none of 450 starts of types 0, 2 and 4
    ended so, so the case is built here from the filter's reading.)"""
    from skills import falls

    g = Getup(2)
    assert g.hold() is None  # no getup has played yet
    pose = np.linspace(-0.5, 0.5, len(nao.joint_names(2)))
    g.last = pose.copy()
    ankles = [nao.joint_names(2).index(n) for n in falls.ANKLE_PITCH]
    others = np.setdiff1d(np.arange(len(pose)), ankles)
    for lean, turn in ((0.0, 0.0), (0.2, falls.HOLD_ANKLE_GAIN * 0.2), (1.0, -falls.HOLD_ANKLE_MAX),
                       (-1.0, falls.HOLD_ANKLE_MAX)):
        g.detector.accel = falls.GRAVITY * np.array([math.sin(lean), 0.0, math.cos(lean)])
        out = g.hold()
        assert np.allclose(out[ankles], pose[ankles] + turn), (lean, out[ankles] - pose[ankles])
        assert np.array_equal(out[others], pose[others])


def recover_as_in_a_match(robot_type: int, seed: int, seconds: float = 4.0,
                       lying: str = "front") -> tuple[int, float, float | None]:
    """A robot lying face down (or `lying` "back") with its legs in the walk's stand pose
    (as a walking robot lands), driven as in a match: `Motion.recover`, else the walk's
    stand. Returns the getups started, the torso's up-vector z after `seconds` and when
    (s) the first getup started (None if none did)."""
    rng = np.random.default_rng(seed)
    tr = Trainer(Lineup((robot_type,), ()), vision=False)
    tr.world.place_ball((10.0, 8.0))
    mo = Motion(robot_type)
    q0 = lying_joints(robot_type, rng, "walk")
    tr.world.place_robot(0, 0.0, 0.0, rng.uniform(-math.pi, math.pi), joints=q0, lying=lying)
    tr.world.settle_height(0)
    first = None
    for k in range(round(seconds / 0.02)):
        pc = tr.percepts()[0]
        v = mo.recover(pc)
        tr.step({0: Action(mo.walk_step(pc, 0.0, 0.0, 0.0) if v is None else v)})
        if first is None and mo.getup.count:
            first = (k + 1) * 0.02
    return mo.getup.count, float(tr.world.torso_up()[0]), first


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_gets_up_from_the_front_as_in_a_match(robot_type):
    """From the walk's bent legs and arms at its sides the front getup first lays the
    body flat on its chest, swinging the arms forward beside it: without that, types
    0-4 stood on the first getup in 0-5 of 20 tries and fell over backward in the rest
    (on the walk course, 10 of type 2's 18 falls were failed getups); with it, in 18-20
    of 20. Two of three seeded tries stand on the first getup."""
    ok = [count == 1 and up > 0.9 for count, up, _ in
          (recover_as_in_a_match(robot_type, seed=100 * robot_type + k) for k in range(3))]
    assert sum(ok) >= 2, f"type {robot_type}: stood on the first front getup in {sum(ok)} of 3 tries"


@pytest.mark.parametrize("robot_type", [0, 4])
def test_a_robot_down_on_its_back_from_walking_starts_its_getup_at_once(robot_type):
    """Lying face up on the walk's bent knees the torso's contacts chatter at the physics
    substep rate. An accelerometer reading one substep aliased that into a steady
    5 m/s^2 along the torso's z axis and +-3 m/s^2 of jitter: the fall detector waited
    for rest for up to 1.9 s (seeds here) or past the 3 s limit (9 of
    benchmarks.getup's 100 walk-start tries on type 4). With the cycle's mean
    acceleration every one of 12 seeded tries starts within 0.14-0.26 s."""
    for k in range(12):
        _, _, first = recover_as_in_a_match(robot_type, 400 + 100 * robot_type + k, 0.6, "back")
        assert first is not None and first < 0.5, f"type {robot_type} seed {k}: getup started at {first} s"


def test_upright_robot_plays_no_getup():
    g = Getup(0)
    for k in range(20):
        assert g.step(0.02 * k, np.zeros(22), np.array([0.0, 0.0, 9.81]), np.zeros(3)) is None
    assert not g.busy and g.count == 0


def test_getup_chooses_the_skill_for_the_side():
    g = Getup(0)
    for k in range(10):
        g.step(0.02 * k, np.zeros(22), np.array([9.81, 0.0, 0.0]), np.zeros(3))
    assert g.busy and g.active == BACK and g.count == 1
    g.reset()
    for k in range(10):
        g.step(0.02 * k, np.zeros(22), np.array([-9.81, 0.0, 0.0]), np.zeros(3))
    assert g.active == FRONT


# ------------------------------------------------------------- malformed files


def test_malformed_getup_skill_names_its_line(tmp_path):
    text = open(skill_path("getup_front.skl")).read().splitlines()
    # Break the first settar of the file: a misspelt joint.
    k = next(i for i, line in enumerate(text) if line.strip().startswith("settar"))
    text[k] = text[k].replace("settar", "settar lle33 5", 1)
    bad = tmp_path / "getup_front.skl"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(ParamError) as e:
        read_skills(bad)
    assert str(e.value).startswith(f"{bad}:{k + 1}:") and "'lle33'" in str(e.value)


def test_malformed_getup_parameter_file_names_its_line(tmp_path):
    from skills.falls import load_getup_skills

    bad = tmp_path / "getup.params"
    bad.write_text("# tuned getup\n\nnot_a_getup_parameter\t3\n")
    with pytest.raises(ParamError, match=r"getup\.params:3: unknown parameter 'not_a_getup_parameter'"):
        load_getup_skills([bad])


@pytest.mark.parametrize("roll_deg, side", [(-90.0, LEFT), (90.0, RIGHT)])
def test_rolls_off_its_side_then_gets_up(roll_deg, side):
    import mujoco

    w = lone_world(0)
    w.place_robot(0, -3.0, 3.0, 0.0, z=0.12)
    p = w.players[0]
    quat = np.zeros(4)
    mujoco.mju_axisAngle2Quat(quat, np.array([1.0, 0.0, 0.0]), math.radians(roll_deg))
    w.data.qpos[p.root_qpos + 3:p.root_qpos + 7] = quat
    mujoco.mj_forward(w.model, w.data)
    w.settle_height(0)
    sense = Proprioception(w)
    pid = JointPid.for_robot(0)
    getup = Getup(0)
    ctrl = np.zeros(w.model.nu)
    hold, played = None, []
    for _ in range(400):
        q, gyro, acc, _ = sense.read()[0]
        target = getup.step(w.time, q, acc, gyro)
        hold = target.copy() if target is not None else (q.copy() if hold is None else hold)
        if getup.active and (not played or played[-1] != getup.active):
            played.append(getup.active)
        ctrl[p.actuators] = pid(hold, q)
        w.step(ctrl)
    assert played[0] == side and played[-1] in (FRONT, BACK)
    assert w.torso_up()[0] > 0.9 and w.torso_positions()[0, 2] > 0.8 * nao.standing_height(0)

"""The skill description language: parsing, units, parameters, errors, reflection, playback."""

import math

import mujoco
import numpy as np
import pytest

from models import nao, robot
from skills.params import ParamError
from skills.skill import (
    SkillPlayer,
    load_skills,
    mirror_angles,
    parse_skills,
    read_skills,
)

D = math.pi / 180

KICK = """\
# a kick in the style of UT Austin Villa's skill files
STARTSKILL KICK_LEFT
STARTSTATE
    settar lle3 $kick_hip lle4 -40 lae2 20 end   // degrees
    settar he1 10 end
    wait 0.1 end
ENDSTATE
STARTSTATE
    inctar lle3 -10 lle2 5 end
    settar lle5 (2 * $kick_hip) - 5 end
    wait $kick_wait
ENDSTATE
ENDSKILL
REFLECTSKILL KICK_LEFT KICK_RIGHT
"""


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_keyframes_in_si(tmp_path):
    skl = write(tmp_path, "kick.skl", KICK)
    par = write(tmp_path, "kick.txt", "kick_hip\t30\nkick_wait\t0.25\n")
    skills = load_skills(skl, [par])
    k = skills["KICK_LEFT"].keyframes
    assert k[0].set == pytest.approx({"llj3": 30 * D, "llj4": -40 * D, "laj2": 20 * D, "hj1": 10 * D})
    assert k[0].wait == pytest.approx(0.1)
    assert k[1].inc == pytest.approx({"llj3": -10 * D, "llj2": 5 * D})
    assert k[1].set == pytest.approx({"llj5": 55 * D})  # (2 * 30) - 5 degrees
    assert k[1].wait == pytest.approx(0.25)
    assert skills["KICK_LEFT"].duration == pytest.approx(0.35)


def test_schema_gives_each_parameter_its_slot_unit():
    src = parse_skills(KICK)
    assert src.schema == {"kick_hip": "deg", "kick_wait": "s"}


def test_later_parameter_files_override(tmp_path):
    skl = write(tmp_path, "kick.skl", KICK)
    a = write(tmp_path, "a.txt", "kick_hip\t30\nkick_wait\t0.25\n")
    b = write(tmp_path, "b.txt", "kick_hip\t40\n")
    k = load_skills(skl, [a, b])["KICK_LEFT"].keyframes
    assert k[0].set["llj3"] == pytest.approx(40 * D)
    assert k[1].wait == pytest.approx(0.25)


@pytest.mark.parametrize("expr, value", [
    ("5", 5 * D), ("-$a", -20 * D), ("$a + 5", 25 * D), ("5 - $a", -15 * D), ("2 * $a", 40 * D),
    ("$a / 2", 10 * D), ("(1 + 2) * 3", 9 * D), ("-(2 * $a - 10)", -30 * D), ("+4.5e1", 45 * D),
    ("$a * 2 + $a", 60 * D),
])
def test_expressions_keep_units_straight(expr, value):
    src = parse_skills(f"STARTSKILL S\nSTARTSTATE\nsettar lle3 {expr} end\nENDSTATE\nENDSKILL\n")
    s = src.bind({"a": 20 * D})["S"]
    assert s.keyframes[0].set["llj3"] == pytest.approx(value)


def test_ut_names_and_spellings_are_aliases():
    text = ("startskill S\nstartstate\nsetTarget EFF_LL3 10 EFF_RA1 -90 end\n"
            "increaseTarget EFF_H2 5 end\nwait 0.1 end\nendstate\nendskill\n")
    k = parse_skills(text).bind()["S"].keyframes[0]
    assert k.set == pytest.approx({"llj3": 10 * D, "raj1": -90 * D})
    assert k.inc == pytest.approx({"hj2": 5 * D})


BAD = [
    # (skill text, line, word)
    ("STARTSKILL S\nSTARTSTATE\nsettar lle9 10 end\nENDSTATE\nENDSKILL\n", 3, "lle9"),
    ("STARTSKILL S\nSTARTSTATE\n\nsettar lle3 abc end\nENDSTATE\nENDSKILL\n", 4, "abc"),
    ("STARTSKILL S\nSTARTSTATE\nsetta lle3 10 end\nENDSTATE\nENDSKILL\n", 3, "setta"),
    ("STARTSKILL S\nSTARTSTATE\nsettar lle3 1@0 end\nENDSTATE\nENDSKILL\n", 3, "@0"),
    ("STARTSKILL S\nSTARTSTATE\nwait 0.1 end\nwait 0.2 end\nENDSTATE\nENDSKILL\n", 4, "wait"),
    ("# x\nSTARTSTATE\n", 2, "STARTSTATE"),
    ("STARTSKILL S\nSTARTSTATE\nsettar lle3 (1 + 2 end\nENDSTATE\nENDSKILL\n", 3, "end"),
    ("STARTSKILL S\nENDSKILL\nREFLECTSKILL T U\n", 3, "T"),
    ("STARTSKILL S\nSTARTSTATE\nsettar lle3 $a end\nwait $a end\nENDSTATE\nENDSKILL\n", 4, "$a"),
    ("STARTSKILL S\nSTARTSTATE\nsettar lle3 $a * $b end\nENDSTATE\nENDSKILL\n", 3, None),
]


@pytest.mark.parametrize("text, line, word", BAD)
def test_errors_name_file_line_and_word(tmp_path, text, line, word):
    p = write(tmp_path, "bad.skl", text)
    with pytest.raises(ParamError) as e:
        read_skills(p).bind({"a": 1.0, "b": 1.0})
    msg = str(e.value)
    assert msg.startswith(f"{p}:{line}:"), msg
    if word is not None:
        assert repr(word) in msg


def test_file_ending_early_names_the_last_line(tmp_path):
    p = write(tmp_path, "bad.skl", "STARTSKILL S\nSTARTSTATE\nsettar lle3 10 end\n")
    with pytest.raises(ParamError, match=r"bad\.skl:3: file ends"):
        read_skills(p)


def test_missing_parameter_names_the_skill_line(tmp_path):
    skl = write(tmp_path, "kick.skl", KICK)
    par = write(tmp_path, "kick.txt", "kick_hip\t30\n")
    with pytest.raises(ParamError, match=r"kick\.skl:11: parameter not set '\$kick_wait'"):
        load_skills(skl, [par])


def test_unknown_name_in_parameter_file_names_that_file(tmp_path):
    skl = write(tmp_path, "kick.skl", KICK)
    par = write(tmp_path, "kick.txt", "kick_hip\t30\nkick_wait\t0.2\nkick_hipp\t3\n")
    with pytest.raises(ParamError, match=r"kick\.txt:3: unknown parameter 'kick_hipp'"):
        load_skills(skl, [par])


# ------------------------------------------------------------------- reflection


def _body_positions(model, data, q, names):
    data.qpos[:] = 0.0
    data.qpos[3] = 1.0
    for n, v in zip(names, q):
        data.qpos[model.jnt_qposadr[model.joint(n).id]] = v
    mujoco.mj_kinematics(model, data)
    return {model.body(b).name: data.xpos[b].copy() for b in range(1, model.nbody)}


@pytest.mark.parametrize("robot_type", [0, 3, 4])
def test_reflected_pose_mirrors_in_y(robot_type):
    model = mujoco.MjModel.from_xml_string(robot.robot_mjcf(robot_type))
    data = mujoco.MjData(model)
    names = nao.joint_names(robot_type)
    specs = nao.joints(robot_type)
    rng = np.random.default_rng(3)
    # Each joint's range mirrored onto its partner must hold both angles.
    q = np.zeros(len(names))
    for _ in range(3):
        for i, s in enumerate(specs):
            q[i] = rng.uniform(s.lower, s.upper)
        m = mirror_angles(q, names)
        ok = all(s.lower - 1e-9 <= v <= s.upper + 1e-9 for s, v in zip(specs, m))
        assert ok, "a mirrored angle left its joint's range"
        a, b = _body_positions(model, data, q, names), _body_positions(model, data, m, names)
        for name, p in a.items():
            other = {"l": "r", "r": "l"}[name[0]] + name[1:] if name[0] in "lr" else name
            assert b[other] == pytest.approx(p * np.array([1, -1, 1]), abs=1e-9), name


def test_reflectskill_mirrors_every_keyframe(tmp_path):
    skills = parse_skills(KICK).bind({"kick_hip": 30 * D, "kick_wait": 0.2})
    left, right = skills["KICK_LEFT"], skills["KICK_RIGHT"]
    assert right.keyframes[0].set == pytest.approx(
        {"rlj3": 30 * D, "rlj4": -40 * D, "raj2": -20 * D, "hj1": -10 * D})
    assert right.keyframes[1].inc == pytest.approx({"rlj3": -10 * D, "rlj2": -5 * D})
    assert left.reflected("X").reflected("Y").keyframes == left.keyframes


# ----------------------------------------------------------------------- player


def test_player_starts_from_current_angles_and_steps_keyframes():
    skills = parse_skills(KICK).bind({"kick_hip": 30 * D, "kick_wait": 0.2})
    names = nao.joint_names(0)
    i = {n: k for k, n in enumerate(names)}
    p = SkillPlayer(skills["KICK_LEFT"], 0)
    q = np.full(len(names), 0.1)
    t = p.step(5.0, q).copy()
    assert t[i["llj3"]] == pytest.approx(30 * D) and t[i["rlj3"]] == pytest.approx(0.1)
    assert not p.done and p.keyframe == 0
    t = p.step(5.08, q).copy()
    assert t[i["llj3"]] == pytest.approx(30 * D) and p.keyframe == 0
    t = p.step(5.1, q).copy()
    assert p.keyframe == 1
    assert t[i["llj3"]] == pytest.approx(20 * D)
    assert t[i["llj2"]] == pytest.approx(0.1 + 5 * D)
    assert t[i["llj5"]] == pytest.approx(55 * D)
    assert not p.done
    p.step(5.3, q)
    assert p.done
    p.reset()
    assert not p.done
    assert p.step(0.0, np.zeros(len(names)))[i["llj2"]] == 0.0


def test_player_clips_to_joint_limits_and_drops_missing_toes():
    src = parse_skills("STARTSKILL S\nSTARTSTATE\nsettar lle4 50 lle7 30 end\nwait 0.1\nENDSTATE\nENDSKILL\n")
    s = src.bind()["S"]
    p0 = SkillPlayer(s, 0)
    t = p0.step(0.0, np.zeros(22))
    assert t[nao.joint_names(0).index("llj4")] == pytest.approx(1 * D)  # knee upper limit
    p4 = SkillPlayer(s, 4)
    t = p4.step(0.0, np.zeros(24))
    assert t[nao.joint_names(4).index("llj7")] == pytest.approx(30 * D)


def test_shipped_skills_load():
    from skills.falls import load_getup_skills

    skills = load_getup_skills()
    for name in ("GETUP_FRONT", "GETUP_BACK", "ROLL_LEFT", "ROLL_RIGHT", "FALL_ARMS"):
        assert name in skills and skills[name].keyframes
    assert skills["GETUP_FRONT"].duration < 3.0 and skills["GETUP_BACK"].duration < 3.0

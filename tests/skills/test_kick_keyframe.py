"""Keyframe kicks in physics: the kick reads only its percepts; the test reads truth.

Run as a script for the figures of the report (distance mean/std, direction
error, success rate over seeded ball offsets, per kick and robot type):

    python -m tests.skills.test_kick_keyframe [--types 0,1,2,3,4] [--tries 10] [--kicks kick,long_kick]
        [--feet left,right] [--seed 0] [--holds 0.6,0.7,0.8,0.9,1.0,1.1]
"""

from __future__ import annotations

import argparse
import json
import math
import re
from dataclasses import dataclass

import numpy as np
import pytest

from models import nao
from models.messages import Action
from models.scene import Lineup
from server.trainer import Trainer
from skills.kicks import KickSpec
from skills.kicks.keyframe import (
    KeyframeKick,
    angle_error,
    default_param_files,
    keyframe_kicks,
    load_kick_sets,
)
from skills.motion import Motion
from skills.params import ParamError
from skills.skill import read_skills, skill_path
from skills.walk import WalkEngine

FALLEN_UP = 0.5  # torso z axis' world-z component below which the robot has fallen
HEAD_PITCH = -0.6  # rad: a robot watching the ball at its feet (agent.kicker.HEAD_PITCH)


@dataclass(frozen=True)
class Outcome:
    """Ground truth of one kick: ball travel (m) and direction (rad, start frame), a fall."""

    distance: float
    direction: float
    fell: bool
    seconds: float  # simulated s from the kick's start to the ball's stop (or the limit)


def stand_pose(robot_type: int) -> np.ndarray:
    """The walk's stand pose (rad, league order; the head at 0)."""
    q = WalkEngine(robot_type).update(0.0, 0.0, 0.0).targets
    return np.where(np.isnan(q), 0.0, q)


def kick_once(kick: KeyframeKick, robot_type: int, offset: tuple[float, float] = (0.0, 0.0),
              limit: float = 4.0, hold: float = 0.6, walk_stand: bool = True) -> Outcome:
    """Stand the robot at the origin facing +x with the ball at the kick's offset (+ `offset`, m),
    play the kick through `Motion.command` from percepts only, then stand until the ball stops
    or `limit` s after the kick's start; a ball still rolling then is extrapolated to its stop
    (`World.ball_rest_position`). Before the kick the robot stands `hold` s: in the walk's
    stand looking at the ball, as agents do (`walk_stand`), or holding the stand pose."""
    tr = Trainer(Lineup((robot_type,), ()), vision=False)
    w = tr.world
    mo = Motion(robot_type)
    q0 = stand_pose(robot_type)
    w.place_robot(0, 0.0, 0.0, 0.0, joints=q0)
    w.settle_height(0)
    bx, by = kick.spec.ball
    w.place_ball((bx + offset[0], by + offset[1]))
    b0 = w.ball_position()[:2].copy()
    head = np.array([math.atan2(b0[1], b0[0]), HEAD_PITCH])  # looking at the ball, as agents do
    for _ in range(round(hold / 0.02)):
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.walk_step(pc, 0.0, 0.0, 0.0, head=head) if walk_stand
                           else mo.command(q0, pc))})
    kick.reset(start=mo.held_target)  # as the agent's Kicker starts it
    target, t0, fell = q0, w.time, False
    while w.time - t0 < limit:
        pc = tr.percepts()[0]
        if not kick.done:
            target = kick.step(pc)
        tr.step({0: Action(mo.command(target, pc))})
        fell = fell or bool(w.torso_up()[0] < FALLEN_UP)
        if (kick.done and w.time - t0 > kick.spec.duration + 0.5
                and np.linalg.norm(w.ball_velocity()[:2]) < 0.02):
            break
    d = w.ball_rest_position() - b0  # a ball still rolling is carried on to its stop
    return Outcome(float(np.hypot(*d)), math.atan2(d[1], d[0]), fell, w.time - t0)


def success(spec: KickSpec, out: Outcome, minimum: float = 1.0) -> bool:
    """The issue's success: the ball moved at least `minimum` m toward the kick's direction
    and the robot did not fall."""
    toward = out.distance * math.cos(angle_error(out.direction, spec.direction))
    return toward >= minimum and not out.fell


def offsets(seed: int, n: int, spread: float = 0.01) -> list[tuple[float, float]]:
    """`n` seeded ball offsets (m), uniform in +-`spread` on x and y."""
    rng = np.random.default_rng(seed)
    return [tuple(v) for v in rng.uniform(-spread, spread, (n, 2))]


# ------------------------------------------------------------------- physics tests

# rad: how far from its spec's direction each kick may send the ball
DIRECTION_TOLERANCE = {"kick": math.radians(15.0), "long_kick": math.radians(15.0)}


def min_distance(spec: KickSpec) -> float:
    """What a kick must reach at least (m): 60% of its nominal distance, and the issue's 1 m."""
    return max(1.0, 0.6 * spec.distance)


# m: what the general and the long kick reach at least on type 0 (the goal for a
# keyframe kick; with the league's ball drag the kick measures about 6.4 m, the long kick 9)
MIN_KICK_DISTANCE = {"kick": 5.0, "long_kick": 6.4}


@pytest.mark.parametrize("foot", ["l", "r"])
@pytest.mark.parametrize("set_name", ["kick", "long_kick"])
def test_kick_moves_the_ball_forward_without_falling(set_name, foot):
    kick = keyframe_kicks(0)[f"{set_name}_{'left' if foot == 'l' else 'right'}"]
    out = kick_once(kick, 0, offset=offsets(seed=7, n=1, spread=0.005)[0])
    assert not out.fell
    assert out.distance >= max(min_distance(kick.spec), MIN_KICK_DISTANCE[set_name]), out
    assert abs(angle_error(out.direction, kick.spec.direction)) < DIRECTION_TOLERANCE[set_name], out


LONG_KICK_SHARE = 0.8  # of its nominal distance, what most long kicks reach at least


@pytest.mark.parametrize("foot", ["l", "r"])
def test_long_kick_reaches_most_of_its_nominal_distance(foot):
    # The long kick (type 0) swings the thigh ahead of the knee's snap with the support hip
    # opening (learned by CMA-ES, kick.params): about 9 m where the old one went 6.3 m.
    # It still falls or misses (the lifting foot brushes the ball) about one kick in eight
    # from a rocking stand, so of 4 seeded kicks (ball offsets within +-5 mm, started at 4
    # moments of the rocking) 3 must reach 80% of the nominal distance without a fall.
    kick = KeyframeKick.load("long_kick", foot, 0)
    assert kick.spec.distance >= 8.0
    outs = [kick_once(kick, 0, offset=off, hold=0.6 + 0.1 * i)
            for i, off in enumerate(offsets(seed=11, n=4, spread=0.005))]
    far = [o for o in outs if not o.fell and o.distance >= LONG_KICK_SHARE * kick.spec.distance
           and abs(angle_error(o.direction, kick.spec.direction)) < DIRECTION_TOLERANCE["long_kick"]]
    assert len(far) >= 3, outs


@pytest.mark.parametrize("robot_type", [1, 2, 3, 4])
def test_kick_works_on_other_types(robot_type):
    # Started at 8 moments of the stand's rocking (after 0.6-1.1 s). These types' kicks
    # still fall often from a rocking stand (issue 4's open shortfall; standing trials,
    # 60 kicks each: type 1 2%, 2 37%, 3 20%, 4 3%), so the test asks for 3 of 8.
    kick = keyframe_kicks(robot_type)["kick_left"]
    outs = [kick_once(kick, robot_type, hold=0.6 + 0.075 * i) for i in range(8)]
    assert sum(success(kick.spec, o, minimum=2.0) for o in outs) >= 3, outs


@pytest.mark.parametrize("robot_type", [3])
def test_a_kick_after_a_long_stand_keeps_its_balance(robot_type):
    # In a walking approach the kick starts after 4-5 s of standing (the settle and the
    # align). Started after 2.6-3.7 s, type 3's kick failed 7 of 12 (mostly rolling over its
    # support foot) until its weight shift was learned (optimization/tasks/kick_shift.task): 4 now.
    kick = keyframe_kicks(robot_type)["kick_left"]
    outs = [kick_once(kick, robot_type, hold=2.6 + 0.1 * i) for i in range(12)]
    assert sum(success(kick.spec, o) for o in outs) >= 7, outs


BASE_POSE_SLIDE = 0.015  # m: how far a foot may move while the kick goes into its base pose


def base_pose_slide(kick: KeyframeKick, robot_type: int, hold: float) -> float:
    """The farthest either foot moves (m, world, on the ground plane) from where it stood while
    the kick plays its base pose (k0, both feet loaded), after `hold` s in the walk's stand."""
    tr = Trainer(Lineup((robot_type,), ()), vision=False)
    w = tr.world
    mo = Motion(robot_type)
    w.place_robot(0, 0.0, 0.0, 0.0, joints=stand_pose(robot_type))
    w.settle_height(0)
    for _ in range(round(hold / 0.02)):
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.walk_step(pc, 0.0, 0.0, 0.0, head=np.array([0.0, HEAD_PITCH])))})
    feet = [w.model.body(f"L1/{f}foot").id for f in "lr"]
    start = w.data.xpos[feet, :2].copy()
    kick.reset(start=mo.held_target)
    slide, t0 = 0.0, w.time
    while kick.player.keyframe <= 0 and w.time - t0 < 2.0:
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.command(kick.step(pc), pc))})
        slide = max(slide, float(np.max(np.linalg.norm(w.data.xpos[feet, :2] - start, axis=1))))
    return slide


@pytest.mark.parametrize("robot_type", [3])
def test_the_feet_stay_put_while_the_kick_goes_into_its_base_pose(robot_type):
    # The base pose straightens the stand's knees by about 33 deg. Applied at once, that makes
    # the robot hop, and type 3's feet, whose stand holds the legs 5.6 deg inward, spread to
    # zero roll as well: here they moved up to 43 mm, so the swing met the ball somewhere else
    # each time. Type 3's kick now slews from the stand's targets in a straight line
    # (kick_base_slew) and keeps the stand's roll (kick_stand_roll): 4-13 mm over holds of
    # 0.6-2 s. (Types 0, 1, 2 and 4 still jump, as their kicks were tuned: type 0's feet move
    # up to 22 mm; slewing, 6-8 mm, but their walking kicks did no better.)
    kick = keyframe_kicks(robot_type)["kick_right"]
    slides = [base_pose_slide(kick, robot_type, hold=0.6 + 0.1 * i) for i in range(3)]
    assert max(slides) < BASE_POSE_SLIDE, slides


@pytest.mark.parametrize("robot_type", [0, 1, 2, 3, 4])
def test_a_kept_stand_roll_is_the_walks(robot_type):
    # kick_stand_roll restates the walk stand's hip roll (types 2 and 3 keep it, the others
    # play 0, as they were tuned); a walk whose stand changed would leave it stale.
    roll = stand_pose(robot_type)[nao.joint_names(robot_type).index("llj2")]
    for name, values in load_kick_sets(default_param_files(robot_type)).items():
        if values["stand_roll"] != 0.0:
            assert abs(values["stand_roll"] - roll) < math.radians(0.1), (name, values["stand_roll"], roll)


def fixed_distance_sets() -> list[str]:
    """The fixed-distance sets ("kick_3m", ...) of the shipped file, by nominal distance."""
    sets = load_kick_sets([skill_path("kick.params")])
    fixed = (s for s in sets if re.fullmatch(r"kick_\d+m", s))
    return sorted(fixed, key=lambda s: sets[s]["distance"])


def fixed_tolerance(nominal: float) -> float:
    """m: how far a fixed-distance kick's mean, or its name, may be from its nominal distance."""
    return max(0.7, 0.2 * nominal)


# Kicks per fixed-distance set (seeded offsets); the test takes their mean. A kick's
# distance scatters 1-1.7 m (sd), so six tries' mean moved by up to 1.2 m when nothing
# but the accelerometer's sampling changed (kick_5m: 5.46 -> 6.66 m, while its benchmark
# figures stayed within their noise); twelve halve that variance.
FIXED_TRIES = 12
FIXED_DIRECTION_TOLERANCE = math.radians(10.0)  # rad, the kicks' mean direction from the spec's


@pytest.mark.parametrize("foot", ["l", "r"])
def test_a_kick_started_at_any_moment_of_the_stands_rocking_does_not_fall(foot):
    # The stand rocks on its feet at about 6.5 Hz; started 0.60-0.75 s after standing
    # (every 10 ms: one whole period), the long kick fell 4 times in 16 per foot until it
    # learnt to wait for its phase (skills.kicks.keyframe.START_PITCH_RATE).
    kick = KeyframeKick.load("long_kick", foot, 0)
    falls = [round(0.6 + 0.01 * i, 2) for i in range(16) if kick_once(kick, 0, hold=0.6 + 0.01 * i).fell]
    assert not falls, falls


def test_a_kick_waits_at_most_start_wait_for_the_pitch_rate():
    from models.messages import Percept
    from skills.kicks.keyframe import START_PITCH_RATE, START_WAIT

    kick = KeyframeKick.load("kick", "l", 0)
    q = stand_pose(0)

    def percept(t: float, rate: float) -> Percept:
        return Percept(t, t, "PlayOn", 0, 0, "L", 1, 0, q.copy(), np.array([0.0, rate, 0.0]),
                       np.array([0.0, 0.0, 9.81]), np.array([20.0, 20.0]))

    kick.reset()
    held = [bool(np.isnan(kick.step(percept(0.02 * i, START_PITCH_RATE - 0.3))).all()) for i in range(40)]
    assert held.index(False) == pytest.approx(START_WAIT / 0.02, abs=1)  # holds, then starts anyway
    kick.reset()
    assert not np.isnan(kick.step(percept(0.0, START_PITCH_RATE + 0.1))).all()  # the right way: at once


@pytest.mark.parametrize("set_name", fixed_distance_sets())
def test_fixed_distance_kick_reaches_its_distance(set_name):
    # Kicks started at FIXED_TRIES moments of the stand's rocking; these kicks still fall
    # about one time in ten from a rocking stand (issue 4's open shortfall): three may.
    kick = keyframe_kicks(0)[f"{set_name}_left"]
    outs = [kick_once(kick, 0, offset=off, hold=0.6 + 0.1 * i)
            for i, off in enumerate(offsets(seed=7, n=FIXED_TRIES, spread=0.005))]
    assert sum(o.fell for o in outs) <= 3, outs
    outs = [o for o in outs if not o.fell]
    nominal = kick.spec.distance
    mean = float(np.mean([o.distance for o in outs]))
    assert abs(mean - nominal) <= fixed_tolerance(nominal), (nominal, mean, outs)
    errors = [angle_error(o.direction, kick.spec.direction) for o in outs]
    assert abs(float(np.mean(errors))) < FIXED_DIRECTION_TOLERANCE, (np.degrees(errors), outs)


def test_fixed_distance_sets_are_named_for_their_distance_and_cover_3_m_up():
    sets = load_kick_sets([skill_path("kick.params")])
    names = fixed_distance_sets()
    for name in names:
        named = float(name[len("kick_"):-1])
        assert abs(named - sets[name]["distance"]) <= fixed_tolerance(named), (name, sets[name]["distance"])
    named = sorted(int(name[len("kick_"):-1]) for name in names)
    assert {3, 4} <= set(named), named
    # the long kick goes at least as far as every fixed-distance kick, the kick_ set nearly so
    assert all(sets["long_kick"]["distance"] >= sets[n]["distance"] for n in names)
    assert sets["kick"]["distance"] >= max(sets[n]["distance"] for n in names) - 0.5


# ------------------------------------------------------------- files and interface


def test_every_set_loads_with_both_feet_mirrored():
    kicks = keyframe_kicks(0)
    assert {"kick_left", "kick_right", "long_kick_left", "long_kick_right"} <= set(kicks)
    left, right = kicks["kick_left"].spec, kicks["kick_right"].spec
    assert left.ball[0] == right.ball[0] and left.ball[1] == -right.ball[1] > -1.0
    assert left.foot == "l" and right.foot == "r" and left.duration > 0.5
    assert 0.0 < left.ball[0] < 0.5  # SI: meters, not millimeters
    assert len(fixed_distance_sets()) >= 1


def test_a_later_parameter_file_overrides(tmp_path):
    extra = tmp_path / "cmaes.params"
    extra.write_text("kick_ball_x\t200\nkick_2m_k4_wait\t0.3\nkick_9m_distance\t9\n")
    kicks = keyframe_kicks(0, [extra])
    assert kicks["kick_left"].spec.ball[0] == pytest.approx(0.2)
    assert kicks["kick_2m_right"].spec.ball[0] == pytest.approx(0.2)  # inherits kick_
    base = kicks["kick_left"].skill
    # keyframes[6] is k4 (k0, ka, k1, k2, k3, k3b, k4, ...)
    assert kicks["kick_2m_left"].skill.duration == pytest.approx(base.duration - base.keyframes[6].wait + 0.3)
    assert kicks["kick_9m_left"].spec.distance == 9.0  # a new set from a later file


def test_malformed_kick_parameter_file_names_its_line(tmp_path):
    bad = tmp_path / "kick.params"
    bad.write_text("# tuned kick\nkick_ball_x\t160\n\nkick_k4_hip\tfast\n")
    with pytest.raises(ParamError, match=r"kick\.params:4: value of kick_k4_hip is not a number: 'fast'"):
        keyframe_kicks(0, [bad])
    bad.write_text("kick_ball_x\t160\nkick_k9_hip\t10\n")
    with pytest.raises(ParamError, match=r"kick\.params:2: unknown kick parameter 'kick_k9_hip'"):
        keyframe_kicks(0, [bad])


def test_malformed_kick_skill_names_its_line(tmp_path):
    text = open(skill_path("kick.skl")).read().splitlines()
    k = next(i for i, line in enumerate(text) if line.strip().startswith("settar"))
    text[k] = text[k].replace("settar", "settar lle9 5", 1)
    bad = tmp_path / "kick.skl"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(ParamError) as e:
        read_skills(bad)
    assert str(e.value).startswith(f"{bad}:{k + 1}:") and "'lle9'" in str(e.value)


# --------------------------------------------------------------------- the figures


HOLDS = (0.6, 0.7, 0.8, 0.9, 1.0, 1.1)  # s of standing before the kicks of `measure`


def measure(robot_type: int, name: str, tries: int, seed: int, holds: tuple[float, ...] = HOLDS) -> dict:
    """Distance mean/std, direction error and success rate of a kick over seeded ball offsets;
    try i stands `holds[i % len(holds)]` s before kicking (the stand rocks, so the kick
    starts at another phase of it)."""
    kick = keyframe_kicks(robot_type)[name]
    outs = [kick_once(kick, robot_type, off, hold=holds[i % len(holds)])
            for i, off in enumerate(offsets(seed, tries))]
    d = np.array([o.distance for o in outs])
    err = np.array([abs(angle_error(o.direction, kick.spec.direction)) for o in outs])
    moved = [o.direction for o in outs if o.distance > 0.5]  # where the ball went (rad, robot frame)
    heading = math.atan2(float(np.mean(np.sin(moved))), float(np.mean(np.cos(moved)))) if moved else math.nan
    return {"type": robot_type, "kick": name, "nominal": kick.spec.distance, "tries": tries,
            "distance_mean": round(float(d.mean()), 2), "distance_std": round(float(d.std()), 2),
            "direction_error_deg": round(float(np.degrees(err.mean())), 1),
            "direction_deg": round(math.degrees(heading), 1), "nominal_direction_deg":
                round(math.degrees(kick.spec.direction), 1),
            "success": sum(success(kick.spec, o) for o in outs) / tries,
            "falls": sum(o.fell for o in outs)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0")
    ap.add_argument("--tries", type=int, default=10)
    ap.add_argument("--kicks", default="", help="comma-separated set names (default: all)")
    ap.add_argument("--feet", default="left,right")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--holds", default=",".join(map(str, HOLDS)),
                    help="comma-separated s of standing before the kick")
    a = ap.parse_args()
    holds = tuple(float(x) for x in a.holds.split(","))
    for t in (int(x) for x in a.types.split(",")):
        sets = a.kicks.split(",") if a.kicks else sorted(
            load_kick_sets([skill_path("kick.params")]), key=lambda s: load_kick_sets(
                [skill_path("kick.params")])[s]["distance"])
        for s in sets:
            for foot in a.feet.split(","):
                print(json.dumps(measure(t, f"{s}_{foot}", a.tries, a.seed + t, holds)), flush=True)


if __name__ == "__main__":
    main()

"""The team's positioning walk (`agent.body.Body._walk_to` on `WalkTo` requests), run and scored.

Most of villa's falls in open play come while walking to a position, turning or
walking forward, not on the go-to-target course the walk sets were learned on
(`benchmarks.falls`). In play the position moves with the ball and the robot walks
on its own noisy pose estimate, ending facing the ball. This runs that: one villa
player (`agent.player`, percepts only) in PlayOn with one posture robot in a
corner; its decision layer is replaced by one request at a time, `WalkTo(target,
heading)`. Every `hop` s a new target is drawn `reach` m (uniform range) away at
any bearing, drifting at up to `drift` m/s, to be reached facing a random heading
(the ball's direction). Ground truth measures the run.

`position_run` serves the `position_walk` task, which learns the go-to-target set's
gait (the stand frozen, so the kicks keep theirs). Frames: the field frame; m, s, rad.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from agent.player import Player
from agent.requests import SkillRequest, Stand, WalkTo
from agent.strategy import TeamView
from agent.teamconfig import VILLA, TeamConfig
from models.geometry import rotate
from models.rules import PlayMode
from optimization.paramvec import walk_sets
from optimization.phases import FALL_PENALTY
from optimization.trials import place_player, solo_match
from optimization.types import TrialResult, Values
from skills.walk import WalkParams

AREA = (-10.0, 10.0, -7.0, 7.0)  # m, field frame: targets are kept inside (x0, x1, y0, y1)
START = (-4.0, 0.0)  # m, field frame
# The stand: the kicks and getups were tuned from it, so this task leaves it as it is.
STAND = ("walk_height", "default_com_pos_x", "fwd_offset", "pid_tilt", "pid_roll", "joint_kp")
GAIT = ("max_step_size_x", "max_step_size_y", "max_step_size_angle", "shift_amount", "step_height",
        "fraction_still", "fraction_on_ground", "fraction_moving", "fraction_in_air", "phase_length",
        "pid_step_size_x", "pid_step_size_y", "pid_step_size_rot", "max_normal_com_error",
        "max_acceptable_com_error", "fwd_offset_factor", "swing_ankle_offset", "pid_arm_x",
        "swing_steepness", "gyro_pitch", "gyro_pitch_walk", "gyro_roll")


class Positioner(Player):
    """The villa player with one request: `request` (stand while it is None)."""

    request: WalkTo | None = None

    def decide(self, view: TeamView) -> SkillRequest:
        return Stand() if self.request is None else self.request


@dataclass(frozen=True)
class PositionRun:
    """What one run measured (ground truth): the distance gained toward each hop's
    target at the hop's end (m), summed; the hops; the falls."""

    gained: float
    hops: int
    falls: int


def position_run(robot_type: int, rng: np.random.Generator, seed: int, seconds: float = 30.0,
                 hop: tuple[float, float] = (1.5, 3.0), reach: tuple[float, float] = (0.5, 4.0),
                 drift: float = 0.4, config: TeamConfig = VILLA,
                 sets: Mapping[str, WalkParams] | None = None) -> PositionRun:
    """`seconds` of walking to moving targets; `sets` replace the body's walk sets of those
    names (the optimization's candidates)."""

    m = solo_match(Positioner, robot_type, seed, 10 * seconds, config, sets)
    w = m.world
    agent = m.agents[0]
    place_player(m, 0, *START, float(rng.uniform(-math.pi, math.pi)))
    w.place_robot(1, 14.5, 9.0, math.pi)  # their goalie out of the way
    w.place_ball((14.0, -9.0))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    t_end = w.time + seconds
    gained, hops = 0.0, 0
    while w.time < t_end - 1e-9:
        here = np.asarray(w.player_pose(0)[:2])
        d, a = rng.uniform(*reach), rng.uniform(-math.pi, math.pi)
        target = np.clip(here + rotate(d, 0.0, a), AREA[::2], AREA[1::2])
        v = np.array(rotate(drift * rng.uniform(0.0, 1.0), 0.0, rng.uniform(-math.pi, math.pi)))
        face = float(rng.uniform(-math.pi, math.pi))
        d0 = float(np.hypot(*(target - here)))
        t0, length = w.time, min(float(rng.uniform(*hop)), t_end - w.time)
        while w.time - t0 < length - 1e-9:
            now = np.clip(target + v * (w.time - t0), AREA[::2], AREA[1::2])
            agent.request = WalkTo(float(now[0]), float(now[1]), heading=face)
            m.step()
        end = np.clip(target + v * (w.time - t0), AREA[::2], AREA[1::2])
        gained += d0 - float(np.hypot(*(end - np.asarray(w.player_pose(0)[:2]))))
        hops += 1
    return PositionRun(gained, hops, int(m.referee.falls["L"]))


@dataclass(frozen=True)
class PositionWalkTask:
    """Learn the go-to-target set's gait (`GAIT`; the stand frozen) on `seconds` of the
    team's positioning walk (`position_run`). Fitness: the distance gained toward the
    targets (m) minus `fall_penalty` a fall."""

    name: str = "position_walk"
    robot_type: int = 0
    seconds: float = 30.0
    fall_penalty: float = 2.0 * FALL_PENALTY
    sets: tuple[str, ...] = ("go_to_target",)

    def __post_init__(self) -> None:
        if self.seconds <= 0 or self.fall_penalty < 0:
            raise ValueError(f"seconds > 0 and fall_penalty >= 0, not {self.seconds}, {self.fall_penalty}")

    @property
    def optimize(self) -> dict[str, tuple[str, ...] | None]:
        return {"go_to_target": GAIT}

    @property
    def worst(self) -> float:
        """A fall every 5 s, no ground gained."""
        return -self.fall_penalty * self.seconds / 5.0

    def trial(self, values: Values, seed: int) -> TrialResult:
        learned = {"go_to_target": walk_sets(values)["go_to_target"]}
        r = position_run(self.robot_type, np.random.default_rng(seed), seed, self.seconds, sets=learned)
        return TrialResult(float(r.gained - self.fall_penalty * r.falls),
                           {"falls": r.falls, "gained": round(r.gained, 3), "hops": r.hops})


def position_walk(robot_type: int = 0, seconds: float = 30.0,
                  fall_penalty: float = 2.0 * FALL_PENALTY) -> PositionWalkTask:
    return PositionWalkTask(robot_type=robot_type, seconds=seconds, fall_penalty=fall_penalty)

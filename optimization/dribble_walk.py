"""The team's dribble (walking through the ball, `agent.body.Body._dribble`), run and scored.

One run is a match in PlayOn of one villa player (`agent.player`, percepts only)
and one posture robot standing in a corner. The ball lies at (-6, 0) plus a
little noise, the target `distance` m away in a direction within +-`spread`
deg of the field's +x; the player starts `start` m behind the ball, facing the
target, and stands until its world model has the ball within 0.2 m (untimed:
it still believes the kickoff's ball at the center). Its decision layer is
replaced by one request, `Dribble(target)`. Ground truth measures the run.

`dribble_run` serves `benchmarks.dribble` and the `dribble_walk` task, which
learns the "position_to_dribble" walk set (the set the body walks through the
ball with) for issue 47's goal: the ball kept within `HOLD` m of the robot at
at least 0.35 m/s. Frames: the field frame; m, s, rad.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from agent.player import Player
from agent.requests import Dribble, SkillRequest, Stand
from agent.strategy import TeamView
from agent.teamconfig import VILLA, TeamConfig
from models.rules import PlayMode
from optimization.paramvec import walk_sets
from optimization.phases import FALL_PENALTY
from optimization.trials import place_player, solo_match
from optimization.types import TrialResult, Values
from skills.walk import WalkParams

HOLD = 1.0  # m: the ball within this of the torso counts as held
FIND_LIMIT = 15.0  # s standing to find the placed ball before the clock starts
BALL_START = (-6.0, 0.0)  # m, field frame
DRIBBLE_SET_TEAM = replace(VILLA, dribble_set="position_to_dribble")  # the team the task learns for


class Dribbler(Player):
    """The villa player with one request: dribble to `target` (team frame, m); stand
    while it is None."""

    target: tuple[float, float] | None = None

    def decide(self, view: TeamView) -> SkillRequest:
        return Stand() if self.target is None else Dribble(self.target)


@dataclass(frozen=True)
class DribbleRun:
    """What one run measured (ground truth). Times in s from the clock's start."""

    done: float | None  # when the ball's progress reached the distance, None if never
    touch: float | None  # the first touch (the ball moved 5 cm), None if never
    gap: float  # m: the ball's largest distance from the torso after the first touch
    off_line: float  # m: the ball's largest distance from the target line after the first touch
    away: float  # s after the first touch with the ball farther than HOLD from the torso
    falls: int
    progress: float  # m along the target line at the end
    distance: float  # m the ball was to go

    @property
    def speed(self) -> float | None:
        """m/s over the distance from the first touch, for a done run."""
        return None if self.done is None else self.distance / (self.done - self.touch)


def dribble_run(robot_type: int, rng: np.random.Generator, seed: int, distance: float = 10.0,
                start: float = 0.5, spread: float = 30.0, limit: float = 60.0,
                config: TeamConfig = VILLA, sets: Mapping[str, WalkParams] | None = None) -> DribbleRun:
    """Dribble `distance` m within `limit` s; `sets` replace the body's walk sets of those
    names (the optimization's candidates)."""

    m = solo_match(Dribbler, robot_type, seed, 10 * limit, config, sets)
    w = m.world
    ball = np.array(BALL_START) + rng.normal(0.0, 0.1, 2)
    a = math.radians(rng.uniform(-spread, spread))
    u = np.array([math.cos(a), math.sin(a)])
    agent = m.agents[0]
    x, y = (ball - start * u).tolist()
    place_player(m, 0, x, y, a)
    w.place_robot(1, 14.5, 9.0, math.pi)  # their goalie out of the way
    w.place_ball(tuple(ball))
    m.referee.set_play_mode(PlayMode.PLAY_ON)
    # Untimed: standing, the player forgets the kickoff's ball and finds this one.
    end = w.time + FIND_LIMIT
    while w.time < end and not (agent.world.ball_filter.initialized
                                and float(np.hypot(*(agent.world.ball_filter.position - ball))) < 0.2):
        m.step()
    agent.target = tuple((ball + distance * u).tolist())
    t0, touch, done = w.time, None, None
    gap = off = away = 0.0
    last = t0
    while w.time - t0 < limit:
        m.step()
        b = w.ball_position()[:2]
        rel = b - ball
        if touch is None and float(np.hypot(*rel)) > 0.05:
            touch = w.time - t0
        if touch is not None:
            g = float(np.hypot(*(b - w.player_pose(0)[:2])))
            gap = max(gap, g)
            if g > HOLD:
                away += w.time - last
            off = max(off, abs(float(u[0] * rel[1] - u[1] * rel[0])))
        last = w.time
        if float(rel @ u) >= distance:
            done = w.time - t0
            break
    return DribbleRun(done, touch, gap, off, away, int(m.referee.falls["L"]),
                      float((w.ball_position()[:2] - ball) @ u), distance)


@dataclass(frozen=True)
class DribbleWalkTask:
    """Learn the walk set the body dribbles with ("position_to_dribble"; go-to-target,
    which lines up behind the ball, frozen): `seconds` of the team's dribble toward a
    target 10 m away (`dribble_run`). Fitness: the ball's progress along the target
    line (m) minus `away_cost` (m/s) for each second the ball is farther than HOLD
    from the torso, minus FALL_PENALTY a fall. A push that sends the ball away and
    chases it at `away_cost` m/s gains nothing."""

    name: str = "dribble_walk"
    robot_type: int = 0
    seconds: float = 20.0
    away_cost: float = 0.3
    spread: float = 30.0
    sets: tuple[str, ...] = ("go_to_target", "position_to_dribble")

    def __post_init__(self) -> None:
        if self.seconds <= 0 or self.away_cost < 0:
            raise ValueError(f"seconds > 0 and away_cost >= 0, not {self.seconds}, {self.away_cost}")

    @property
    def optimize(self) -> dict[str, tuple[str, ...] | None]:
        return {"position_to_dribble": None}

    @property
    def worst(self) -> float:
        return -2.0 * FALL_PENALTY - self.away_cost * self.seconds

    def trial(self, values: Values, seed: int) -> TrialResult:
        learned = {"position_to_dribble": walk_sets(values)["position_to_dribble"]}
        rng = np.random.default_rng(seed)
        r = dribble_run(self.robot_type, rng, seed, limit=self.seconds, spread=self.spread,
                        config=DRIBBLE_SET_TEAM, sets=learned)
        fitness = r.progress - self.away_cost * r.away - FALL_PENALTY * r.falls
        return TrialResult(float(fitness), {"falls": r.falls, "progress": round(r.progress, 3),
                                            "away_s": round(r.away, 2), "gap": round(r.gap, 2),
                                            "touch_s": r.touch})


def dribble_walk(robot_type: int = 0, seconds: float = 20.0, away_cost: float = 0.3) -> DribbleWalkTask:
    return DribbleWalkTask(robot_type=robot_type, seconds=seconds, away_cost=away_cost)

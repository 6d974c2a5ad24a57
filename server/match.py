"""The 20 ms match loop: percepts out, actions in, physics, referee.

Agents are plain objects with `act(percept) -> Action`, made by a team's
factory `(side, unum, robot_type, seed) -> agent`. The loop gives each agent
only its own `Percept`; nothing else of the world reaches it.
"""

from __future__ import annotations

import logging
import math
import sys
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from models import nao
from models.messages import Action, HeardMessage, Percept
from models.rules import (
    BEAM_NOISE_ANGLE,
    BEAM_NOISE_XY,
    HALF_TIME,
    PLAY_MODES,
    TEAM_SIZE,
    VISION_PERIOD,
    PlayMode,
    Side,
    robot_types_problem,
)
from models.scene import Lineup, default_types
from server.hearing import Hearing, say_error
from server.log import LogRecorder, MatchLog
from server.referee import Referee
from server.sensors import Proprioception, percepts
from server.vision import VisionSensor
from server.world import PhysicsDiverged, World

log = logging.getLogger(__name__)


class Agent(Protocol):
    def act(self, percept: Percept) -> Action: ...


AgentFactory = Callable[[str, int, int, int], Agent]

__all__ = ["Agent", "AgentFactory", "Match", "MatchResult", "PhysicsDiverged", "Timing", "lineup_for",
           "team_types"]


def last_line(exc: BaseException) -> str:
    """An exception as one line: its type and the last line of its message."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[-1]}" if text else type(exc).__name__


@dataclass
class Timing:
    """Wall time spent per part of the loop (s)."""

    physics: float = 0.0
    sensors: float = 0.0
    vision: float = 0.0  # part of sensors
    effectors: float = 0.0
    referee: float = 0.0
    agents: float = 0.0
    log: float = 0.0

    def as_dict(self) -> dict[str, float]:
        return {k: round(v, 3) for k, v in self.__dict__.items()}


@dataclass
class MatchResult:
    score: dict[str, int]
    events: list[dict]
    stats: dict[str, dict]
    lineup: dict[str, list[int]]
    teams: dict[str, str]
    seed: int
    half_time: float
    game_time: float
    wall_time: float
    timing: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {
            "score": self.score, "goal_difference": self.score["L"] - self.score["R"],
            "teams": self.teams, "lineup": self.lineup, "seed": self.seed,
            "half_time": self.half_time, "game_time": round(self.game_time, 3),
            "wall_time": round(self.wall_time, 3),
            "real_time_factor": round(self.game_time / max(self.wall_time, 1e-9), 2),
            "stats": self.stats, "timing": self.timing, "events": self.events,
        }


def team_types(factory: AgentFactory, n: int, name: str = "team") -> tuple[int, ...]:
    """Robot types of uniform numbers 1..n: those the team's factory chooses (its
    `robot_types`, as a league agent names its type when it joins), else the default
    (`models.scene.default_types`). ValueError, naming the team, for a bad choice or one
    that breaks the league's rule for a full team (`models.rules.robot_types_problem`)."""
    chosen = getattr(factory, "robot_types", None)
    if chosen is None:
        return default_types(n)
    chosen = tuple(chosen)
    if len(chosen) < n:
        raise ValueError(f"team {name!r} chooses {len(chosen)} robot types for {n} players")
    for t in chosen[:n]:
        if isinstance(t, bool) or not isinstance(t, (int, np.integer)) or t not in nao.TYPES:
            raise ValueError(f"team {name!r} chooses robot type {t!r}; valid types are 0, 1, 2, 3, 4")
    types = tuple(int(t) for t in chosen[:n])
    problem = robot_types_problem(types)
    if problem is not None:
        raise ValueError(f"team {name!r} chooses robot types {list(types)}: {problem}")
    return types


def lineup_for(left: AgentFactory, right: AgentFactory, n_left: int, n_right: int,
               names: tuple[str, str] = ("left", "right")) -> Lineup:
    """The line-up of two teams of n_left and n_right players, each with the robot types
    it chooses (`team_types`)."""
    return Lineup(team_types(left, n_left, names[0]), team_types(right, n_right, names[1]))


class Match:
    """One match between two teams of agents."""

    def __init__(self, left: AgentFactory, right: AgentFactory, lineup: Lineup | None = None,
                 half_time: float = HALF_TIME, seed: int = 0, record: bool = False,
                 team_names: tuple[str, str] = ("left", "right")) -> None:
        if half_time <= 0:
            raise ValueError(f"half time must be positive, got {half_time}")
        if lineup is None:  # each team's own choice, held to the rule by team_types
            lineup = lineup_for(left, right, TEAM_SIZE, TEAM_SIZE, team_names)
        else:
            for name, types in zip(team_names, (lineup.left, lineup.right)):
                problem = robot_types_problem(types)
                if problem is not None:
                    raise ValueError(f"team {name!r} plays robot types {list(types)}: {problem}")
        self.lineup = lineup
        if not self.lineup.left or not self.lineup.right:
            raise ValueError("a match needs 1 to 11 players a side")
        self.seed = seed
        self.half_time = half_time
        self.team_names = team_names
        seeds = np.random.SeedSequence(seed).spawn(4)
        rng_vision, rng_hear, self.rng_beam, rng_agents = (np.random.default_rng(s) for s in seeds)
        self.world = World(self.lineup)
        self.referee = Referee(self.world, half_time=half_time)
        self.proprio = Proprioception(self.world)
        self.vision = VisionSensor(self.world, rng_vision)
        self.hearing = Hearing(self.world.side_of, rng_hear)
        agent_seeds = rng_agents.integers(0, 2**31 - 1, len(self.world.players))
        self.agents: list[Agent] = []
        for p, s in zip(self.world.players, agent_seeds):
            factory = left if p.side == Side.LEFT else right
            self.agents.append(factory(p.side, p.unum, p.robot_type, int(s)))
        self.n_joints = [len(p.joint_qpos) for p in self.world.players]
        self.max_speed = [np.array([j.max_speed for j in nao.joints(p.robot_type)])
                          for p in self.world.players]
        self._max_speed = np.concatenate(self.max_speed)
        self._act_index = np.concatenate([p.actuators for p in self.world.players])
        # Agents that crashed (raised, or answered with a malformed action): index -> reason.
        # Like the league's crashed agents, their robots get zero joint velocities from then on.
        self.crashed: dict[int, str] = {}
        self._idle = [Action(np.zeros(n)) for n in self.n_joints]
        self.cycle = 0
        self.heard: dict[int, list[HeardMessage]] = {}
        self.warnings: dict[int, list[str]] = {}
        self.targets = np.full((len(self.world.players), 2), np.nan)
        self.timing = Timing()
        self.recorder = (LogRecorder(self.world.xml, [p.name for p in self.world.players])
                         if record else None)
        self._mode_index = {m: k for k, m in enumerate(PLAY_MODES)}

    # ------------------------------------------------------------------ one cycle

    def percepts(self) -> list[Percept]:
        """Every player's percept for the current cycle."""
        ref = self.referee
        vision = {}
        if self.cycle % VISION_PERIOD == 0:
            t0 = wallclock.perf_counter()
            vision = self.vision.see_all()
            self.timing.vision += wallclock.perf_counter() - t0
        return percepts(self.world, self.proprio, vision, ref.game_time, ref.mode.value,
                        (ref.score["L"], ref.score["R"]), self.heard, self.warnings)

    def step(self) -> None:
        """Run one 20 ms cycle."""
        w, ref, t = self.world, self.referee, self.timing
        t0 = wallclock.perf_counter()
        percepts = self.percepts()
        t1 = wallclock.perf_counter()
        actions = self._act(percepts)
        t2 = wallclock.perf_counter()
        ctrl, said, warnings = self._apply(actions)
        t3 = wallclock.perf_counter()
        touches = w.step(ctrl)
        w.check_physics()
        t4 = wallclock.perf_counter()
        ref.update(touches)
        t5 = wallclock.perf_counter()
        self.heard = self.hearing.route(self.cycle, w.time, said, w.torso_positions(),
                                        w.headings()) if said else {}
        self.warnings = warnings
        self.cycle += 1
        t6 = wallclock.perf_counter()
        if self.recorder is not None:
            self.recorder.record(w.time, ref.game_time, w.data.qpos, self._mode_index[ref.mode],
                                 (ref.score["L"], ref.score["R"]), self.targets)
        t7 = wallclock.perf_counter()
        t.sensors += (t1 - t0) + (t6 - t5)
        t.agents += t2 - t1
        t.effectors += t3 - t2
        t.physics += t4 - t3
        t.referee += t5 - t4
        t.log += t7 - t6

    def _act(self, percepts: list[Percept]) -> list[Action]:
        """Every agent's action; a crashed agent (now or before) is idle."""
        actions = []
        crashed = self.crashed
        for i, (agent, pc) in enumerate(zip(self.agents, percepts)):
            if crashed and i in crashed:
                actions.append(self._idle[i])
                continue
            try:
                actions.append(agent.act(pc))
            except Exception as exc:  # noqa: BLE001 - a crashed agent must not stop the match
                self._crash(i, f"act raised {last_line(exc)}")
                actions.append(self._idle[i])
        return actions

    def _crash(self, i: int, reason: str) -> None:
        """Agent i crashed: its robot gets zero joint velocities from now on, and an event says so."""
        p = self.world.players[i]
        self.crashed[i] = reason
        log.warning("%s crashed: %s", p.name, reason)
        self.referee._event("agent_crashed", p.side, p.unum, reason)

    def _apply(self, actions: list[Action]) -> tuple[np.ndarray, dict[int, str], dict[int, list[str]]]:
        """Effectors: joint velocities, says and beams. An agent whose action is malformed
        (not an Action, or joint velocities of the wrong length or not finite) has crashed;
        a bad say is dropped with a warning, as the league does."""
        w = self.world
        said: dict[int, str] = {}
        warnings: dict[int, list[str]] = {}
        try:  # the usual case: every agent sends the right number of finite velocities
            ok = all(type(a) is Action for a in actions)
            if ok:
                jv = [a.joint_velocities for a in actions]
                v = np.concatenate(jv, dtype=float)
                ok = v.ndim == 1 and [len(x) for x in jv] == self.n_joints and bool(np.isfinite(v).all())
        except (AttributeError, TypeError, ValueError):
            ok = False
        if not ok:
            actions = list(actions)
            for i, a in enumerate(actions):
                reason = self._malformed(i, a)
                if reason is not None:
                    self._crash(i, reason)
                    actions[i] = self._idle[i]
            v = np.concatenate([np.asarray(a.joint_velocities, dtype=float) for a in actions])
        beam_ok = None
        self.targets.fill(np.nan)
        for i, a in enumerate(actions):
            if a.say is not None:
                err = say_error(a.say)
                if err is None:
                    said[i] = a.say
                else:
                    log.warning("%s: %s", w.players[i].name, err)
                    warnings.setdefault(i, []).append(err)
            if a.beam is not None:
                if beam_ok is None:
                    beam_ok = self.referee.beam_allowed()
                if beam_ok:
                    try:
                        self._beam(i, a.beam)
                    except (TypeError, ValueError) as exc:
                        self._crash(i, f"malformed beam: {last_line(exc)}")
                else:
                    warnings.setdefault(i, []).append(f"beam refused in {self.referee.mode.value}")
            if a.annotations and a.annotations.get("target") is not None:
                self.targets[i] = a.annotations["target"]
        ctrl = np.zeros(w.model.nu)
        ctrl[self._act_index] = np.maximum(np.minimum(v, self._max_speed), -self._max_speed)
        return ctrl, said, warnings

    def _malformed(self, i: int, a: object) -> str | None:
        """Why agent i's action is malformed, or None when it is fine."""
        if not isinstance(a, Action):
            return f"act returned {type(a).__name__}, not an Action"
        n = self.n_joints[i]
        try:
            v = np.asarray(a.joint_velocities, dtype=float)
        except (TypeError, ValueError):
            return f"joint_velocities must be {n} finite numbers; got {type(a.joint_velocities).__name__}"
        if v.shape != (n,):
            return f"joint_velocities must be {n} finite numbers; got shape {v.shape}"
        if not np.all(np.isfinite(v)):
            return f"joint_velocities must be {n} finite numbers; got a non-finite value"
        return None

    def _beam(self, i: int, beam: tuple[float, float, float]) -> None:
        """Beam player i to (x, y, heading) of its team frame, with the league's noise."""
        w = self.world
        x, y, th = (float(b) for b in beam)
        if not all(math.isfinite(b) for b in (x, y, th)):
            return
        if w.players[i].side == Side.RIGHT:
            x, y, th = -x, -y, th + math.pi
        x += self.rng_beam.uniform(-BEAM_NOISE_XY, BEAM_NOISE_XY)
        y += self.rng_beam.uniform(-BEAM_NOISE_XY, BEAM_NOISE_XY)
        th += self.rng_beam.uniform(-BEAM_NOISE_ANGLE, BEAM_NOISE_ANGLE)
        x = float(np.clip(x, -15.0, 15.0))
        y = float(np.clip(y, -10.0, 10.0))
        w.place_robot(i, x, y, th)
        w.settle_height(i)

    # -------------------------------------------------------------------- running

    def run(self, progress: bool = False, max_cycles: int | None = None) -> MatchResult:
        """Play until GameOver (or max_cycles) and return the result."""
        start = wallclock.perf_counter()
        total = 2 * self.half_time
        bar = None
        if progress:
            from tqdm import tqdm
            bar = tqdm(total=round(total), unit="game s", file=sys.stderr, dynamic_ncols=True,
                       mininterval=0.2 if sys.stderr.isatty() else 10.0,  # logs get a line per 10 s
                       bar_format="{l_bar}{bar}| {n:.0f}/{total:.0f} game s [{elapsed}<{remaining}{postfix}]")
        shown = 0.0
        while self.referee.mode != PlayMode.GAME_OVER:
            if max_cycles is not None and self.cycle >= max_cycles:
                break
            self.step()
            if bar is not None and (self.cycle % 50 == 0 or self.referee.mode == PlayMode.GAME_OVER):
                g = self.referee.game_time
                bar.update(g - shown)
                shown = g
                bar.set_postfix_str(f"{self.referee.score['L']}:{self.referee.score['R']}",
                                    refresh=False)
        if bar is not None:
            bar.close()
        return self.result(wallclock.perf_counter() - start)

    def result(self, wall_time: float) -> MatchResult:
        ref = self.referee
        stats = {}
        total_possession = sum(ref.possession.values()) or 1.0
        for team in Side:
            stats[team] = {
                "possession_time": round(ref.possession[team], 2),
                "possession_share": round(ref.possession[team] / total_possession, 3),
                "ball_touches": ref.touches[team],
                "falls": ref.falls[team],
                "territory": round(ref.territory(team), 3),
            }
        return MatchResult(
            score=dict(ref.score), events=[e.to_dict() for e in ref.events], stats=stats,
            lineup={"L": list(self.lineup.left), "R": list(self.lineup.right)},
            teams={"L": self.team_names[0], "R": self.team_names[1]}, seed=self.seed,
            half_time=self.half_time, game_time=ref.game_time, wall_time=wall_time,
            timing=self.timing.as_dict(),
        )

    def match_log(self) -> MatchLog:
        if self.recorder is None:
            raise RuntimeError("this match was not recorded (record=False)")
        return self.recorder.finish([e.to_dict() for e in self.referee.events])

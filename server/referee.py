"""The league's referee (rcssserver3d's SoccerRuleAspect), on ground truth.

Every decision is an `Event`. The referee moves things only as the rules let
it: the ball to its restart spot, players out of places they may not be (too
close at restarts, a fourth defender in the penalty area, a player down too
long). The left team ('L') attacks +x.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from models import field
from models.rules import (
    BEFORE_KICKOFF_TIME,
    CYCLE,
    DROP_BALL_TIME,
    FALLEN_REPOSITION_TIME,
    FREE_KICK_DISTANCE,
    GOAL_KICK_DISTANCE,
    GOAL_PAUSE,
    GOALIE_FALLEN_REPOSITION_TIME,
    GOALIE_NOT_STANDING_REPOSITION_TIME,
    HALF_TIME,
    MAX_IN_PENALTY_AREA,
    NOT_STANDING_REPOSITION_TIME,
    PlayMode,
    Side,
    restart,
)
from server._kernels import fallen_rules, penalty_area_rules
from server.world import World

PM = PlayMode
RESTARTS = {PM.KICK_OFF_LEFT, PM.KICK_OFF_RIGHT, PM.KICK_IN_LEFT, PM.KICK_IN_RIGHT,
            PM.CORNER_KICK_LEFT, PM.CORNER_KICK_RIGHT, PM.GOAL_KICK_LEFT, PM.GOAL_KICK_RIGHT}
LIVE = RESTARTS | {PM.PLAY_ON}
GOALIE = 1  # uniform number of the goalie

# Torso tilt thresholds on the z component of the torso's up axis.
DOWN_UP_Z = 0.5  # below: lying (down); a fall is counted once until the player stands again
STANDING_UP_Z = 0.7  # above, with the torso high enough: standing


@dataclass
class Event:
    """One referee decision. time is game time (s); team 'L'/'R'; player a uniform number."""

    time: float
    kind: str
    team: str | None = None
    player: int | None = None
    detail: str = ""

    def to_dict(self) -> dict:
        return asdict(self)


class Referee:
    """Play modes, score, restarts and the league's player rules."""

    def __init__(self, world: World, half_time: float = HALF_TIME, first_kickoff: Side = Side.LEFT) -> None:
        self.world = world
        self.half_time = half_time
        self.first_kickoff = Side(first_kickoff)
        n = len(world.players)
        self.mode = PM.BEFORE_KICK_OFF
        self.mode_since = 0.0  # server time the mode began
        self.game_time = 0.0
        self.half = 1
        self.score = {"L": 0, "R": 0}
        self.events: list[Event] = []
        self.last_touch: int | None = None
        self.kickoff_taker: int | None = None
        self.kickoff_pending = False  # the kickoff's second touch has not happened yet
        self.next_kickoff = self.first_kickoff
        self.down_since = np.full(n, np.nan)
        self.unsteady_since = np.full(n, np.nan)
        self.fallen = np.zeros(n, dtype=bool)
        self.area_since = np.full(n, np.nan)
        self.possession = {"L": 0.0, "R": 0.0}
        self.play_on_time = 0.0  # s of play on ...
        self.ball_x_time = 0.0  # ... and the ball's field x integrated over it (m s): territory
        self.touches = {"L": 0, "R": 0}
        self.falls = {"L": 0, "R": 0}
        self.is_goalie = world.unum_of == GOALIE
        self._own_sign = np.where(world.side_of == Side.LEFT, -1.0, 1.0)  # sign of x in the own half
        self._nobody = np.zeros(n, dtype=bool)
        self._standing_z = 0.6 * world.heights  # m, torso height above which a player stands
        self._down_limit = np.where(self.is_goalie, GOALIE_FALLEN_REPOSITION_TIME,
                                    FALLEN_REPOSITION_TIME)
        self._unsteady_limit = np.where(self.is_goalie, GOALIE_NOT_STANDING_REPOSITION_TIME,
                                        NOT_STANDING_REPOSITION_TIME)
        self._new_falls = np.empty(n, dtype=np.int64)  # players, written by fallen_rules
        self._late = np.empty(n, dtype=np.int64)
        self._inside = np.zeros(n, dtype=bool)  # in the own penalty area, by penalty_area_rules

    # ------------------------------------------------------------------ helpers

    def _event(self, kind: str, team: str | None = None, player: int | None = None,
               detail: str = "") -> None:
        self.events.append(Event(round(self.game_time, 3), kind, team, player, detail))

    def _set_mode(self, mode: PlayMode, detail: str = "") -> None:
        self.mode = mode
        self.mode_since = self.world.time
        self._event("play_mode", mode.team, None, mode.value + (f": {detail}" if detail else ""))

    def set_play_mode(self, mode: PlayMode) -> None:
        """Trainer command: switch to `mode` now (a kickoff in progress is forgotten)."""
        self.kickoff_pending = False
        self.kickoff_taker = None
        self._set_mode(PlayMode(mode), "trainer")

    def beam_allowed(self) -> bool:
        """Players may beam before kickoff and while a goal is celebrated."""
        return self.mode in (PM.BEFORE_KICK_OFF, PM.GOAL_LEFT, PM.GOAL_RIGHT)

    def _unum(self, i: int | None) -> int | None:
        return None if i is None else int(self.world.unum_of[i])

    def _team(self, i: int) -> Side:
        return Side(str(self.world.side_of[i]))

    def _move(self, i: int, x: float, y: float, why: str) -> None:
        w = self.world
        x = float(np.clip(x, -field.HALF_LENGTH, field.HALF_LENGTH))
        y = float(np.clip(y, -field.HALF_WIDTH - 0.5, field.HALF_WIDTH + 0.5))
        heading = 0.0 if self._team(i) == Side.LEFT else math.pi
        w.place_robot(i, x, y, heading)
        w.settle_height(i)
        self.down_since[i] = np.nan
        self.unsteady_since[i] = np.nan
        self._event("reposition", self._team(i), self._unum(i), why)

    def _kickoff(self, team: str) -> None:
        self.world.place_ball((0.0, 0.0))
        self.kickoff_taker = None
        self.kickoff_pending = True
        self._set_mode(restart("kick_off", team))

    # --------------------------------------------------------------- main update

    def update(self, touches: list[int]) -> None:
        """Apply the rules after one physics cycle; `touches` are the players that
        started touching the ball during it, in order."""
        if self.mode == PM.GAME_OVER:
            return
        w = self.world
        if self.mode != PM.BEFORE_KICK_OFF:
            self.game_time += CYCLE
        for i in touches:
            self._touch(i)
        if self.mode in LIVE:
            self._check_ball()
        elapsed = w.time - self.mode_since
        if self.mode == PM.BEFORE_KICK_OFF and elapsed >= BEFORE_KICKOFF_TIME - 1e-9:
            self._kickoff(self.next_kickoff)
        elif self.mode in (PM.GOAL_LEFT, PM.GOAL_RIGHT) and elapsed >= GOAL_PAUSE - 1e-9:
            self._kickoff(self.mode.team.other)
        elif self.mode in RESTARTS and elapsed >= DROP_BALL_TIME - 1e-9:
            self._event("drop_ball", self.mode.team, None, f"no touch for {DROP_BALL_TIME:g} s")
            self.kickoff_pending = False  # a dropped ball is no kickoff: anyone may score from it
            self._set_mode(PM.PLAY_ON)
        if self.half == 1 and self.game_time >= self.half_time - 1e-9:
            self.half = 2
            self._event("half_time")
            self.next_kickoff = self.first_kickoff.other
            w.place_ball((0.0, 0.0))
            self._set_mode(PM.BEFORE_KICK_OFF)
        elif self.half == 2 and self.game_time >= 2 * self.half_time - 1e-9:
            self._event("game_over", None, None, f"{self.score['L']}:{self.score['R']}")
            self._set_mode(PM.GAME_OVER)
            return
        if self.mode in RESTARTS:
            self._keep_away()
        if self.mode == PM.PLAY_ON:
            self._illegal_defense()
            self.play_on_time += CYCLE
            self.ball_x_time += float(self.world.ball_position()[0]) * CYCLE
            if self.last_touch is not None:
                self.possession[self._team(self.last_touch)] += CYCLE
        self._fallen()

    def territory(self, team: str) -> float:
        """The ball's mean field x over play on, toward `team`'s attacking goal (m; the
        left team attacks +x): how far into the opponents' half play was, on average."""
        x = self.ball_x_time / self.play_on_time if self.play_on_time else 0.0
        return x if team == "L" else -x

    def _touch(self, i: int) -> None:
        team = self._team(i)
        self.touches[team] += 1
        self.last_touch = i
        if self.kickoff_pending:
            if self.kickoff_taker is None:
                self.kickoff_taker = i
            elif i != self.kickoff_taker:
                self.kickoff_pending = False
        if self.mode in RESTARTS:
            self._set_mode(PM.PLAY_ON, f"touched by {team}{self._unum(i)}")

    def _check_ball(self) -> None:
        w = self.world
        x, y, z = w.ball_position().tolist()
        r = field.BALL_RADIUS
        last = self.last_touch
        last_team = self._team(last) if last is not None else None
        if abs(x) > field.HALF_LENGTH + r:
            sx = 1.0 if x > 0 else -1.0
            attackers = Side.LEFT if x > 0 else Side.RIGHT
            defenders = attackers.other
            if abs(y) < field.GOAL_WIDTH / 2 and z < field.GOAL_HEIGHT:
                if self.kickoff_pending:
                    self._event("no_goal", attackers, self._unum(last),
                                "the kickoff was not touched by a second player")
                    self._goal_kick(defenders, sx)
                    return
                self.score[attackers] += 1
                self._event("goal", attackers, self._unum(last) if last_team == attackers else None,
                            f"{self.score['L']}:{self.score['R']}"
                            + ("" if last_team == attackers else " (own goal)"))
                self.next_kickoff = defenders
                w.place_ball((sx * (field.HALF_LENGTH + 0.3), 0.0))
                self._set_mode(restart("goal", attackers))
                return
            if last_team == defenders:
                self._event("out", defenders, self._unum(last), "over the end line")
                w.place_ball((sx * field.HALF_LENGTH, math.copysign(field.HALF_WIDTH, y)))
                self._set_mode(restart("corner_kick", attackers))
            else:
                self._event("out", last_team, self._unum(last), "over the end line")
                self._goal_kick(defenders, sx)
        elif abs(y) > field.HALF_WIDTH + r:
            team = last_team.other if last_team else (Side.RIGHT if x < 0 else Side.LEFT)
            self._event("out", last_team, self._unum(last), "over the side line")
            w.place_ball((float(np.clip(x, -field.HALF_LENGTH, field.HALF_LENGTH)),
                          math.copysign(field.HALF_WIDTH, y)))
            self._set_mode(restart("kick_in", team))

    def _goal_kick(self, team: str, sx: float) -> None:
        self.kickoff_pending = False
        self.world.place_ball((sx * (field.HALF_LENGTH - GOAL_KICK_DISTANCE), 0.0))
        self._set_mode(restart("goal_kick", team))

    # ------------------------------------------------------------ player rules

    def _keep_away(self) -> None:
        """At restarts, keep the other team FREE_KICK_DISTANCE from the ball (out of
        the penalty area at a goal kick; in its own half, outside the center
        circle, at a kickoff)."""
        w = self.world
        team = self.mode.team
        ball = w.ball_position()[:2]
        pos = w.torso_positions()
        x, y = pos[:, 0], pos[:, 1]
        own = self._own_sign  # sign of x in each player's own half
        kickoff = self.mode in (PM.KICK_OFF_LEFT, PM.KICK_OFF_RIGHT)
        wrong_half = (x * own < 0) if kickoff else self._nobody
        x[wrong_half] = 0.5 * own[wrong_half]
        opponent = w.side_of != team
        goal_kick = self.mode in (PM.GOAL_KICK_LEFT, PM.GOAL_KICK_RIGHT)
        if goal_kick:
            gx = -field.HALF_LENGTH if team == Side.LEFT else field.HALF_LENGTH
            front = abs(gx) - field.PENALTY_DEPTH
            close = opponent & (np.abs(x) > front) & (np.abs(y) < field.PENALTY_WIDTH / 2) & (x * gx > 0)
        else:
            d = np.hypot(x - ball[0], y - ball[1])
            close = opponent & (d < FREE_KICK_DISTANCE)
        move = wrong_half | close
        if not move.any():
            return
        for i in np.flatnonzero(move).tolist():
            if wrong_half[i]:
                self._move(i, x[i], y[i], "in the opponents' half at kickoff")
            if not close[i]:
                continue
            if goal_kick:
                self._move(i, math.copysign(front - GOAL_KICK_DISTANCE, gx), y[i],
                           "in the penalty area at a goal kick")
                continue
            u = np.array([x[i], y[i]]) - ball
            u = u / d[i] if d[i] > 1e-6 else np.array([own[i], 0.0])
            target = ball + u * (FREE_KICK_DISTANCE + 0.3)
            if kickoff:
                target[0] = own[i] * max(abs(target[0]), 0.5)
            self._move(i, target[0], target[1], "too close to the ball at a restart")

    def _illegal_defense(self) -> None:
        w = self.world
        inside = self._inside
        n = penalty_area_rules(w.data.xpos, w.torso_ids, self._own_sign,
                               (field.HALF_LENGTH, field.PENALTY_DEPTH, field.PENALTY_WIDTH / 2),
                               self.area_since, w.time, inside)
        if n <= MAX_IN_PENALTY_AREA:  # the usual case
            return
        pos = w.torso_positions()
        for team in Side:
            idx = np.nonzero(inside & (w.side_of == team))[0]
            if len(idx) <= MAX_IN_PENALTY_AREA:
                continue
            cand = [i for i in idx if not self.is_goalie[i]]
            i = max(cand, key=lambda k: (self.area_since[k], k))
            sx = -1.0 if team == Side.LEFT else 1.0
            self._event("illegal_defense", team, self._unum(i),
                        f"{len(idx)} players in the own penalty area")
            self._move(i, sx * (field.HALF_LENGTH - field.PENALTY_DEPTH - 0.5), pos[i, 1],
                       "illegal defense")
            self.area_since[i] = np.nan

    def _fallen(self) -> None:
        w = self.world
        d = w.data
        new_falls, late = self._new_falls, self._late
        nf, nl = fallen_rules(
            d.xpos, d.xmat, w.torso_ids, self._standing_z, self.fallen, self.down_since,
            self.unsteady_since, self._down_limit, self._unsteady_limit, w.time,
            (DOWN_UP_Z, STANDING_UP_Z), new_falls, late)
        for i in new_falls[:nf].tolist():
            self.falls[self._team(i)] += 1
        if nl == 0 or self.mode not in LIVE:
            return
        pos = w.torso_positions()
        for i in late[:nl].tolist():
            self.fallen[i] = False
            y = math.copysign(field.HALF_WIDTH + 0.4, pos[i, 1] if pos[i, 1] != 0 else 1.0)
            self._move(i, pos[i, 0], y, "down or not standing too long")

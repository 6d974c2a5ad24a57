"""Rule and timing constants of the RoboCup 3D simulation league (SI units)."""

from __future__ import annotations

import math
from collections import Counter
from enum import Enum

CYCLE = 0.02  # s, one agent cycle
PHYSICS_DT = 0.005  # s, MuJoCo timestep (4 substeps a cycle)
HALF_TIME = 300.0  # s of game time per half
GOAL_PAUSE = 3.0  # s in Goal_* before the kickoff
BEFORE_KICKOFF_TIME = 1.0  # s the match runner leaves for beaming before it kicks off
DROP_BALL_TIME = 15.0  # s without a touch at a restart before the ball is dropped
FREE_KICK_DISTANCE = 2.0  # m opponents are kept from the ball at restarts
GOAL_KICK_DISTANCE = 1.0  # m opponents are kept outside the penalty area at a goal kick
BEAM_NOISE_XY = 0.05  # m, uniform +-
BEAM_NOISE_ANGLE = math.radians(10.0)  # rad, uniform +-
MAX_IN_PENALTY_AREA = 3  # defenders allowed in their own penalty area
FALLEN_REPOSITION_TIME = 15.0  # s down before the referee repositions a player
GOALIE_FALLEN_REPOSITION_TIME = 30.0
NOT_STANDING_REPOSITION_TIME = 30.0
GOALIE_NOT_STANDING_REPOSITION_TIME = 60.0

VISION_PERIOD = 3  # cycles between vision percepts
VIEW_CONE = math.radians(120.0)  # full horizontal and vertical aperture
VISION_SIGMA_DIST = 0.0965  # percent of the distance, one sigma
VISION_SIGMA_HORIZONTAL = math.radians(0.1480)
VISION_SIGMA_VERTICAL = math.radians(0.1225)
VISION_CALIBRATION_ERROR = 0.005  # m, uniform +- per axis, fixed per robot

SAY_MAX_LENGTH = 20
SAY_ALPHABET = frozenset(chr(c) for c in range(0x21, 0x7F)) - {"(", ")"}
HEAR_DISTANCE = 50.0  # m
HEAR_PERIOD = 2  # cycles: a player hears one message per team in that window

TEAM_SIZE = 11
# A full team's robot types (the 2014 rule, MacAlpine's dissertation 4.2.4): at least 3 types,
# at most 7 robots of one type and at most 9 of any two types.
MIN_ROBOT_TYPES = 3
MAX_OF_ONE_TYPE = 7
MAX_OF_TWO_TYPES = 9


class Side(str, Enum):
    """A team's side of the field: the left team defends the goal at -x.

    A `str` Enum equal to the letter SimSpark uses, so it compares, hashes and
    prints as "L"/"R" (dict keys, JSON and names like "L3" stay as they were)."""

    LEFT = "L"
    RIGHT = "R"

    __str__ = str.__str__
    __format__ = str.__format__

    @property
    def other(self) -> Side:
        """The opposing side."""
        return Side.RIGHT if self is Side.LEFT else Side.LEFT


class PlayMode(str, Enum):
    """The league's play modes; values are the names SimSpark sends."""

    BEFORE_KICK_OFF = "BeforeKickOff"
    KICK_OFF_LEFT = "KickOff_Left"
    KICK_OFF_RIGHT = "KickOff_Right"
    PLAY_ON = "PlayOn"
    KICK_IN_LEFT = "KickIn_Left"
    KICK_IN_RIGHT = "KickIn_Right"
    CORNER_KICK_LEFT = "corner_kick_left"
    CORNER_KICK_RIGHT = "corner_kick_right"
    GOAL_KICK_LEFT = "goal_kick_left"
    GOAL_KICK_RIGHT = "goal_kick_right"
    GOAL_LEFT = "Goal_Left"
    GOAL_RIGHT = "Goal_Right"
    GAME_OVER = "GameOver"

    @property
    def team(self) -> Side | None:
        """The side a mode belongs to (Side.LEFT for "KickOff_Left"), else None."""
        return _MODE_TEAM[self]


PLAY_MODES = tuple(PlayMode)
_MODE_TEAM = {m: Side.LEFT if m.value.lower().endswith("_left")
              else Side.RIGHT if m.value.lower().endswith("_right") else None for m in PlayMode}


def restart(kind: str, team: str) -> PlayMode:
    """The play mode of a restart kind ('kick_off', 'kick_in', 'corner_kick',
    'goal_kick', 'goal') for team 'L' or 'R'."""
    return PlayMode[f"{kind.upper()}_{Side(team).name}"]


def _type_counts(types: tuple[int, ...] | list[int]) -> list[int]:
    """Robots of each type among `types`, most first."""
    return sorted(Counter(types).values(), reverse=True)


def robot_types_problem(types: tuple[int, ...] | list[int]) -> str | None:
    """Why a team's robot types (index i: uniform number i + 1) break the league's rule, or
    None. The rule binds a full team (TEAM_SIZE players); smaller sides may use any types."""
    if len(types) < TEAM_SIZE:
        return None
    counts = _type_counts(types)
    if len(counts) < MIN_ROBOT_TYPES:
        return f"{len(counts)} robot types; a full team needs at least {MIN_ROBOT_TYPES}"
    if counts[0] > MAX_OF_ONE_TYPE:
        return f"{counts[0]} robots of one type; at most {MAX_OF_ONE_TYPE}"
    if counts[0] + counts[1] > MAX_OF_TWO_TYPES:
        return f"{counts[0] + counts[1]} robots of two types; at most {MAX_OF_TWO_TYPES}"
    return None


def robot_type_join_problem(types: tuple[int, ...] | list[int], new: int) -> str | None:
    """Why a team whose robots so far have `types` may not take one more of type `new` (the
    league's server refuses such an agent as it joins): more than MAX_OF_ONE_TYPE of a type
    or more than MAX_OF_TWO_TYPES of two (which leaves a full team MIN_ROBOT_TYPES types)."""
    counts = _type_counts([*types, new])
    if counts[0] > MAX_OF_ONE_TYPE:
        return f"{counts[0]} robots of type {new}; at most {MAX_OF_ONE_TYPE}"
    if len(counts) > 1 and counts[0] + counts[1] > MAX_OF_TWO_TYPES:
        return f"{counts[0] + counts[1]} robots of two types; at most {MAX_OF_TWO_TYPES}"
    return None

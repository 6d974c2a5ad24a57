"""What a role asks of the body for one cycle (team frame, m, rad).

The decision layer returns one of these; `agent.body.Body` turns it into joint
velocities through the skills. A skill that has begun (a kick, a dive, a
getup) finishes before the body takes another request.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class WalkTo:
    """Walk to (x, y); end facing `heading` (None: face the way there). The decision
    layer has already bent (x, y) round other players (D.1.2)."""

    x: float
    y: float
    heading: float | None = None
    set_name: str = "go_to_target"


@dataclass(frozen=True)
class Kick:
    """Approach the ball and kick it toward `target` with one of `kicks` (names)."""

    target: tuple[float, float]
    kicks: tuple[str, ...]


@dataclass(frozen=True)
class Dribble:
    """Walk through the ball toward `target` (D.1.6)."""

    target: tuple[float, float]


@dataclass(frozen=True)
class Stand:
    """Stand still, facing `heading` when given (turning on the spot first)."""

    heading: float | None = None


@dataclass(frozen=True)
class Dive:
    """Play a goalie dive (a `skills.dive.DIVES` name), then get up."""

    name: str


SkillRequest = WalkTo | Kick | Dribble | Stand | Dive

__all__ = ["Dive", "Dribble", "Kick", "SkillRequest", "Stand", "WalkTo"]

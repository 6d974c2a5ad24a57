"""Teams by name: each a factory (side, unum, robot_type, seed) -> agent."""

from __future__ import annotations

from collections.abc import Callable


class UnknownTeam(ValueError):
    pass


def _posture() -> Callable:
    from agent.posture import PostureAgent
    return PostureAgent


def _villa() -> Callable:
    from agent.player import villa
    return villa


TEAMS: dict[str, Callable[[], Callable]] = {"posture": _posture, "villa": _villa}


def names() -> list[str]:
    return sorted(TEAMS)


def factory(name: str) -> Callable:
    """The agent factory of team `name`, or UnknownTeam naming the known teams."""
    if name not in TEAMS:
        raise UnknownTeam(f"unknown team {name!r}; known teams: {', '.join(names())}")
    return TEAMS[name]()

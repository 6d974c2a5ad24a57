"""Teams by name, by villa variant `villa:NAME` (`agent.teamconfig.VARIANTS`, any
case), or by spec `package.module:factory`: each a factory
(side, unum, robot_type, seed) -> agent."""

from __future__ import annotations

import importlib
from collections.abc import Callable


class UnknownTeam(ValueError):
    pass


def _posture() -> Callable:
    from agent.posture import PostureAgent
    return PostureAgent


def _villa() -> Callable:
    from agent.variants import VillaFactory
    return VillaFactory()  # the villa config, as `agent.player.villa`


TEAMS: dict[str, Callable[[], Callable]] = {"posture": _posture, "villa": _villa}


def names() -> list[str]:
    return sorted(TEAMS)


def variants() -> list[str]:
    """The villa variants' names (`villa:NAME`)."""
    from agent.teamconfig import VARIANTS
    return list(VARIANTS)


def _variant(name: str) -> Callable:
    from agent.teamconfig import UnknownVariant
    from agent.variants import villa_variant
    try:
        return villa_variant(name)
    except UnknownVariant as exc:
        raise UnknownTeam(str(exc)) from None


def factory(spec: str) -> Callable:
    """The agent factory of team `spec`: a registered name, a villa variant `villa:NAME`
    (case-insensitive), or `package.module:factory` (a callable (side, unum, robot_type,
    seed) -> agent). A bad one raises UnknownTeam with one line saying why."""
    head, sep, tail = spec.partition(":")
    if sep and head.strip().lower() == "villa":
        return _variant(tail)
    if ":" not in spec:
        if spec not in TEAMS:
            raise UnknownTeam(f"unknown team {spec!r}; known teams: {', '.join(names())}"
                              f" (or package.module:factory)")
        return TEAMS[spec]()
    module_name, _, attr = spec.partition(":")
    if not module_name or not attr:
        raise UnknownTeam(f"team spec {spec!r} must be package.module:factory")
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        raise UnknownTeam(f"team {spec!r}: no module named {exc.name!r}") from None
    except Exception as exc:  # noqa: BLE001 - any failure to import is the spec's fault
        last = (str(exc).strip().splitlines() or [""])[-1]
        raise UnknownTeam(f"team {spec!r}: importing {module_name} failed: "
                          f"{type(exc).__name__}: {last}") from None
    obj = module
    for part in attr.split("."):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            raise UnknownTeam(f"team {spec!r}: {module_name} has no {attr!r}") from None
    if not callable(obj):
        raise UnknownTeam(f"team {spec!r}: {attr} is not callable")
    return obj

"""Team factories for the batch and CLI tests, as team specs `tests.batch_teams:NAME`."""

from __future__ import annotations

from agent.posture import PostureAgent


class _Raising(PostureAgent):
    def act(self, percept):
        if percept.game_time >= 0.1:
            raise RuntimeError("agent gave up")
        return super().act(percept)


def raising_agent(side, unum, robot_type, seed):
    """Posture agents that raise in act after 0.1 s of game time."""
    return _Raising(side, unum, robot_type, seed)


def broken_factory(side, unum, robot_type, seed):
    """A factory that cannot make an agent."""
    raise RuntimeError("no agent for you")


posture = PostureAgent
not_callable = 42


class _Typed:
    """Posture agents of a team that chooses its robot types (uniform numbers 1-11)."""

    def __init__(self, types: tuple[int, ...]) -> None:
        self.robot_types = types

    def __call__(self, side, unum, robot_type, seed):
        return PostureAgent(side, unum, robot_type, seed)


toes_first = _Typed((4, 4, 3, 0, 0, 0, 0, 0, 0, 2, 2))
all_toes = _Typed((4,) * 11)  # one type: against the league's rule for a full team

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

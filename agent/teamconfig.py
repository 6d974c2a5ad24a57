"""The villa team's switches: one team, configured (variants for ablations are configs).

Each field names one component of the strategy ("Positioning to Win" section 6
turns them off one at a time). Distances in m, times in s.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class TeamConfig:
    """How the villa team plays. The defaults are the full team."""

    formation: str = "default.formation"  # a file in formations/data/ or a path
    assignment: str = "mmd-msd2"  # a `formations.scram.METHODS` name, or "static"
    voting: bool = True  # follow the team's voted role mapping, not one's own
    communication: bool = True  # say and hear team messages
    collision_avoidance: bool = True  # D.1.2 when walking to a position
    all_ball: bool = False  # every field player goes to the ball
    kicks: bool = True  # may kick
    dribble: bool = True  # may dribble
    dribble_near: float = 2.0  # m: dribble (not kick) when an opponent is this close to the ball (D.2.1)
    marking: bool = True  # mark attackers when the opponents have the ball
    kick_anticipation: bool = True  # run to where a teammate's kick will land
    kick_box: float = 1.0  # the kicks' stopping boxes scaled by this (wider: quicker, less exact)
    formation_shift: float = 0.0  # m added to every formation x (+: offensive, -: defensive)


VILLA = TeamConfig()

__all__ = ["VILLA", "TeamConfig"]

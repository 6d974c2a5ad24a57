"""A training world: agents' percepts and actions without a referee.

For skill benchmarks, tests and optimization tasks (SimSpark's trainer
commands): the caller places robots and the ball through `world` (the
trainer interface), reads ground truth from it for fitness, and steps the
agents, which see only their percepts. Play mode stays PlayOn unless set.
"""

from __future__ import annotations

import numpy as np

from models.messages import Action, Percept
from models.rules import PLAY_MODES, VISION_PERIOD, PlayMode
from models.scene import Lineup
from server.sensors import Proprioception, percepts
from server.vision import VisionSensor
from server.world import World


class Trainer:
    """One world, its sensors and a cycle counter."""

    def __init__(self, lineup: Lineup, seed: int = 0, vision: bool = True) -> None:
        self.world = World(lineup)
        self.proprio = Proprioception(self.world)
        self.vision = VisionSensor(self.world, np.random.default_rng(seed)) if vision else None
        self.play_mode = PlayMode.PLAY_ON
        self.cycle = 0
        m = self.world
        self._act = [p.actuators for p in m.players]
        self._max = [m.model.actuator_ctrlrange[p.actuators, 1] for p in m.players]
        self.ctrl = np.zeros(m.model.nu)

    def scale_motors(self, speed: float = 1.0, torque: float = 1.0) -> None:
        """Diagnosis only, not the league's robot: every joint's speed cap and every motor's
        torque limit times `speed` and `torque` (which bound holds a skill back?)."""
        if speed <= 0.0 or torque <= 0.0:
            raise ValueError(f"motor scales must be positive, got speed {speed} and torque {torque}")
        m = self.world.model
        m.actuator_ctrlrange[:] *= speed
        m.actuator_forcerange[:] *= torque
        self._max = [m.actuator_ctrlrange[p.actuators, 1] for p in self.world.players]

    def set_play_mode(self, mode: PlayMode | str) -> None:
        self.play_mode = PlayMode(mode)
        assert self.play_mode in PLAY_MODES

    def percepts(self) -> list[Percept]:
        """Every player's percept for this cycle (vision every third cycle)."""
        seen = (self.vision.see_all() if self.vision is not None and self.cycle % VISION_PERIOD == 0
                else {})
        return percepts(self.world, self.proprio, seen, self.world.time, self.play_mode.value, (0, 0))

    def step(self, actions: dict[int, Action] | list[Action]) -> list[int]:
        """Apply joint velocities of the given players (others hold still) and run one cycle.

        Returns the players that started touching the ball."""
        items = actions.items() if isinstance(actions, dict) else enumerate(actions)
        self.ctrl[:] = 0.0
        for i, a in items:
            self.ctrl[self._act[i]] = np.clip(a.joint_velocities, -self._max[i], self._max[i])
        self.cycle += 1
        return self.world.step(self.ctrl)

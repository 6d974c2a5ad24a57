"""Proprioception: joint angles, gyro, accelerometer and sole forces of every player."""

from __future__ import annotations

import numpy as np

from models.messages import HeardMessage, Percept, Vision
from server.world import World


class Proprioception:
    """Reads every player's joint and body sensors with two gathers a cycle."""

    def __init__(self, world: World) -> None:
        self.world = world
        players = world.players
        self._q = np.concatenate([p.joint_qpos for p in players])
        self._s = np.concatenate([p.sensors for p in players])
        self._q_split = np.cumsum([len(p.joint_qpos) for p in players])[:-1]
        self._s_split = np.cumsum([len(p.sensors) for p in players])[:-1]

    def read(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per player: (joint angles rad, gyro rad/s, accelerometer m/s^2, sole forces N);
        gyro and accelerometer in the torso frame."""
        d = self.world.data
        q = np.split(d.qpos[self._q], self._q_split)
        s = np.split(d.sensordata[self._s], self._s_split)
        return [(qi, si[0:3], si[3:6], si[6:]) for qi, si in zip(q, s)]


def percepts(world: World, proprio: Proprioception, vision: dict[int, Vision], game_time: float,
             play_mode: str, score: tuple[int, int], heard: dict[int, list[HeardMessage]] | None = None,
             warnings: dict[int, list[str]] | None = None) -> list[Percept]:
    """Every player's percept for the current cycle of `world`."""
    heard = heard or {}
    warnings = warnings or {}
    out = []
    for i, (q, gyro, acc, soles) in enumerate(proprio.read()):
        p = world.players[i]
        out.append(Percept(
            time=round(world.time, 6), game_time=round(game_time, 6), play_mode=play_mode,
            score_left=score[0], score_right=score[1], side=p.side, unum=p.unum,
            robot_type=p.robot_type, joints=q, gyro=gyro, accel=acc, foot_forces=soles,
            vision=vision.get(i), heard=tuple(heard.get(i, ())), warnings=tuple(warnings.get(i, ())),
        ))
    return out

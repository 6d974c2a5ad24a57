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
        # Per player: (first joint, end of joints, first sensor, end of sensors) in the
        # two gathered arrays; a player's sensors are gyro (3), accelerometer (3), soles.
        q_end = np.cumsum([len(p.joint_qpos) for p in players]).tolist()
        s_end = np.cumsum([len(p.sensors) for p in players]).tolist()
        self._slices = [(qe - len(p.joint_qpos), qe, se - len(p.sensors), se)
                        for p, qe, se in zip(players, q_end, s_end)]

    def read(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per player: (joint angles rad, gyro rad/s, accelerometer m/s^2, sole forces N);
        gyro and accelerometer in the torso frame."""
        d = self.world.data
        q = d.qpos[self._q]
        s = d.sensordata[self._s]
        return [(q[q0:q1], s[s0:s0 + 3], s[s0 + 3:s0 + 6], s[s0 + 6:s1])
                for q0, q1, s0, s1 in self._slices]


def percepts(world: World, proprio: Proprioception, vision: dict[int, Vision], game_time: float,
             play_mode: str, score: tuple[int, int], heard: dict[int, list[HeardMessage]] | None = None,
             warnings: dict[int, list[str]] | None = None) -> list[Percept]:
    """Every player's percept for the current cycle of `world`."""
    heard = heard or {}
    warnings = warnings or {}
    time, game_time = round(world.time, 6), round(game_time, 6)
    left, right = score
    return [Percept(
        time=time, game_time=game_time, play_mode=play_mode, score_left=left, score_right=right,
        side=p.side, unum=p.unum, robot_type=p.robot_type, joints=q, gyro=gyro, accel=acc,
        foot_forces=soles, vision=vision.get(i) if vision else None,
        heard=tuple(heard[i]) if i in heard else (), warnings=tuple(warnings[i]) if i in warnings else (),
    ) for i, (p, (q, gyro, acc, soles)) in enumerate(zip(world.players, proprio.read()))]

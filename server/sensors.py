"""Proprioception: joint angles, gyro, accelerometer and sole forces of every player."""

from __future__ import annotations

import numpy as np

from models import robot, scene
from models.messages import HeardMessage, Percept, Vision
from server._kernels import body_sensors
from server.world import World


class Proprioception:
    """Every player's joint angles, gyro, accelerometer and sole forces, read in one
    compiled pass (`server._kernels.body_sensors`).

    The model carries MuJoCo sensors for all of these (joint positions, a gyro and
    an accelerometer at the torso's `imu` site, a touch sensor under each sole), but
    `World` steps with MuJoCo's sensor stage off: the kernel computes the same
    values from the state of the last forward pass. MuJoCo's sensor stage took
    about 57 us a cycle (each touch sensor loops over every contact, and the
    accelerometer needs an extra pass for accelerations); the kernel's call takes
    15-35 us. Readings describe the start of the last physics substep, as the
    sensor stage of that substep would, but for the accelerometer: it reads the
    torso's mean acceleration over the cycle (`World.root_acc`), as SimSpark's
    does over its 20 ms step and as a real IMU's anti-alias filter would. MuJoCo's
    reading is one substep's acceleration, and contact chatter at the substep
    rate aliases into it: a robot lying still on its back with bent knees read a
    steady 5 m/s^2 along its torso's z axis (tilt 64 deg instead of 90) and
    +-3 m/s^2 of jitter, so the fall detector never saw it at rest and half the
    failed back getups from a walking fall never started.
    """

    def __init__(self, world: World) -> None:
        self.world = world
        m = world.model
        players = world.players
        self._q = np.concatenate([p.joint_qpos for p in players])
        q_end = np.cumsum([len(p.joint_qpos) for p in players]).tolist()
        self._slices = [(qe - len(p.joint_qpos), qe, len(robot.sole_names(p.robot_type)))
                        for p, qe in zip(players, q_end)]
        self._torso = np.array([p.torso for p in players], dtype=np.int64)
        for p in players:  # the kernel's shortcut: the IMU frame is the torso frame
            imu = m.site(scene.prefix(p.side, p.unum) + "imu")
            if np.any(imu.pos != 0.0) or np.any(imu.quat != (1.0, 0.0, 0.0, 0.0)):
                raise ValueError(f"{p.name}: the imu site must sit at the torso origin, unrotated")
        self._sole_of_body = np.full(m.nbody, -1, dtype=np.int64)
        sites, slots = [], []
        for i, p in enumerate(players):
            for j, foot in enumerate(robot.sole_names(p.robot_type)):
                site = m.site(scene.prefix(p.side, p.unum) + foot + "_sole")
                self._sole_of_body[m.site_bodyid[site.id]] = len(sites)
                sites.append(site.id)
                slots.append((i, j))
        self._sole_site = np.array(sites, dtype=np.int64)
        self._sole_slot = np.array(slots, dtype=np.int64).reshape(-1, 2)
        self._geom_body = m.geom_bodyid.astype(np.int64)
        self._site_size = m.site_size.copy()
        self._gravity = m.opt.gravity.copy()
        self._out = np.zeros((len(players), 10))

    def body(self) -> np.ndarray:
        """(n, 10) per player: gyro (rad/s), accelerometer (m/s^2), both in the torso
        frame, then sole forces (N; left foot, right foot, then type 4's left and
        right toe; unused columns 0). A fresh array."""
        d = self.world.data
        c = d.contact
        body_sensors(d.xmat, d.cvel, self.world.root_acc, self._torso, self._gravity,
                     self._geom_body, c.geom, c.pos, c.frame, c.efc_address, c.dim, d.efc_force,
                     self._sole_of_body, self._sole_site, d.site_xpos, d.site_xmat,
                     self._site_size, self._sole_slot, self._out)
        return self._out.copy()

    def read(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
        """Per player: (joint angles rad, gyro rad/s, accelerometer m/s^2, sole forces N);
        gyro and accelerometer in the torso frame."""
        q = self.world.data.qpos[self._q]
        s = self.body()
        return [(q[q0:q1], row[0:3], row[3:6], row[6:6 + k])
                for (q0, q1, k), row in zip(self._slices, s)]


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

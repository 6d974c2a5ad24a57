"""The simulated world: one MuJoCo model of a whole line-up and its index tables.

`World` owns `MjModel`/`MjData`. It steps physics in 20 ms cycles, notes which
robots touch the ball, and offers the trainer interface (place the ball and
robots, give the ball a velocity, read ground truth), like SimSpark's monitor
commands. Only the referee, tests, optimization tasks and statistics use the
trainer interface; agents see the world only through `server.sensors`.

Frames: the world frame is the field frame of `models.field` (m, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from models import field, nao, robot, scene
from models.messages import SEEN_PARTS
from models.rules import CYCLE, PHYSICS_DT, Side
from server._kernels import ball_touchers


class PhysicsDiverged(RuntimeError):
    """The simulation became unstable (non-finite state, or MuJoCo's instability warnings).

    A match that raises it has no valid result: it is never silently reset."""


# MuJoCo's warnings of an unstable simulation (it resets MjData when it gives them).
_UNSTABLE = (mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL,
             mujoco.mjtWarning.mjWARN_BADQACC)


@dataclass(frozen=True)
class PlayerIndex:
    """Where one player lives in the MuJoCo model."""

    index: int  # position in World.players
    side: Side
    unum: int
    robot_type: int
    root_qpos: int  # address of the free joint's 7 qpos (x y z, quaternion w x y z)
    root_qvel: int  # address of its 6 qvel
    joint_qpos: np.ndarray  # qpos addresses of the hinges, league order
    joint_qvel: np.ndarray
    actuators: np.ndarray  # actuator ids, league order
    sensors: np.ndarray  # sensordata addresses of MuJoCo's gyro (3), accelerometer (3), soles (2 or 4)
    torso: int  # body id
    camera: int  # site id
    parts: np.ndarray  # body ids of SEEN_PARTS
    geoms: tuple[int, int]  # [first, last] geom id of the robot

    @property
    def name(self) -> str:
        return f"{self.side}{self.unum}"


class World:
    """A match scene in MuJoCo with index tables and the trainer interface."""

    def __init__(self, lineup: scene.Lineup, timestep: float = PHYSICS_DT) -> None:
        if not 0 < timestep <= PHYSICS_DT + 1e-12 or abs(CYCLE / timestep - round(CYCLE / timestep)) > 1e-9:
            raise ValueError(f"timestep {timestep} must divide {CYCLE} s and be at most {PHYSICS_DT} s")
        self.lineup = lineup
        self.xml = scene.scene_mjcf(lineup, timestep)
        self.model = mujoco.MjModel.from_xml_string(self.xml)
        self.data = mujoco.MjData(self.model)
        self.substeps = round(CYCLE / timestep)
        m = self.model
        self.players: list[PlayerIndex] = []
        geom_owner = np.full(m.ngeom, -1, dtype=np.int32)
        for i, (side, unum, t) in enumerate(lineup.players()):
            p = scene.prefix(side, unum)
            names = nao.joint_names(t)
            jid = [m.joint(p + n).id for n in names]
            sens = []
            for s in ["gyro", "acc"] + robot.sole_names(t):
                sid = m.sensor(p + s).id
                sens.extend(range(m.sensor_adr[sid], m.sensor_adr[sid] + m.sensor_dim[sid]))
            torso = m.body(p + "torso").id
            gids = np.nonzero(m.body_rootid[m.geom_bodyid] == torso)[0]
            geom_owner[gids] = i
            root = m.joint(p + "root").id
            self.players.append(PlayerIndex(
                index=i, side=side, unum=unum, robot_type=t,
                root_qpos=int(m.jnt_qposadr[root]), root_qvel=int(m.jnt_dofadr[root]),
                joint_qpos=m.jnt_qposadr[jid].copy(), joint_qvel=m.jnt_dofadr[jid].copy(),
                actuators=np.array([m.actuator(p + n.replace("j", "e", 1)).id for n in names]),
                sensors=np.array(sens), torso=torso, camera=m.site(p + "camera").id,
                parts=np.array([m.body(p + b).id for b in SEEN_PARTS]),
                geoms=(int(gids.min()), int(gids.max())),
            ))
        self.geom_owner = geom_owner
        # The player owning each degree of freedom (-1: the ball), to name a diverging robot.
        torso_of = {p.torso: p.index for p in self.players}
        self.dof_owner = np.array([torso_of.get(int(m.body_rootid[b]), -1) for b in m.dof_bodyid])
        self.ball_geom = m.geom("ball").id
        self._touch_buf = np.empty(64, dtype=np.int32)  # a ball touches a few geoms at once
        self.ball_body = m.body("ball").id
        ball_joint = m.joint("ball_x").id  # slides x, y, z then the ball joint: a free joint's layout
        self.ball_qpos = int(m.jnt_qposadr[ball_joint])
        self.ball_qvel = int(m.jnt_dofadr[ball_joint])
        self.torso_ids = np.array([p.torso for p in self.players])
        self.camera_ids = np.array([p.camera for p in self.players])
        self.part_ids = np.stack([p.parts for p in self.players])  # (n, 5)
        self.side_of = np.array([str(p.side) for p in self.players])  # "L"/"R" per player
        self.unum_of = np.array([p.unum for p in self.players])
        self.heights = np.array([nao.standing_height(p.robot_type) for p in self.players])
        self.time = 0.0
        self._touching: set[int] = set()  # players in contact with the ball after the last substep
        self._root_dofs = np.array([[p.root_qvel + k for k in range(3)] for p in self.players],
                                   dtype=np.int64).reshape(-1, 3)
        # Each torso origin's mean linear acceleration over the last cycle (world frame,
        # m/s^2), for the accelerometer (`server.sensors`); a placed robot's is its
        # acceleration at placement.
        self.root_acc = np.zeros((len(self.players), 3))
        # MuJoCo's sensor stage stays off: `server.sensors.Proprioception` computes the
        # same readings from MjData once a cycle, for less.
        m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_SENSOR)
        mujoco.mj_forward(m, self.data)
        self.root_acc[:] = self.data.qacc[self._root_dofs]

    # ------------------------------------------------------------------ physics

    def step(self, ctrl: np.ndarray) -> list[int]:
        """Advance one 20 ms cycle with actuator controls `ctrl` (rad/s per actuator).

        Returns the players (indices into `players`) that started touching the
        ball during the cycle, in the order they did.
        """
        m, d = self.model, self.data
        np.copyto(d.ctrl, ctrl)
        touches: list[int] = []
        touching = self._touching
        buf, ball, owner = self._touch_buf, self.ball_geom, self.geom_owner
        v0 = d.qvel[self._root_dofs]
        for _ in range(self.substeps):
            mujoco.mj_step(m, d)
            n = ball_touchers(d.contact.geom, ball, owner, buf)
            if n or touching:  # usually nobody touches the ball: no sets to build
                now = set(buf[:n].tolist())
                touches.extend(sorted(now - touching))
                touching = now
        self._touching = touching
        dt = self.substeps * m.opt.timestep
        np.subtract(d.qvel[self._root_dofs], v0, out=self.root_acc)
        self.root_acc /= dt
        self.time += dt
        return touches

    def check_physics(self) -> None:
        """Raise PhysicsDiverged when the state is not finite or MuJoCo warned of instability."""
        d = self.data
        warned = [w for w in _UNSTABLE if d.warning[w].number]
        if not warned and math.isfinite(float(d.qpos.sum() + d.qvel.sum())):
            return
        if warned:
            w = warned[0]
            k = int(d.warning[w].lastinfo)
            what = f"MuJoCo warning {w.name} (dof {k})"
        else:
            bad = np.nonzero(~np.isfinite(d.qvel))[0]
            k = int(bad[0]) if len(bad) else -1
            if k < 0:
                bad_q = np.nonzero(~np.isfinite(d.qpos))[0]
                k = int(np.searchsorted(self.model.jnt_qposadr, bad_q[0], side="right")) - 1
                k = int(self.model.jnt_dofadr[k])
            what = f"non-finite state (dof {k})"
        owner = int(self.dof_owner[k]) if 0 <= k < len(self.dof_owner) else -1
        who = self.players[owner].name if owner >= 0 else "the ball"
        raise PhysicsDiverged(f"physics diverged at {self.time:.2f} s: {what} of {who}")

    # --------------------------------------------------------------- ground truth

    def ball_position(self) -> np.ndarray:
        """Ball center (m, world frame)."""
        return self.data.qpos[self.ball_qpos:self.ball_qpos + 3].copy()

    def ball_velocity(self) -> np.ndarray:
        """Ball linear velocity (m/s, world frame)."""
        return self.data.qvel[self.ball_qvel:self.ball_qvel + 3].copy()

    def torso_positions(self) -> np.ndarray:
        """(n, 3) torso centers (m, world frame)."""
        return self.data.xpos[self.torso_ids]  # fancy indexing copies

    def torso_up(self) -> np.ndarray:
        """(n,) z component of each torso's up axis: 1 upright, 0 lying."""
        return self.data.xmat[self.torso_ids, 8]  # fancy indexing copies

    def headings(self) -> np.ndarray:
        """(n,) yaw of each torso's x axis in the world frame (rad)."""
        xm = self.data.xmat[self.torso_ids]
        return np.arctan2(xm[:, 3], xm[:, 0])

    def player_pose(self, i: int) -> tuple[float, float, float]:
        """(x, y, heading) of player i's torso in the world frame."""
        p = self.data.xpos[self.players[i].torso]
        return float(p[0]), float(p[1]), float(self.headings()[i])

    def joint_angles(self, i: int) -> np.ndarray:
        """Player i's hinge angles (rad, league order)."""
        return self.data.qpos[self.players[i].joint_qpos].copy()

    def player(self, side: str, unum: int) -> int:
        """Index of the player with this side and uniform number."""
        for p in self.players:
            if p.side == side and p.unum == unum:
                return p.index
        raise KeyError(f"no player {side}{unum} in this line-up")

    # -------------------------------------------------------------------- trainer

    def place_ball(self, pos: tuple[float, float] | np.ndarray, z: float | None = None,
                   velocity: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> None:
        """Put the ball at (x, y[, z]) (m, world frame) with a linear velocity (m/s)."""
        d = self.data
        a, v = self.ball_qpos, self.ball_qvel
        d.qpos[a] = pos[0]
        d.qpos[a + 1] = pos[1]
        d.qpos[a + 2] = field.BALL_RADIUS if z is None else z
        d.qpos[a + 3:a + 7] = (1.0, 0.0, 0.0, 0.0)
        d.qvel[v:v + 3] = velocity
        d.qvel[v + 3:v + 6] = 0.0
        mujoco.mj_forward(self.model, d)

    def ball_rest_position(self) -> np.ndarray:
        """Where the ball will come to rest (x, y; m, world frame) if nothing touches it:
        a ball rolling on the ground is carried on by `field.rolling_distance`, one in
        the air or at rest stays where it is (ground truth for trials and benchmarks)."""
        p, v = self.ball_position()[:2], self.ball_velocity()[:2]
        speed = float(np.hypot(v[0], v[1]))
        if speed < 0.02 or self.ball_position()[2] > 2.0 * field.BALL_RADIUS:
            return p
        return p + v * (field.rolling_distance(speed) / speed)

    def set_ball_velocity(self, velocity: tuple[float, float, float]) -> None:
        """Give the ball a linear velocity (m/s, world frame), rolling without slip
        when it lies on the ground."""
        d = self.data
        v = self.ball_qvel
        d.qvel[v:v + 3] = velocity
        # Spin of rolling without slipping: omega = z x v / r.
        d.qvel[v + 3:v + 6] = (-velocity[1] / field.BALL_RADIUS, velocity[0] / field.BALL_RADIUS, 0.0)

    def place_robot(self, i: int, x: float, y: float, heading: float,
                    joints: np.ndarray | None = None, z: float | None = None,
                    lying: str | None = None) -> None:
        """Put player i upright (or `lying` "front"/"back") at (x, y) with a heading
        (world frame, m and rad), joints at `joints` (rad, league order) if given,
        every velocity zero."""
        p = self.players[i]
        d = self.data
        if joints is not None:
            d.qpos[p.joint_qpos] = joints
        d.qvel[p.root_qvel:p.root_qvel + 6] = 0.0
        d.qvel[p.joint_qvel] = 0.0
        qyaw = np.array([math.cos(heading / 2), 0.0, 0.0, math.sin(heading / 2)])
        if lying is None:
            quat = qyaw
            height = self.heights[i] + 0.005 if z is None else z
        else:
            pitch = math.pi / 2 if lying == "front" else -math.pi / 2
            qp = np.array([math.cos(pitch / 2), 0.0, math.sin(pitch / 2), 0.0])
            quat = np.empty(4)
            mujoco.mju_mulQuat(quat, qyaw, qp)
            height = 0.07 if z is None else z
        a = p.root_qpos
        d.qpos[a:a + 3] = (x, y, height)
        d.qpos[a + 3:a + 7] = quat
        mujoco.mj_forward(self.model, d)
        self.root_acc[i] = d.qacc[self._root_dofs[i]]

    def settle_height(self, i: int) -> None:
        """Lower player i so that its lowest sole just touches the ground."""
        d = self.data
        p = self.players[i]
        m = self.model
        boxes = [g for g in range(p.geoms[0], p.geoms[1] + 1)
                 if m.geom_type[g] == mujoco.mjtGeom.mjGEOM_BOX and m.geom_contype[g]]
        # Lowest corner of each box: center z minus |R[2, :]| . half extents.
        lo = min(d.geom_xpos[g, 2] - np.abs(d.geom_xmat[g, 6:9]) @ m.geom_size[g] for g in boxes)
        d.qpos[p.root_qpos + 2] -= lo - 0.0005
        mujoco.mj_forward(self.model, d)
        self.root_acc[i] = d.qacc[self._root_dofs[i]]

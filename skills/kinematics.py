"""Forward kinematics and center of mass of one robot, by pinocchio over the physics MJCF.

Everything is expressed in the TORSO frame (torso center, x forward, y left,
z up), meters and radians. Joint angles are given in the league's order
(`models.nao.joint_names(t)`) with the league's sign conventions.

The pinocchio model is built from `models.robot.robot_mjcf(t)`, the same
document MuJoCo simulates, so the two agree to rounding. The torso's free
joint is kept and always set to the identity, which makes pinocchio's world
frame the torso frame.
"""

from __future__ import annotations

import functools
import math
import os
import tempfile
import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from models import nao
from models.robot import robot_mjcf
from skills import _kernels as kernels

SIDES = ("l", "r")
LEG_JOINTS = tuple(f"lj{i}" for i in range(1, 7))  # per side, prefixed with "l"/"r"
ARM_JOINTS = tuple(f"aj{i}" for i in range(1, 5))


def _pinocchio_mjcf(robot_type: int) -> str:
    """The physics MJCF, adapted for pinocchio's parser.

    Pinocchio treats geoms with contype = conaffinity = 0 as visual only and
    leaves their mass out, while MuJoCo counts every geom's mass. Collision
    flags mean nothing to kinematics, so they are dropped here.
    """
    root = ET.fromstring(robot_mjcf(robot_type))
    for geom in root.iter("geom"):
        geom.attrib.pop("contype", None)
        geom.attrib.pop("conaffinity", None)
    return ET.tostring(root, encoding="unicode")


def build_model(robot_type: int) -> pin.Model:
    """Pinocchio model of robot type `robot_type` (free-flyer root at the torso): a copy of
    the one parsed per type."""
    return pin.Model(_parsed_model(robot_type))


@functools.cache
def _parsed_model(robot_type: int) -> pin.Model:
    fd, path = tempfile.mkstemp(suffix=".xml", prefix=f"nao{robot_type}_")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(_pinocchio_mjcf(robot_type))
        return pin.buildModelFromMJCF(path)
    finally:
        os.unlink(path)


class RobotKinematics:
    """Forward kinematics, frames and center of mass of one robot type, in the torso frame.

    Every method taking `q` expects the joint angles (rad) in league order
    (`self.joint_names`), shape (22,) or (24,) for type 4. Poses are 4x4
    homogeneous transforms (m).
    """

    def __init__(self, robot_type: int):
        self.robot_type = robot_type
        self.model = build_model(robot_type)
        self.data = self.model.createData()
        self.joint_names: list[str] = nao.joint_names(robot_type)
        specs = nao.joints(robot_type)
        self.lower = np.array([j.lower for j in specs])
        self.upper = np.array([j.upper for j in specs])
        m = self.model
        # League order -> pinocchio configuration index.
        self._qidx = np.array([m.idx_qs[m.getJointId(n)] for n in self.joint_names], dtype=int)
        self._q = pin.neutral(m)  # root stays at the identity: world == torso
        self._fid = {f.name: i for i, f in enumerate(m.frames)}
        self._sole = (self._fid["lfoot_sole"], self._fid["rfoot_sole"])
        self._ankle = (m.getJointId("llj6"), m.getJointId("rlj6"))
        self._camera = self._fid["camera"]
        self.mass = float(pin.computeTotalMass(m))
        self._com_tables()

    def _com_tables(self) -> None:
        """The joint tree for `skills._kernels.center_of_mass` (its docstring gives the layout)."""
        m = self.model
        league = {int(iq): k for k, iq in enumerate(self._qidx)}  # configuration index -> league index
        kinds = {"JointModelRX": kernels.J_RX, "JointModelRY": kernels.J_RY, "JointModelRZ": kernels.J_RZ,
                 "JointModelRevoluteUnaligned": kernels.J_UNALIGNED, "JointModelFreeFlyer": kernels.J_FREE}
        ij, fj = np.zeros((m.njoints, 3), dtype=np.int64), np.zeros((m.njoints, 19))
        mass = np.zeros(m.njoints)
        for i in range(1, m.njoints):
            joint, place, inertia = m.joints[i], m.jointPlacements[i], m.inertias[i]
            kind = kinds[joint.shortname()]
            ij[i] = kind, m.parents[i], -1 if kind == kernels.J_FREE else league[joint.idx_q]
            fj[i, 0:9] = place.rotation.reshape(9)
            fj[i, 9:12] = place.translation
            if kind == kernels.J_UNALIGNED:
                fj[i, 12:15] = joint.extract().axis
            fj[i, 15:18] = inertia.mass * inertia.lever
            mass[i] = inertia.mass
        for i in range(m.njoints - 1, 0, -1):  # subtree masses, summed in pinocchio's order
            mass[m.parents[i]] += mass[i]
        fj[:, 18] = mass
        self._com_int, self._com_float = ij, fj

    # ----------------------------------------------------------------- helpers

    def index(self, name: str) -> int:
        """Position of joint `name` (e.g. "llj4") in the league-order vector."""
        return self.joint_names.index(name)

    def leg_indices(self, side: str) -> np.ndarray:
        """League-order positions of one leg's six joints lj1..lj6, side "l" or "r"."""
        return np.array([self.index(side + j) for j in LEG_JOINTS], dtype=int)

    def arm_indices(self, side: str) -> np.ndarray:
        """League-order positions of one arm's joints aj1..aj4, side "l" or "r"."""
        return np.array([self.index(side + j) for j in ARM_JOINTS], dtype=int)

    def pin_q(self, q) -> np.ndarray:
        """Pinocchio configuration (torso at the identity) for league-order angles `q`."""
        self._q[self._qidx] = q
        return self._q

    def _fk(self, q) -> None:
        pin.forwardKinematics(self.model, self.data, self.pin_q(q))

    def _frame(self, fid: int) -> np.ndarray:
        return pin.updateFramePlacement(self.model, self.data, fid).homogeneous

    # ------------------------------------------------------------------ queries

    def frame_pose(self, q, name: str) -> np.ndarray:
        """4x4 pose of a body, joint or site frame `name` in the torso frame."""
        self._fk(q)
        return self._frame(self._fid[name])

    def foot_poses(self, q) -> tuple[np.ndarray, np.ndarray]:
        """(left, right) 4x4 poses of the sole centers (sites `*foot_sole`) in the torso frame."""
        self._fk(q)
        return self._frame(self._sole[0]), self._frame(self._sole[1])

    def ankle_positions(self, q) -> tuple[np.ndarray, np.ndarray]:
        """(left, right) ankle joint centers (m, torso frame)."""
        self._fk(q)
        oMi = self.data.oMi
        return oMi[self._ankle[0]].translation.copy(), oMi[self._ankle[1]].translation.copy()

    def com(self, q) -> np.ndarray:
        """Center of mass (m, torso frame), shape (3,): pinocchio's centerOfMass, bit for
        bit, compiled (`skills._kernels.center_of_mass`)."""
        out = np.empty(3)
        kernels.center_of_mass(np.asarray(q, dtype=float), self._com_int, self._com_float, out)
        return out

    def feet_and_com(self, q) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Hot path: (left sole 4x4, right sole 4x4, com (3,)) from one kinematics pass."""
        com = pin.centerOfMass(self.model, self.data, self.pin_q(q), False).copy()
        return self._frame(self._sole[0]), self._frame(self._sole[1]), com

    def camera_pose(self, q) -> np.ndarray:
        """4x4 pose of the head camera (x along the line of sight) in the torso frame."""
        self._fk(q)
        return self._frame(self._camera)

    def frame_jacobian(self, q, name: str) -> np.ndarray:
        """6 x n Jacobian of frame `name` (local frame: linear then angular) w.r.t. league `q`."""
        J = pin.computeFrameJacobian(self.model, self.data, self.pin_q(q), self._fid[name],
                                     pin.ReferenceFrame.LOCAL)
        # For revolute joints the velocity index is the configuration index minus one
        # (the free flyer has nq 7 and nv 6).
        return J[:, self._qidx - 1]


# ------------------------------------------------------------------ leg geometry


@dataclass(frozen=True)
class LegGeometry:
    """One leg's constants for the closed-form IK, from the pinocchio model at zero angles.

    Vectors are in the torso frame's axes (m). The three hip axes meet at `hip`;
    the ankle pitch and roll axes meet at the ankle. The hip yaw-pitch axis is
    (0, cos(tilt), sin(tilt)); the pitch joints (lj3, lj4, lj5) turn about -y and
    the roll joints (lj2, lj6) about +x, as in `models.nao`.
    """

    side: str  # "l" or "r"
    hip: np.ndarray  # hip joint center in the torso frame
    tilt: float  # rad, direction of the hip yaw-pitch axis in the y-z plane
    thigh: np.ndarray  # hip -> knee at zero angles (y = 0)
    shank: np.ndarray  # knee -> ankle at zero angles (y = 0)
    sole: np.ndarray  # ankle -> sole center, in the foot frame
    lower: np.ndarray  # (6,) rad, lj1..lj6
    upper: np.ndarray  # (6,) rad
    reach_min: float  # m, shortest hip-ankle distance (knee at its lower limit)
    reach_max: float  # m, longest hip-ankle distance (knee at its upper limit)

    def __post_init__(self):
        # Plain floats for the scalar IK (numpy scalars are several times slower).
        object.__setattr__(self, "consts", (
            tuple(float(v) for v in self.hip), float(self.tilt),
            float(self.thigh[0]), float(self.thigh[2]), float(self.shank[0]), float(self.shank[2]),
            tuple(float(v) for v in self.sole),
            tuple(float(v) for v in self.lower), tuple(float(v) for v in self.upper)))
        # What the IK derives from them every call: thigh and shank lengths, the knee's
        # law-of-cosines terms, the knee angle's fixed part, the yaw-pitch axis' cos/sin.
        hx, hz, kx, kz = self.consts[2:6]
        lh, lk = math.hypot(hx, hz), math.hypot(kx, kz)
        object.__setattr__(self, "derived", (
            lh * lh, lk * lk, 2.0 * lh * lk, math.atan2(hx, -hz) - math.atan2(kx, -kz),
            math.cos(self.consts[1]), math.sin(self.consts[1])))
        # All of them in one float array for the compiled IK (`skills._kernels.solve_leg`).
        hip, tilt, hx, hz, kx, kz, sole, lo, up = self.consts
        object.__setattr__(self, "kconsts", np.array(
            [*hip, tilt, hx, hz, kx, kz, *sole, *lo, *up, float(self.reach_min), float(self.reach_max),
             *self.derived]))


@dataclass(frozen=True)
class ArmGeometry:
    """One arm's constants for the pointing IK (m, torso axes, zero angles)."""

    side: str
    shoulder: np.ndarray  # shoulder joint center (aj1 and aj2 axes meet here)
    hand: np.ndarray  # shoulder -> hand tip (end of the lower arm) with every arm joint at zero
    lower: np.ndarray  # (2,) rad, aj1 and aj2
    upper: np.ndarray  # (2,) rad


@dataclass(frozen=True)
class LegsGeometry:
    """Both legs (and arms) of one robot type."""

    robot_type: int
    left: LegGeometry
    right: LegGeometry
    left_arm: ArmGeometry
    right_arm: ArmGeometry

    def leg(self, side: str) -> LegGeometry:
        """The leg of side "l"/"left" or "r"/"right"."""
        return self.left if side[0] == "l" else self.right

    def arm(self, side: str) -> ArmGeometry:
        """The arm of side "l"/"left" or "r"/"right"."""
        return self.left_arm if side[0] == "l" else self.right_arm


def _knee_reach(thigh: np.ndarray, shank: np.ndarray, knee: float) -> float:
    """Hip-ankle distance for knee angle `knee` (rad): |Ry(knee) thigh + shank|."""
    c, s = np.cos(knee), np.sin(knee)
    x = c * thigh[0] + s * thigh[2] + shank[0]
    z = -s * thigh[0] + c * thigh[2] + shank[2]
    return float(np.hypot(x, z))


def _expect(cond: bool, what: str) -> None:
    if not cond:
        raise ValueError(f"robot model does not fit the closed-form leg IK: {what}")


def geometry_from(kin: RobotKinematics) -> LegsGeometry:
    """Read the IK geometry of both legs and arms off `kin`'s model at zero angles."""
    m, d = kin.model, kin.model.createData()
    q0 = pin.neutral(m)
    pin.computeJointJacobians(m, d, q0)
    pin.framesForwardKinematics(m, d, q0)

    def origin(name: str) -> np.ndarray:
        return d.oMi[m.getJointId(name)].translation.copy()

    def axis(name: str) -> np.ndarray:
        jid = m.getJointId(name)
        J = pin.getJointJacobian(m, d, jid, pin.ReferenceFrame.WORLD)
        return J[3:, m.idx_vs[jid]].copy()

    tol = 1e-9
    ex, ey = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    legs, arms = {}, {}
    for s in SIDES:
        names = [s + j for j in LEG_JOINTS]
        hip, knee, ankle = origin(names[0]), origin(names[3]), origin(names[4])
        _expect(np.allclose(origin(names[1]), hip, atol=tol)
                and np.allclose(origin(names[2]), hip, atol=tol), "hip axes do not meet")
        _expect(np.allclose(origin(names[5]), ankle, atol=tol), "ankle axes do not meet")
        a1 = axis(names[0])
        _expect(abs(a1[0]) < tol, "hip yaw-pitch axis not in the y-z plane")
        _expect(np.allclose(axis(names[1]), ex, atol=tol) and np.allclose(axis(names[5]), ex, atol=tol),
                "roll axes are not +x")
        _expect(all(np.allclose(axis(n), -ey, atol=tol) for n in names[2:5]), "pitch axes are not -y")
        thigh, shank = knee - hip, ankle - knee
        _expect(abs(thigh[1]) < tol and abs(shank[1]) < tol, "knee offset out of the sagittal plane")
        sole = d.oMf[m.getFrameId(f"{s}foot_sole")].translation - ankle
        idx = kin.leg_indices(s)
        lo, up = kin.lower[idx].copy(), kin.upper[idx].copy()
        legs[s] = LegGeometry(
            side=s, hip=hip, tilt=float(np.arctan2(a1[2], a1[1])), thigh=thigh, shank=shank,
            sole=sole, lower=lo, upper=up,
            reach_min=_knee_reach(thigh, shank, lo[3]), reach_max=_knee_reach(thigh, shank, up[3]))

        # Arm: shoulder pitch about -y then roll about z, meeting at the shoulder.
        an = [s + j for j in ARM_JOINTS]
        shoulder = origin(an[0])
        _expect(np.allclose(origin(an[1]), shoulder, atol=tol), "shoulder axes do not meet")
        _expect(np.allclose(axis(an[0]), -ey, atol=tol) and np.allclose(axis(an[1]), [0, 0, 1], atol=tol),
                "shoulder axes are not -y, z")
        lowerarm = next(ln for ln in nao.links(kin.robot_type) if ln.name == f"{s}lowerarm")
        half = nao.size_to_project(lowerarm.size)[0] / 2
        tip = d.oMf[m.getFrameId(f"{s}lowerarm")].translation + np.array([half, 0.0, 0.0])
        aidx = kin.arm_indices(s)[:2]
        arms[s] = ArmGeometry(side=s, shoulder=shoulder, hand=tip - shoulder,
                              lower=kin.lower[aidx].copy(), upper=kin.upper[aidx].copy())
    return LegsGeometry(kin.robot_type, legs["l"], legs["r"], arms["l"], arms["r"])


@functools.cache
def leg_geometry(robot_type: int) -> LegsGeometry:
    """IK geometry of robot type `robot_type` (cached; read off the pinocchio model)."""
    return geometry_from(RobotKinematics(robot_type))

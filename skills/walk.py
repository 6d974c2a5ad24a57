"""The omnidirectional walk engine of UT Austin Villa (dissertation section 8.2.5).

A double linear inverted pendulum chooses the torso's trajectory over the
stance foot; the feet follow simple smooth functions of the phase: a cosine
lift, a cosh side-to-side shift, a sigmoid forward swing and a cosine groin
(hip yaw-pitch) rotation for turning. Requested velocities in [-1, 1] are
filtered by a proportional controller into step sizes clamped at the maximum
steps; a center-of-mass error shrinks the steps; torso tilt and roll (from the
IMU) tilt the feet back level; balance steps (off in the shipped sets) put the
swing foot toward where the torso leans. Inverse kinematics turns the foot targets into
joint angles. When asked to stop, the robot jogs in place for half a second,
then stands.

Frames: foot targets are ankle positions and foot orientations in the torso
frame (x forward, y left, z up; m, rad). Odometry is the torso's motion over
the ground in its own frame since the previous call (m, m, rad); its turn is the
gyro's when the caller passes the gyro.

Phase bookkeeping follows the dissertation: the phase phi runs from phi_start
to phi_end (initially -0.5 .. 0.5) at 1/phase_length per second; at the end the
feet swap roles and the new pendulum starts where its lateral position matches
the old one: cosh(0.5 k phi_start) = 6 - cosh(0.5 k phi_end), k = sqrt(g / z).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from models import nao
from models.rules import CYCLE
from skills import _kernels as kernels
from skills.ik import LegIK
from skills.kinematics import RobotKinematics
from skills.params import PathLike, load_param_sets

G = 9.80665
FOOT_SEPARATION = 0.10  # m between the ankles at rest (UT's fixed value)
STOP_JOG_TIME = 0.5  # s of jogging in place before standing still
STAND_DAMP_TIME = 1.0  # s after a stop request that the ankles' gyro damping stays on ...
STAND_DAMP_FADE = 0.5  # s ... before it has faded out (see `foot_targets`)
BALANCE_SMOOTHING = 0.3  # weight of a new tilt/roll estimate in the balance terms' low-pass
BALANCE_STEP_OUT = 0.06  # m: most a balance step moves the swing foot (forward, back or out) ...
BALANCE_STEP_IN = 0.02  # m ... and inward, toward the stance foot
DATA = Path(__file__).parent / "data"
_ZERO3 = np.zeros(3)  # the kernel's gyro when there is none

# Parameter files name these (UT names); units as UT writes them, converted once at load.
WALK_SCHEMA: dict[str, str] = {
    "max_step_size_x": "mm", "max_step_size_y": "mm", "max_step_size_angle": "rad",
    "shift_amount": "mm", "walk_height": "mm", "step_height": "mm",
    "fraction_still": "1", "fraction_on_ground": "1", "fraction_moving": "1",
    "fraction_in_air": "1", "phase_length": "s", "default_com_pos_x": "mm",
    "pid_step_size_x": "1", "pid_step_size_y": "1", "pid_step_size_rot": "1",
    "max_normal_com_error": "mm", "max_acceptable_com_error": "mm",
    "fwd_offset": "mm", "fwd_offset_factor": "1", "swing_ankle_offset": "rad",
    "pid_tilt": "1", "pid_roll": "1", "pid_com_x": "1", "pid_com_y": "1", "pid_com_z": "1",
    "pid_arm_x": "1", "pid_arm_y": "1",
    "toe_const_offset": "rad", "toe_amplitude": "rad", "toe_phase_offset": "rad",
    "ankle_const_offset": "rad", "ankle_amplitude": "rad", "ankle_phase_offset": "rad",
    "arm_pitch": "rad", "arm_roll": "rad",
    # Additions to UT's set: gyro damping of the ankles (rad of foot turn per rad/s;
    # gyro_pitch_walk more at a full forward step) and the joint controller's
    # proportional gain (1/s) the walk is tuned with.
    "gyro_pitch": "1", "gyro_roll": "1", "joint_kp": "1", "heading_gain": "1", "gyro_pitch_walk": "1",
    "backward_factor": "1",
    # The forward swing's sigmoid steepness (UT: 10); lower is gentler on the motors.
    "swing_steepness": "1",
    # Balance steps: the swing foot goes toward where the torso leans, by balance_step_x
    # (forward) and balance_step_y (sideways) m per rad of tilt and roll beyond the deadband.
    "balance_step_x": "1", "balance_step_y": "1", "balance_deadband": "rad",
    # The landed foot's offset fades over this fraction of the next step (the torso moves over it).
    "balance_fade": "1",
    # A backward swing's fraction_still (< 0: fraction_still). Lowering the foot and swinging
    # it back both extend the hip, so a late backward swing meets the joints' speed cap.
    "backward_fraction_still": "1",
    # The swing foot's lift in place, growing to step_height with the step (< 0: step_height).
    # The 40 mm lift swings knee and ankle at their speed cap: stepping in place the foot
    # landed behind its target and the robot drifted backward.
    "slow_step_height": "mm",
}

# The named parameter sets of section 4.1 and the prefix each has in parameter files.
WALK_SETS: dict[str, str] = {
    "go_to_target": "", "sprint": "sprint_", "position_to_dribble": "dribble_",
    "approach_to_kick": "approach_",
}


@dataclass(frozen=True)
class WalkParams:
    """One walk parameter set, SI units."""

    max_step_size_x: float = 0.05
    max_step_size_y: float = 0.04
    max_step_size_angle: float = 1.22
    shift_amount: float = 0.02
    walk_height: float = 0.175
    step_height: float = 0.02
    fraction_still: float = 0.2
    fraction_on_ground: float = 0.2
    fraction_moving: float = 0.6
    fraction_in_air: float = 0.6
    phase_length: float = 0.38
    default_com_pos_x: float = 0.0
    pid_step_size_x: float = 0.03
    pid_step_size_y: float = 0.03
    pid_step_size_rot: float = 0.03
    max_normal_com_error: float = 0.0075
    max_acceptable_com_error: float = 0.0125
    fwd_offset: float = 0.0025
    fwd_offset_factor: float = 0.5
    swing_ankle_offset: float = -0.0873
    pid_tilt: float = 0.15
    pid_roll: float = 0.2
    # UT's CoM and arm-y balance gains: read so that UT-style files load, not used by
    # this engine (its CoM feedback is the step factor above; its arms swing by pid_arm_x).
    pid_com_x: float = 1.0
    pid_com_y: float = 1.0
    pid_com_z: float = 0.0
    pid_arm_x: float = 0.0
    pid_arm_y: float = 0.0
    toe_const_offset: float = 0.0
    toe_amplitude: float = 0.0
    toe_phase_offset: float = 0.0
    ankle_const_offset: float = 0.0
    ankle_amplitude: float = 0.0
    ankle_phase_offset: float = 0.0
    arm_pitch: float = -1.5
    arm_roll: float = 0.15
    gyro_pitch: float = 0.0
    gyro_roll: float = 0.0
    gyro_pitch_walk: float = 0.0
    joint_kp: float = 15.0
    heading_gain: float = 0.0
    backward_factor: float = 0.5
    swing_steepness: float = 10.0
    balance_step_x: float = 0.0
    balance_step_y: float = 0.0
    balance_deadband: float = 0.0
    balance_fade: float = 1.0
    backward_fraction_still: float = -1.0
    slow_step_height: float = -1.0

    @classmethod
    def from_values(cls, values: Mapping[str, float], base: WalkParams | None = None) -> WalkParams:
        known = {f.name for f in fields(cls)}
        kw = {k: v for k, v in values.items() if k in known}
        return cls(**{**(base.__dict__ if base else {}), **kw})


def default_param_files(robot_type: int) -> list[Path]:
    """The shipped walk parameter files for a robot type, general first."""
    files = [DATA / "walk_defaults.txt", DATA / f"walk_type{robot_type}.txt"]
    return [f for f in files if f.exists()]


def load_walk_sets(paths: Iterable[PathLike]) -> dict[str, WalkParams]:
    """Every named walk set from parameter files (later files override earlier ones).

    Unprefixed names set go-to-target; a set with a prefix starts from
    go-to-target's values and overrides what its prefixed names give.
    """
    raw = load_param_sets(list(paths), WALK_SCHEMA, WALK_SETS.values())
    base = WalkParams.from_values(raw[""])
    return {name: WalkParams.from_values(raw[prefix], base) if prefix else base
            for name, prefix in WALK_SETS.items()}


def direction_to_xy(direction: float, max_x: float, max_y: float) -> tuple[float, float]:
    """Walk inputs (x, y) in [-1, 1] for walking toward `direction` (rad, torso frame)
    as fast as possible given the sets' maximum speeds (section 8.2.5's formula)."""
    c, s = math.cos(direction), math.sin(direction)
    ax, ay = abs(c) * max_y, abs(s) * max_x
    if ay <= ax:  # |tan(direction)| <= max_y / max_x: x saturates
        x, y = 1.0, (abs(s) / abs(c)) * max_x / max_y if c != 0 else 1.0
    else:
        x, y = (abs(c) / abs(s)) * max_y / max_x, 1.0
    return math.copysign(x, c), math.copysign(y, s)


@dataclass
class WalkOutput:
    """Joint targets (rad, league order; head entries NaN: the walk leaves the head
    alone) and odometry (dx, dy, dtheta) of the torso since the last call (torso
    frame, m and rad; dtheta from the gyro when the engine has it, standing too)."""

    targets: np.ndarray
    odometry: tuple[float, float, float]
    standing: bool


class WalkEngine:
    """The walk of one robot: call `update` once per 20 ms cycle.

    The cycle runs compiled (`skills._kernels.walk_update`, its center of mass too) over
    a state vector; the phase, step and balance terms read as attributes."""

    def __init__(self, robot_type: int, sets: Mapping[str, WalkParams] | None = None,
                 dt: float = CYCLE) -> None:
        self.robot_type = robot_type
        self.sets = dict(sets) if sets is not None else load_walk_sets(default_param_files(robot_type))
        self.params = self.sets["go_to_target"]
        self.dt = dt
        self.ik = LegIK(robot_type)
        self.kin = RobotKinematics(robot_type)
        self.names = nao.joint_names(robot_type)
        self.index = {n: i for i, n in enumerate(self.names)}
        self.legs = {s: np.array([self.index[f"{s}lj{k}"] for k in range(1, 7)]) for s in "lr"}
        geo = self.ik.geom
        self.hip = {s: np.asarray(geo.leg(s).hip, dtype=float) for s in "lr"}
        # The kernels' constants: both legs' IK constants (hip center first) and the
        # target indices of `skills._kernels.I_LEGS` and after.
        self._legs = np.stack([geo.left.kconsts, geo.right.kconsts])
        ix = self.index
        toe = nao.robot_type(robot_type).toe
        toes = [ix[f"{s}lj{j}"] for s in "lr" for j in (7, 5)] if toe else [0, 0, 0, 0]
        arms = ("laj1", "raj1", "laj2", "raj2", "laj3", "raj3", "laj4", "raj4")
        self._idx = np.array([*self.legs["l"], *self.legs["r"], *(ix[n] for n in arms), int(toe), *toes],
                             dtype=np.int64)
        self._pvecs: dict[int, tuple[WalkParams, np.ndarray]] = {}
        self._s = np.zeros(kernels.WALK_STATE)
        self._feet = np.zeros((2, 6))
        self._full = np.zeros(len(self.names))
        self.reset()

    def step_begins(self) -> bool:
        """True in the first cycle of a walk step, with both feet still down (a change of
        support: where a stop or a change of walk set does not trip the robot)."""
        return self.phi - self.phi_start < 1e-9 + self.dt / self.params.phase_length

    def reset(self) -> None:
        """Stand still, as after a getup or a beam."""
        s = self._s
        s[:] = 0.0
        s[kernels.S_PHI_START], s[kernels.S_PHI_END] = -0.5, 0.5
        s[kernels.S_PHI] = -0.5
        s[kernels.S_STOP_TIME] = STAND_DAMP_TIME + STAND_DAMP_FADE  # zero velocity asked long ago
        s[kernels.S_STEP_FACTOR] = 1.0

    # ---------------------------------------------------------------- the state

    @property
    def phi_start(self) -> float:
        """Phase at which the current step began."""
        return float(self._s[kernels.S_PHI_START])

    @property
    def phi_end(self) -> float:
        """Phase at which the current step ends (the feet swap)."""
        return float(self._s[kernels.S_PHI_END])

    @property
    def phi(self) -> float:
        """The walk's phase now."""
        return float(self._s[kernels.S_PHI])

    @property
    def swing(self) -> str:
        """The swinging foot: "l" or "r"."""
        return "r" if self._s[kernels.S_SWING] else "l"

    @property
    def step(self) -> np.ndarray:
        """Current step sizes x (m), y (m), theta (rad) (a copy)."""
        return self._s[kernels.S_STEP_X:kernels.S_STEP_TH + 1].copy()

    @property
    def walking(self) -> bool:
        """Stepping (jogging in place too), not standing."""
        return bool(self._s[kernels.S_WALKING])

    @property
    def stop_time(self) -> float:
        """s since zero velocity was requested."""
        return float(self._s[kernels.S_STOP_TIME])

    @property
    def tilt(self) -> float:
        """Low-passed torso pitch (rad) the feet turn against."""
        return float(self._s[kernels.S_TILT])

    @property
    def roll(self) -> float:
        """Low-passed torso roll (rad) the feet turn against."""
        return float(self._s[kernels.S_ROLL])

    @property
    def step_factor(self) -> float:
        """The center-of-mass error's factor on the steps (0..1)."""
        return float(self._s[kernels.S_STEP_FACTOR])

    @property
    def gyro(self) -> np.ndarray:
        """The last cycle's gyro (rad/s, torso frame; zeros without one; a copy)."""
        return self._s[kernels.S_GYRO_X:kernels.S_GYRO_Z + 1].copy()

    @property
    def heading_error(self) -> float:
        """rad turned beyond the requested turn while walking."""
        return float(self._s[kernels.S_HEADING_ERROR])

    @property
    def turn_step(self) -> float:
        """rad per phase the feet turn, with the heading correction."""
        return float(self._s[kernels.S_TURN_STEP])

    @property
    def latched(self) -> tuple[float, float]:
        """Side step (m) and turn (rad) of the current step."""
        return float(self._s[kernels.S_LATCHED_Y]), float(self._s[kernels.S_LATCHED_TH])

    @property
    def expected_com(self) -> np.ndarray | None:
        """The CoM (m, torso frame) the last targets put the body at (a copy); None after
        a reset. The next cycle's measured CoM is held against it."""
        s, i = self._s, kernels.S_EXPECTED_COM
        return s[i:i + 3].copy() if s[kernels.S_HAS_EXPECTED_COM] else None

    def _param_vector(self, p: WalkParams) -> np.ndarray:
        """The kernels' vector of `p` (`skills._kernels.WALK_PARAMS`), made once per set."""
        hit = self._pvecs.get(id(p))
        if hit is None or hit[0] is not p:
            hit = self._pvecs[id(p)] = (p, np.array([float(getattr(p, n)) for n in kernels.WALK_PARAMS]))
        return hit[1]

    # ---------------------------------------------------------------- the cycle

    def update(self, x: float, y: float, turn: float, set_name: str = "go_to_target",
               tilt: float = 0.0, roll: float = 0.0, gyro: np.ndarray | None = None,
               joints: np.ndarray | None = None) -> WalkOutput:
        """One cycle: desired speeds in [-1, 1] of the set's maximum steps.

        tilt/roll: the torso's estimated pitch (forward positive) and roll (rad,
        from the IMU); joints: measured angles (league order) for the center of
        mass feedback; gyro: the torso's angular velocity (rad/s, torso frame).
        """
        s, pv, legs, idx, com_int, com_float, dt, feet, full = self._kernel_args(set_name)
        has_gyro, has_joints = gyro is not None, joints is not None
        q = np.empty(len(self.names))
        standing, ox, oy, oth = kernels.walk_update(
            s, pv, legs, idx, float(x), float(y), float(turn), float(tilt), float(roll),
            np.ascontiguousarray(gyro, dtype=float) if has_gyro else _ZERO3, has_gyro,
            np.ascontiguousarray(joints, dtype=float) if has_joints else full, has_joints,
            com_int, com_float, dt, feet, q, full)
        return WalkOutput(q, (ox, oy, oth), standing)

    def select(self, set_name: str) -> WalkParams:
        """Walk with set `set_name` from now, or, while a step is under way, from the next
        step's beginning (a change of set mid-swing can trip the robot); the set in use."""
        if set_name not in self.sets:
            raise KeyError(f"unknown walk set {set_name!r}; sets are {', '.join(self.sets)}")
        p = self.sets[set_name]
        if p is not self.params and (not self.walking or self.step_begins()):
            self.params = p
        return self.params

    def _kernel_args(self, set_name: str) -> tuple:
        """Take walk set `set_name` for this cycle; the walk kernels' state, parameters and
        tables: (state, params, leg constants, target indices, the CoM tables, dt, feet
        scratch, CoM scratch)."""
        p = self.select(set_name)
        kin = self.kin
        return (self._s, self._param_vector(p), self._legs, self._idx, kin._com_int, kin._com_float, self.dt,
                self._feet, self._full)

    # -------------------------------------------------------------- foot targets

    def foot_targets(self, standing: bool = False) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """(ankle position, foot rpy) per side in the torso frame for the current phase,
        the swinging foot first.

        The lift is a cosine over the in-air fraction; the stance foot slides back
        uniformly while the swing foot swings forward on a sigmoid; side to side the
        pendulum's cosh shift plus the side step (the leading foot steps out, the feet
        never cross); the groin turns the feet (a left turn is led by the right foot,
        as the hip yaw-pitch only turns toes in); the feet turn against the low-passed
        tilt and roll, with gyro damping that fades out once the robot stands; a balance
        step moves the swing foot toward where the torso leans, and the foot keeps that
        offset as it lands, fading over `balance_fade` of the next step.
        """
        feet = np.empty((2, 6))
        kernels.walk_feet(self._s, self._param_vector(self.params), self._legs, bool(standing), feet)
        swing = self.swing
        stance = "r" if swing == "l" else "l"
        return {side: (feet[i, :3].copy(), feet[i, 3:].copy())
                for side, i in ((swing, "lr".index(swing)), (stance, "lr".index(stance)))}

"""The walk engine in plain Python: the reference `skills._kernels.walk_update` and
`walk_feet` follow line for line (tests compare them bit for bit)."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from models import nao
from models.rules import CYCLE
from skills.ik import LegIK
from skills.kinematics import RobotKinematics
from skills.walk import (
    BALANCE_SMOOTHING,
    BALANCE_STEP_IN,
    BALANCE_STEP_OUT,
    FOOT_SEPARATION,
    STAND_DAMP_FADE,
    STAND_DAMP_TIME,
    STOP_JOG_TIME,
    G,
    WalkOutput,
    WalkParams,
    default_param_files,
    load_walk_sets,
)


def _clip(v: float, lo: float, hi: float) -> float:
    """np.clip of one float (NaN stays NaN)."""
    return lo if v < lo else hi if v > hi else v


def _dead(v: float, band: float) -> float:
    return v - band if v > band else v + band if v < -band else 0.0


def _sigmoid(v: float) -> float:
    return 1.0 / (1.0 + math.exp(-v))



class WalkEngineRef:
    """`skills.walk.WalkEngine` in plain Python (its update, foot targets and swap)."""

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
        # _targets' indices, looked up once: each leg as a slice where its joints are
        # consecutive (league order), the arm joints, the toes and ankle pitches.
        self._leg_at = {}
        for s, ix in self.legs.items():
            start = int(ix[0])
            run = np.array_equal(ix, np.arange(start, start + 6))
            self._leg_at[s] = slice(start, start + 6) if run else ix
        ix = self.index
        self._arms = (ix["laj1"], ix["raj1"], ix["laj2"], ix["raj2"])
        self._arms_zero = tuple(ix[n] for n in ("laj3", "raj3", "laj4", "raj4"))
        self._toe = nao.robot_type(robot_type).toe
        self._toes = tuple((ix[f"{s}lj7"], ix[f"{s}lj5"]) for s in "lr") if self._toe else ()
        self._nan = np.full(len(self.names), np.nan)
        self.reset()

    def step_begins(self) -> bool:
        """True in the first cycle of a walk step, with both feet still down (a change of
        support: where a stop or a change of walk set does not trip the robot)."""
        return self.phi - self.phi_start < 1e-9 + self.dt / self.params.phase_length

    def reset(self) -> None:
        """Stand still, as after a getup or a beam."""
        self.phi_start, self.phi_end = -0.5, 0.5
        self.phi = self.phi_start
        self.swing = "l"
        self.step = np.zeros(3)  # current step sizes x (m), y (m), theta (rad)
        self.walking = False
        self.stop_time = STAND_DAMP_TIME + STAND_DAMP_FADE  # s since zero velocity was requested (long ago)
        self.tilt = 0.0
        self.roll = 0.0
        self.step_factor = 1.0
        self.expected_com: np.ndarray | None = None
        self.gyro = np.zeros(3)
        self.balance = (0.0, 0.0)  # the swing foot's balance step (m, x and y, torso frame)
        self.balance_stance = (0.0, 0.0)  # the stance foot's, the one it landed with
        self.heading_error = 0.0  # rad turned beyond the requested turn while walking
        self.turn_step = 0.0  # rad per phase the feet turn, with the heading correction
        self.latched = (0.0, 0.0)  # side step (m) and turn (rad) of the current step

    # ---------------------------------------------------------------- the cycle

    def update(self, x: float, y: float, turn: float, set_name: str = "go_to_target",
               tilt: float = 0.0, roll: float = 0.0, gyro: np.ndarray | None = None,
               joints: np.ndarray | None = None) -> WalkOutput:
        """One cycle: desired speeds in [-1, 1] of the set's maximum steps.

        tilt/roll: the torso's estimated pitch (forward positive) and roll (rad,
        from the IMU); joints: measured angles (league order) for the center of
        mass feedback; gyro: the torso's angular velocity (rad/s, torso frame).
        """
        if set_name not in self.sets:
            raise KeyError(f"unknown walk set {set_name!r}; sets are {', '.join(self.sets)}")
        p = self.sets[set_name]
        if p is not self.params and self.walking and not self.step_begins():
            p = self.params  # a new set takes over as a step begins
        self.params = p
        # Scalar floats (the same operations as the 3-arrays they replaced, bit for bit).
        mx, my, ma = p.max_step_size_x, p.max_step_size_y, p.max_step_size_angle
        dx = _clip(float(x), -1.0, 1.0) * mx
        dy = _clip(float(y), -1.0, 1.0) * my
        dt_ = _clip(float(turn), -1.0, 1.0) * ma
        if dx < 0:  # backward steps are shorter (the feet land toe first otherwise)
            dx *= p.backward_factor
        moving = abs(dx) > 1e-9 or abs(dy) > 1e-9 or abs(dt_) > 1e-9
        self.stop_time = 0.0 if moving else self.stop_time + self.dt
        # Proportional step-size filter, clamped at the maximum steps.
        s0, s1, s2 = self.step.tolist()
        s0 = _clip(s0 + p.pid_step_size_x * (dx - s0), -mx, mx)
        s1 = _clip(s1 + p.pid_step_size_y * (dy - s1), -my, my)
        s2 = _clip(s2 + p.pid_step_size_rot * (dt_ - s2), -ma, ma)
        # Center-of-mass error feedback (sensed vs expected a cycle ago) shrinks the steps.
        if joints is not None and self.expected_com is not None:
            com, exp = self.kin.com(joints), self.expected_com
            err = max(abs(float(com[0] - exp[0])), abs(float(com[1] - exp[1])))
            span = max(p.max_acceptable_com_error - p.max_normal_com_error, 1e-6)
            self.step_factor = 1.0 - min(1.0, max(0.0, (err - p.max_normal_com_error) / span))
            f = self.step_factor
            s0, s1, s2 = s0 * f, s1 * f, s2 * f
        self.step = np.array([s0, s1, s2])
        # Balance: the feet turn against the torso's tilt and roll (low-passed),
        # with gains pid_tilt and pid_roll: a torso falling forward presses its toes down.
        self.tilt += BALANCE_SMOOTHING * (tilt - self.tilt)
        self.roll += BALANCE_SMOOTHING * (roll - self.roll)
        self.gyro = np.zeros(3) if gyro is None else np.asarray(gyro, dtype=float)
        standing = not moving and self.stop_time >= STOP_JOG_TIME
        if standing:
            self.walking = False
            self.heading_error = 0.0
            self.turn_step = 0.0
            self.phi = self.phi_start
            self.step[:] = 0.0
            self.balance = self.balance_stance = (0.0, 0.0)
            targets = self._targets(standing=True)
            # Standing, the torso still turns as it settles over feet a turn left
            # at different yaws (10-25 deg after a turn in place): the gyro counts it.
            turned = float(self.gyro[2]) * self.dt if gyro is not None else 0.0
            return WalkOutput(targets, (0.0, 0.0, turned), True)
        new_phase = not self.walking
        self.walking = True
        self.phi += self.dt / p.phase_length
        if self.phi >= self.phi_end:
            self._swap()
            new_phase = True
        span = self.phi_end - self.phi_start
        # The torso moves one step per phase over the ground.
        frac = self.dt / (p.phase_length * span)
        # Heading hold: the gyro measures how far the torso turned beyond (or short of)
        # the requested turn; the feet turn against that error (heading_gain per phase).
        turned = self.gyro[2] * self.dt if gyro is not None else self.turn_step * frac
        self.heading_error += turned - s2 * frac
        limit = p.max_step_size_angle
        wanted_turn = _clip(s2 - p.heading_gain * self.heading_error, -limit, limit)
        if new_phase:  # side step and turn are fixed for a whole step, so no foot changes lead
            self.latched = (s1, wanted_turn)
        self.turn_step = self.latched[1]
        # Balance step: the swing foot goes toward where the torso leans.
        sign = 1.0 if self.swing == "l" else -1.0
        bx = _clip(p.balance_step_x * _dead(self.tilt, p.balance_deadband),
                   -BALANCE_STEP_OUT, BALANCE_STEP_OUT)
        outward = _clip(-sign * p.balance_step_y * _dead(self.roll, p.balance_deadband),
                        -BALANCE_STEP_IN, BALANCE_STEP_OUT)
        self.balance = (bx, sign * outward)
        targets = self._targets(standing=False)
        odo = (s0 * frac, self.latched[0] * frac, turned)
        return WalkOutput(targets, odo, False)

    def _swap(self) -> None:
        p = self.params
        k = math.sqrt(G / p.walk_height)
        alpha = 6.0 - math.cosh(0.5 * k * self.phi_end)
        start = -math.acosh(alpha) / (0.5 * k) if alpha >= 1.0 else -0.5
        start = max(start, -0.5)
        self.phi_start, self.phi_end = start, -start
        self.phi = self.phi_start
        self.swing = "r" if self.swing == "l" else "l"
        self.balance_stance = self.balance  # the swing foot has landed

    # -------------------------------------------------------------- foot targets

    @staticmethod
    def _lift(p, sx: float, sy: float, sth: float) -> float:
        """The swing foot's lift (m): slow_step_height in place growing to step_height with
        the step's share of its bound (< 0: step_height throughout)."""
        if p.slow_step_height < 0:
            return p.step_height
        bx = p.max_step_size_x * (p.backward_factor if sx < 0 else 1.0)
        r = max(abs(sx) / max(bx, 1e-9), max(abs(sy) / max(p.max_step_size_y, 1e-9),
                                               abs(sth) / max(p.max_step_size_angle, 1e-9)))
        return p.slow_step_height + (p.step_height - p.slow_step_height) * min(r, 1.0)

    def foot_targets(self, standing: bool = False) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """(ankle position, foot rpy) per side in the torso frame for the current phase."""
        p = self.params
        t = 0.0 if standing else (self.phi - self.phi_start) / (self.phi_end - self.phi_start)
        t = min(max(t, 0.0), 1.0)
        k = math.sqrt(G / p.walk_height)
        # A swing (and a lift) must end within its step, whatever the fractions say.
        fs, fg = min(p.fraction_still, 0.9), min(p.fraction_on_ground, 0.9)
        fm, fa = min(p.fraction_moving, 1.0 - fs), min(p.fraction_in_air, 1.0 - fg)
        sx, sy, sth = (0.0, 0.0, 0.0) if standing else (self.step[0], *self.latched)
        swing, stance = self.swing, ("r" if self.swing == "l" else "l")
        sign = {"l": 1.0, "r": -1.0}
        # Gyro damping of the ankles steadies the steps and the sway after a stop; it fades
        # out once the robot stands, where its one-cycle-late feedback would feed the
        # stance's own 7 Hz sway (walk_defaults.txt says what that did).
        fade = 1.0
        if standing:
            fade = min(max((STAND_DAMP_TIME + STAND_DAMP_FADE - self.stop_time) / STAND_DAMP_FADE, 0.0), 1.0)
        gyro_roll, gyro_pitch = fade * p.gyro_roll, fade * p.gyro_pitch
        # Walking forward or back the ankles damp pitch harder, in proportion to the
        # step length (turning in place and standing keep gyro_pitch alone).
        gyro_pitch += p.gyro_pitch_walk * min(1.0, abs(sx) / max(p.max_step_size_x, 1e-9))
        # Lift: cosine during the in-air fraction.
        zfrac = 0.5 * (1 - math.cos(2 * math.pi * (t - fg) / fa)) if fg <= t <= fg + fa else 0.0
        # Forward: the stance foot slides back uniformly (the torso moves over it);
        # the swing foot swings forward on a sigmoid while in the moving fraction.
        # A backward swing may start moving sooner (backward_fraction_still; < 0: as fs).
        xs, xm = fs, fm
        if sx < 0 and p.backward_fraction_still >= 0:
            xs = min(p.backward_fraction_still, 0.9)
            xm = min(p.fraction_moving, 1.0 - xs)
        if t < xs:
            xfrac = -0.5 - t
        elif t < xs + xm:
            c = p.swing_steepness
            s = _sigmoid(c * (-0.5 + (t - xs) / xm))
            s0, s1 = _sigmoid(-0.5 * c), _sigmoid(0.5 * c)
            s = (s - s0) / (s1 - s0)
            xfrac = (-0.5 - xs) + s * ((1.5 - xs - xm) - (-0.5 - xs))
        else:
            xfrac = 1.5 - t
        x_stance, x_swing = sx * (0.5 - t), sx * xfrac
        dx = p.default_com_pos_x + p.fwd_offset - sx * p.fwd_offset_factor
        # Side to side: the cosh shift of the pendulum, plus the side step.
        phi = self.phi_start if standing else self.phi
        shift = 0.0 if standing else p.shift_amount * (-1.5 + 0.5 * math.cosh(0.5 * k * phi))
        y_stance = 0.5 * FOOT_SEPARATION + shift
        y_swing = FOOT_SEPARATION - y_stance
        if t < fs:
            yfrac = 0.0
        elif t < fs + fm:
            yfrac = 0.5 * (1 - math.cos(math.pi * (t - fs) / fm))
        else:
            yfrac = 1.0
        # Side step: the leading foot (on the side of motion) steps out by |sy| while it
        # swings, the trailing stance foot drifts out as the body moves over it; in the
        # next phase both come back. The feet never cross.
        lead = "l" if sy > 0 else "r"
        a = abs(sy)
        swing_out = a * yfrac if swing == lead else a * (1.0 - yfrac)
        stance_out = a * (1.0 - t) if stance == lead else a * t
        # Turning: the groin turns the feet by the same rule. The league's hip yaw-pitch
        # (-90..1 deg) only turns a foot's toes in, so a left turn is led by the right foot.
        groin = 0.0
        if t >= fs + fm:
            groin = abs(sth)
        elif t >= fs:
            groin = 0.5 * abs(sth) * (1 - math.cos(math.pi * (t - fs) / fm))
        tlead = "r" if sth > 0 else "l"
        swing_yaw = groin if swing == tlead else abs(sth) - groin
        stance_yaw = abs(sth) * (1.0 - t) if stance == tlead else abs(sth) * t
        out = {}
        for side, xo, yo, out_y, yaw, z in (
            (swing, x_swing, y_swing, swing_out, swing_yaw, self._lift(p, sx, sy, sth) * zfrac),
            (stance, x_stance, y_stance, stance_out, stance_yaw, 0.0),
        ):
            hip = self.hip[side]
            pos = np.array([hip[0] + xo + dx, sign[side] * (yo + out_y), hip[2] - p.walk_height + z])
            rpy = np.array([p.pid_roll * self.roll + gyro_roll * self.gyro[0],
                            p.pid_tilt * self.tilt + gyro_pitch * self.gyro[1], -sign[side] * yaw])
            if side == swing and not standing:  # toes up stepping forward, down stepping back
                rpy[1] += p.swing_ankle_offset * zfrac * (1.0 if sx >= 0 else -1.0)
                pos[0] += self.balance[0] * yfrac
                pos[1] += self.balance[1] * yfrac
            elif not standing:  # the torso moves over where the foot landed
                fade = max(0.0, 1.0 - t / max(p.balance_fade, 1e-9))
                pos[0] += self.balance_stance[0] * fade
                pos[1] += self.balance_stance[1] * fade
            out[side] = (pos, rpy)
        return out

    def _targets(self, standing: bool) -> np.ndarray:
        p = self.params
        q = self._nan.copy()
        feet = self.foot_targets(standing)
        for side, (pos, rpy) in feet.items():
            q6, _ = self.ik.solve(side, pos, rpy, target="ankle")
            q[self._leg_at[side]] = q6
        # Arms hang with a little swing against the legs (pid_arm_x) for balance.
        swing_x = feet["l"][0][0] - feet["r"][0][0]
        la1, ra1, la2, ra2 = self._arms
        q[la1] = p.arm_pitch - p.pid_arm_x * swing_x
        q[ra1] = p.arm_pitch + p.pid_arm_x * swing_x
        q[la2] = p.arm_roll
        q[ra2] = -p.arm_roll
        for i in self._arms_zero:
            q[i] = 0.0
        if self._toe:
            t = 0.0 if standing else (self.phi - self.phi_start) / (self.phi_end - self.phi_start)
            toe = p.toe_amplitude * math.cos(t * math.pi + p.toe_phase_offset) + p.toe_const_offset
            ank = p.ankle_amplitude * math.cos(t * math.pi + p.ankle_phase_offset) + p.ankle_const_offset
            for i_toe, i_ank in self._toes:
                q[i_toe] = toe
                q[i_ank] += ank
        full = np.where(np.isnan(q), 0.0, q)
        self.expected_com = self.kin.com(full)
        return q

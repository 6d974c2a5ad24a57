"""How fast a kick swings the foot into the ball, against what the joints' speed limits allow.

For each kick and robot type, `--tries` standing kicks as `benchmarks.kick`
plays them (`optimization.kick.kick_trial`). Around the cycle in which the
ball starts to move (its speed passes 0.5 m/s):

* foot speed before and after: the speed of the foot's point that meets the
  ball (the ball's center less its radius along the direction it then takes),
  along that direction, at the last cycle before and the first after (20 ms
  apart: the contact lies between; m/s, world frame);
* launch speed: the ball's largest speed over the next 0.1 s (m/s);
* two kinematic bounds on that point's speed, with the support foot held still
  and every joint at its motor's speed limit in the helpful direction: the
  kicking leg's six joints alone ("leg"), and every joint between the feet
  ("legs": the support leg also tilts the body); the larger at the two poses.
  They ignore the torque it takes to reach the limits.

The first line gives the launch speed a roll of `--far` m needs
(`models.field.rolling_distance`). Ground truth only (a benchmark, not the agent).

    python -m benchmarks.kickspeed [--types 0] [--kicks long_kick_left ik_forward_left] [--tries 10]
                                   [--seed 0] [--far 15]
"""

from __future__ import annotations

import argparse
import json
import sys

import mujoco
import numpy as np
from scipy.optimize import brentq

from benchmarks.machine import machine
from models.field import BALL_RADIUS, rolling_distance
from optimization.kick import kick_trial
from server.world import World
from skills.kicks import all_kicks

LAUNCH = 0.5  # m/s: the ball counts as kicked above this speed
LAUNCH_WINDOW = 0.1  # s after the kick over which the launch speed is the ball's largest


def launch_speed_for(distance: float) -> float:
    """Ball speed (m/s) that rolls `distance` m before it rests."""
    return float(brentq(lambda v: rolling_distance(v) - distance, 1e-6, 100.0))


class SwingProbe:
    """Called after every cycle of one kick trial (`kick_trial`'s observe); keeps the
    state a cycle back and measures the contact speed and its bounds when the ball
    starts to move. kicking_foot: "lfoot" or "rfoot"."""

    def __init__(self, kicking_foot: str) -> None:
        self.kicking_foot = kicking_foot
        self.world: World | None = None  # bound at the first call
        self.prev: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.result: dict | None = None
        self._launch: tuple[float, list[float]] | None = None

    def _bind(self, world: World) -> None:
        m = world.model
        kicking_foot = self.kicking_foot
        self.world = world
        self.scratch = mujoco.MjData(m)
        body = {m.body(i).name.rsplit("/", 1)[-1]: i for i in range(m.nbody)}
        self.foot = body[kicking_foot]
        self.support = body["rfoot" if kicking_foot == "lfoot" else "lfoot"]
        free = [j for j in range(m.njnt) if m.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE]
        if len(free) != 1:
            raise ValueError("SwingProbe needs a scene with one robot")
        self.free = np.arange(m.jnt_dofadr[free[0]], m.jnt_dofadr[free[0]] + 6)
        self.hinges, self.leg, limits = [], [], []
        side = kicking_foot[0]
        for a in range(m.nu):
            j = int(m.actuator_trnid[a, 0])
            self.hinges.append(int(m.jnt_dofadr[j]))
            limits.append(float(m.actuator_ctrlrange[a, 1]))  # rad/s: the motor's speed limit
            self.leg.append(m.joint(j).name.rsplit("/", 1)[-1].startswith(f"{side}lj"))
        self.hinges = np.array(self.hinges)
        self.limits = np.array(limits)
        self.leg = np.array(self.leg)

    def __call__(self, world: World) -> None:
        if self.world is None:
            self._bind(world)
        d = world.data
        v = world.ball_velocity()[:3]
        if self._launch is not None:
            t0, speeds = self._launch
            if world.time - t0 <= LAUNCH_WINDOW + 1e-9:
                speeds.append(float(np.linalg.norm(v)))
                self.result["launch_speed"] = max(speeds)
        elif self.result is None and self.prev is not None and np.linalg.norm(v) > LAUNCH:
            u = v / np.linalg.norm(v)
            qpos, qvel, ball = self.prev
            before, local = self._measure(qpos, qvel, u, point=ball - BALL_RADIUS * u)
            after, _ = self._measure(d.qpos.copy(), d.qvel.copy(), u, local=local)
            self.result = {"speed_before": before["speed"], "speed_after": after["speed"],
                           "from_joints": before["from_joints"],
                           "bound_leg": max(before["bound_leg"], after["bound_leg"]),
                           "bound_legs": max(before["bound_legs"], after["bound_legs"]),
                           "launch_speed": float(np.linalg.norm(v))}
            self._launch = (world.time, [self.result["launch_speed"]])
        self.prev = (d.qpos.copy(), d.qvel.copy(), world.ball_position())

    def _measure(self, qpos: np.ndarray, qvel: np.ndarray, u: np.ndarray,
                 point: np.ndarray | None = None, local: np.ndarray | None = None
                 ) -> tuple[dict, np.ndarray]:
        """Speed along u of a point on the kicking foot at state (qpos, qvel), and the
        bounds; the point given in the world frame (`point`) or the foot's (`local`, m).
        Also returns the point in the foot's frame."""
        m, s = self.world.model, self.scratch
        s.qpos[:], s.qvel[:] = qpos, qvel
        mujoco.mj_forward(m, s)
        pos, rot = s.xpos[self.foot], s.xmat[self.foot].reshape(3, 3)
        world_point = pos + rot @ local if local is not None else np.asarray(point, dtype=float)
        jp, jr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jac(m, s, jp, jr, world_point, self.foot)
        sp, sr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        mujoco.mj_jacBody(m, s, sp, sr, self.support)
        S = np.vstack([sp, sr])  # the support foot's twist: held at zero
        A = jp[:, self.hinges] - jp[:, self.free] @ np.linalg.solve(S[:, self.free], S[:, self.hinges])
        gain = np.abs(u @ A) * self.limits  # m/s each joint can add along u
        return ({"speed": float(u @ (jp @ qvel)), "bound_leg": float(gain[self.leg].sum()),
                 "bound_legs": float(gain.sum()),
                 "from_joints": float(u @ (A @ qvel[self.hinges]))},  # the same, support foot still
                rot.T @ (world_point - pos))


def swing_stats(robot_type: int, kick_name: str, tries: int, seed: int) -> dict:
    """Mean foot, launch speeds and bounds over `tries` standing kicks (one JSON row)."""
    kick = all_kicks(robot_type)[kick_name]
    foot = "rfoot" if kick_name.endswith("_right") else "lfoot"
    rng = np.random.default_rng([seed, robot_type, sum(map(ord, kick_name))])
    rows, dist = [], []
    for i in range(tries):
        probe = SwingProbe(foot)
        r = kick_trial(robot_type, kick, "standing", rng, seed * 1000 + i, observe=probe)
        dist.append(r["distance"])
        if probe.result is not None:
            rows.append(probe.result)
    out = {"kick": kick_name, "robot_type": robot_type, "tries": tries, "kicked": len(rows),
           "distance_mean_m": round(float(np.mean(dist)), 2)}
    if rows:
        mean = {k: float(np.mean([r[k] for r in rows])) for k in rows[0]}
        out.update({
            "foot_speed_before_mps": round(mean["speed_before"], 2),
            "foot_speed_after_mps": round(mean["speed_after"], 2),
            "launch_speed_mean_mps": round(mean["launch_speed"], 2),
            "bound_leg_mean_mps": round(mean["bound_leg"], 2),
            "bound_legs_mean_mps": round(mean["bound_legs"], 2),
            "foot_speed_over_leg_bound": round(max(mean["speed_before"], mean["speed_after"])
                                               / mean["bound_leg"], 2),
        })
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", type=int, nargs="+", default=[0], choices=range(5), metavar="T")
    ap.add_argument("--kicks", nargs="+", default=["long_kick_left", "ik_forward_left"])
    ap.add_argument("--tries", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--far", type=float, default=15.0, help="distance (m) whose launch speed to print")
    args = ap.parse_args(argv)
    if args.tries < 1:
        ap.error(f"--tries must be at least 1, not {args.tries}")
    if args.far <= 0:
        ap.error(f"--far must be positive, not {args.far}")
    known = set(all_kicks(0))
    for k in args.kicks:
        if k not in known:
            ap.error(f"unknown kick {k!r}; one of {', '.join(sorted(known))}")
    print(json.dumps({"machine": machine(), "far_m": args.far,
                      "launch_speed_for_far_mps": round(launch_speed_for(args.far), 2)}), flush=True)
    for t in args.types:
        for k in args.kicks:
            print(json.dumps(swing_stats(t, k, args.tries, args.seed)), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

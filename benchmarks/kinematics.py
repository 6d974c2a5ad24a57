"""Microbenchmark of the agent's kinematics: FK + CoM, closed-form leg IK, numeric leg IK.

Run: python benchmarks/kinematics.py [--type T] [--n N]
Prints JSON lines: machine info first, then microseconds per call.
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
import time

import numpy as np
import pinocchio as pin

from benchmarks.machine import cpu_model
from skills.frames import matrix_to_rpy
from skills.ik import LegIK
from skills.kinematics import RobotKinematics


def per_call_us(fn, args_list, repeat: int = 3) -> float:
    """Best-of-`repeat` mean microseconds of fn(*args) over args_list."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for args in args_list:
            fn(*args)
        best = min(best, (time.perf_counter() - t0) / len(args_list))
    return best * 1e6


class NumericLegIK:
    """Damped least squares on one leg's six joints with pinocchio's frame Jacobian."""

    def __init__(self, kin: RobotKinematics, iterations: int = 5, damping: float = 1e-6):
        self.kin, self.iterations, self.damping = kin, iterations, damping
        self.model, self.data = kin.model, kin.model.createData()
        self.fids = {s: self.model.getFrameId(f"{s}foot_sole") for s in "lr"}
        self.vidx = {s: kin._qidx[kin.leg_indices(s)] - 1 for s in "lr"}  # free flyer: nv = nq - 1

    def solve(self, side: str, target: pin.SE3, q_start: np.ndarray) -> np.ndarray:
        m, d, fid, vi = self.model, self.data, self.fids[side], self.vidx[side]
        q = self.kin.pin_q(q_start).copy()
        for _ in range(self.iterations):
            pin.forwardKinematics(m, d, q)
            err = pin.log6(pin.updateFramePlacement(m, d, fid).actInv(target)).vector
            J = pin.computeFrameJacobian(m, d, q, fid, pin.ReferenceFrame.LOCAL)[:, vi]
            dq = np.linalg.solve(J.T @ J + self.damping * np.eye(6), J.T @ err)
            q[vi + 1] += dq
        return q[vi + 1]


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--type", type=int, default=0)
    ap.add_argument("--n", type=int, default=2000)
    args = ap.parse_args(argv)
    print(json.dumps({
        "machine": platform.platform(), "cpu": cpu_model(), "python": sys.version.split()[0],
        "numpy": np.__version__, "pinocchio": pin.__version__,
    }))

    kin, ik = RobotKinematics(args.type), LegIK(args.type)
    rng = np.random.default_rng(0)
    # Walking-like postures: random angles within a band around the stand pose.
    stand = np.zeros(len(kin.joint_names))
    for s in "lr":
        stand[kin.leg_indices(s)] = [0.0, 0.0, 0.35, -0.7, 0.35, 0.0]
    qs = [np.clip(stand + rng.uniform(-0.3, 0.3, stand.shape), kin.lower, kin.upper) for _ in range(args.n)]
    feet = [kin.foot_poses(q) for q in qs]
    targets = [(L[:3, 3].copy(), matrix_to_rpy(L[:3, :3]), R[:3, 3].copy(), matrix_to_rpy(R[:3, :3]))
               for L, R in feet]

    def report(name: str, us: float, **extra) -> None:
        print(json.dumps({"bench": name, "type": args.type, "us_per_call": round(us, 2), **extra}))

    report("fk_feet_and_com", per_call_us(kin.feet_and_com, [(q,) for q in qs]))
    report("com", per_call_us(kin.com, [(q,) for q in qs]))
    report("ik_closed_form_both_legs", per_call_us(ik.solve_both, targets))
    report("ik_closed_form_one_leg", per_call_us(ik.solve, [("l", t[0], t[1]) for t in targets]))

    num = NumericLegIK(kin)
    se3 = [(pin.SE3(L[:3, :3], L[:3, 3]), pin.SE3(R[:3, :3], R[:3, 3])) for L, R in feet]

    def numeric_both(tl: pin.SE3, tr: pin.SE3) -> None:
        num.solve("l", tl, stand)
        num.solve("r", tr, stand)

    m = min(args.n, 500)
    report("ik_numeric_5iter_both_legs", per_call_us(numeric_both, se3[:m]))

    # Accuracy (sole position error, m) of each method on the same targets.
    err_cf, err_num = [], []
    for q, (L, _), (tl, _), t in zip(qs[:m], feet[:m], se3[:m], targets[:m]):
        q6, _ = ik.solve("l", t[0], t[1])
        q2 = q.copy()
        q2[kin.leg_indices("l")] = q6
        err_cf.append(np.linalg.norm(kin.foot_poses(q2)[0][:3, 3] - L[:3, 3]))
        q2[kin.leg_indices("l")] = num.solve("l", tl, stand)
        err_num.append(np.linalg.norm(kin.foot_poses(q2)[0][:3, 3] - L[:3, 3]))
    print(json.dumps({"accuracy": "max sole position error (m)", "closed_form": float(max(err_cf)),
                      "numeric_5iter_from_stand": float(max(err_num))}))


if __name__ == "__main__":
    main()

"""IK kicks in physics: distance, direction error and success per kick and robot type.

    python -m benchmarks.ikkick [--types 0,1] [--kicks ik_forward_left,...] [--tries 10] [--seed 0]
                                [--jitter 0.01] [--params FILE ...]

One JSON line per kick and type. Each try: a robot (Trainer, no referee) stands
0.5 s at the origin, the ball is put at the kick's `spec.ball` plus a seeded
uniform offset within +-jitter (m) on x and y, the kick is reset with the ball's
true offset (robot frame) and played from percepts only; then the robot stands
while the ball rolls to a stop (at most `--roll` s; the rest is extrapolated by
`World.ball_rest_position`). Figures: distance the ball moved (m), direction
error (deg, against `spec.direction`: the mean of its size, and its signed mean
(the bias, + to the left) and standard deviation, which tell aim from scatter),
success (the ball's displacement along the kick's direction is at least 1 m and
the robot did not fall), falls, and the backswing's clearance of the ball at the
spec's offset (mm, kinematics: `backswing_clearance`; below zero the foot grazes
the ball before the strike). The kick never reads simulator state; the trial
does, for the figures.
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import time
import zlib

import mujoco
import numpy as np

from agent.kicker import SKILL_GAINS
from benchmarks.walk import new_robot
from models import nao
from models.field import BALL_RADIUS
from models.geometry import Pose2, wrap
from models.messages import Action
from models.robot import robot_mjcf
from skills.kicks.ik import IkKick, ik_kicks

CLEARANCE_SAMPLES = 80  # samples of the backswing checked by `backswing_clearance`


def kick_trial(t: int, kick: IkKick, offset: tuple[float, float] = (0.0, 0.0), roll: float = 3.0,
               stand: float = 0.5) -> dict:
    """One kick in physics; returns distance (m), direction (rad, robot frame at the start),
    along (m, displacement along spec.direction), fell, and the direction's deviation
    from spec.direction (rad, + to the left) and its size (error)."""
    tr, mo = new_robot(t)
    w = tr.world
    for _ in range(round(stand / 0.02)):  # stand and kick at the kicks' gains, as the Kicker does
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0, kp=SKILL_GAINS[0]))})
    mo.skill_gains(SKILL_GAINS)
    x0, y0, h0 = w.player_pose(0)
    start = Pose2(x0, y0, h0)
    bx, by = kick.spec.ball[0] + offset[0], kick.spec.ball[1] + offset[1]
    w.place_ball(start.to_world(bx, by))
    b0 = w.ball_position()[:2].copy()
    kick.reset((bx, by))
    fell = False
    while not kick.done:
        pc = tr.percepts()[0]
        tr.step({0: Action(mo.command(kick.step(pc), pc))})
        if w.torso_up()[0] < 0.5:
            fell = True
            break
    mo.reset()
    n = round(roll / 0.02)
    for _ in range(n):
        if fell or np.linalg.norm(w.ball_velocity()[:2]) < 0.02:
            break
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
        if w.torso_up()[0] < 0.5:
            fell = True
    rest = w.ball_rest_position()  # a ball still rolling is carried on to its stop
    dx, dy = Pose2(b0[0], b0[1], h0).to_local(rest[0], rest[1])
    dist = math.hypot(dx, dy)
    direction = math.atan2(dy, dx)
    a = kick.spec.direction
    along = dx * math.cos(a) + dy * math.sin(a)
    return {"distance": dist, "direction": direction, "along": along, "fell": fell,
            "deviation": wrap(direction - a), "error": abs(wrap(direction - a))}


class _Scene:
    """One robot of a type and a free-floating ball geom, posed kinematically (no physics)."""

    def __init__(self, robot_type: int) -> None:
        xml = robot_mjcf(robot_type).replace(
            "</worldbody>", f'<body name="ball" mocap="true"><geom name="ball" type="sphere" '
            f'size="{BALL_RADIUS}" contype="0" conaffinity="0"/></body></worldbody>')
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        m = self.model
        self.qadr = np.array([m.jnt_qposadr[m.joint(n).id] for n in nao.joint_names(robot_type)])
        self.ball = m.geom("ball").id
        self.leg = {side: [g for g in range(m.ngeom) if m.body(m.geom_bodyid[g]).name in
                           (f"{side}shank", f"{side}ankle", f"{side}foot", f"{side}toe")]
                    for side in "lr"}


_SCENES: dict[int, _Scene] = {}


def backswing_clearance(kick: IkKick, ball: tuple[float, float] | None = None) -> tuple[float, float]:
    """Least distance (m) between the ball and the kicking shank, ankle, foot or toe while
    the foot swings back, before the strike; and the normalized swing time of it.

    Kinematics only: the torso upright where the kick puts it, the legs at the
    kick's IK targets, the ball at `ball` (robot frame, m; default the spec's). The
    backswing runs to the pull-back: the waypoint farthest back against the kick's
    direction. A backswing that grazes the ball rolls it off the strike's path (type
    4's toe clipped it in most walking IK 45-in kicks). Leaves `kick` reset to the
    spec's ball."""
    sc = _SCENES.setdefault(kick.robot_type, _Scene(kick.robot_type))
    m, d = sc.model, sc.data
    kick.reset(ball)
    u = np.array([math.cos(kick.spec.direction), math.sin(kick.spec.direction)])
    back = min(kick.params.waypoints, key=lambda w: float(u @ w.pos[:2])).t
    d.mocap_pos[0] = [kick.ball[0], kick.ball[1], BALL_RADIUS]
    best, at = math.inf, 0.0
    for s in np.linspace(0.0, back, CLEARANCE_SAMPLES + 1):
        t = kick.params.shift_time + float(s) * kick.params.swing_time
        _, torso, _ = kick.pose_at(t)
        q = kick.targets_at(t)
        d.qpos[:3] = torso
        d.qpos[3:7] = [1.0, 0.0, 0.0, 0.0]
        d.qpos[sc.qadr] = np.where(np.isnan(q), 0.0, q)
        mujoco.mj_kinematics(m, d)
        for g in sc.leg[kick.kick_side]:
            dist = mujoco.mj_geomDistance(m, d, sc.ball, g, 0.5, None)
            if dist < best:
                best, at = dist, float(s)
    kick.reset()
    return best, at


def run(types, names, tries, seed, jitter, params, roll) -> list[dict]:
    out = []
    for t in types:
        kicks = ik_kicks(t, params)
        for name in names or list(kicks):
            kick = kicks[name]
            rng = np.random.default_rng([seed, t, zlib.crc32(name.encode())])
            res = []
            t0 = time.perf_counter()
            for _ in range(tries):
                off = tuple(rng.uniform(-jitter, jitter, 2))
                res.append(kick_trial(t, kick, off, roll))
            dist = np.array([r["distance"] for r in res])
            err = np.degrees([r["error"] for r in res])
            dev = np.degrees([r["deviation"] for r in res])
            ok = [r["along"] >= 1.0 and not r["fell"] for r in res]
            line = {"kick": name, "type": t, "tries": tries, "jitter_m": jitter,
                    "distance_mean_m": round(float(dist.mean()), 3),
                    "distance_std_m": round(float(dist.std()), 3),
                    "direction_error_mean_deg": round(float(err.mean()), 1),
                    "direction_bias_deg": round(float(dev.mean()), 1),
                    "direction_sd_deg": round(float(dev.std()), 1),
                    "success_rate": round(sum(ok) / tries, 2),
                    "falls": sum(r["fell"] for r in res),
                    "backswing_clearance_mm": round(1000.0 * backswing_clearance(kick)[0], 1),
                    "seconds": round(time.perf_counter() - t0, 1),
                    "machine": f"{platform.node()} {platform.processor() or platform.machine()}"}
            print(json.dumps(line), flush=True)
            out.append(line)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--types", default="0")
    ap.add_argument("--kicks", default="")
    ap.add_argument("--tries", type=int, default=10)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--jitter", type=float, default=0.01)
    ap.add_argument("--roll", type=float, default=3.0)
    ap.add_argument("--params", nargs="*", default=[])
    a = ap.parse_args()
    run([int(x) for x in a.types.split(",")], [k for k in a.kicks.split(",") if k], a.tries, a.seed,
        a.jitter, a.params, a.roll)


if __name__ == "__main__":
    main()

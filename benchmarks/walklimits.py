"""Where a walk's speed is bounded: steps, joint speed caps, motor torque, foot contact.

For each robot type and walk set, the robot walks straight ahead (`--direction`:
forward, backward or left) at full input for `--seconds` s from the stand (as
`benchmarks.walk` measures speeds), its control reading only its percepts, and the
benchmark reads ground truth (speeds and steps along the direction):

* speed (m/s), steps per second and step length (m) against the speed the walk
  planned (its own odometry: where it put the feet) and the set's bound,
  `max_step_size_x / phase_length` (a full step every phase; a step lasts a whole
  number of 20 ms cycles, so 0.19 s steps come 5 a second; backward the step is
  `backward_factor` times that, sideways `max_step_size_y`);
* the walk's mean step factor: the share of the asked step it takes while the
  CoM the joints measure strays from the one its targets expect
  (`max_normal_com_error` .. `max_acceptable_com_error`; 1 is the whole step);
* per leg joint (left and right pooled, `lj1` hip yaw-pitch ... `lj6` ankle roll):
  the share of cycles whose command is at the joint's speed cap (6.14 rad/s;
  the server clamps anything above), the share of cycles ending with the motor
  at its torque limit (10 N m; sampled at the end of each 20 ms cycle), the mean
  lag |joint velocity - command| (rad/s) and the peak joint speed;
* the feet: the share of cycles with both feet loaded (double support) and
  with neither (flight), from the percept's foot forces (type 4: sole and toe),
  and how far the one loaded foot slides on the ground per step (m; a foot
  that pushes off while sliding carries the body less far than its step);
* the stand's torso height (m), which the kicks are tuned from.

A joint whose command sits at its cap, or a motor at its limit, most of a step
cannot swing faster: longer or quicker steps must come from elsewhere (a lower
lift, a flatter knee, the stand height). One JSON line per type and set, then a
table.

`--cap-scale` and `--torque-scale` raise the joints' speed cap and the motors'
torque limit for diagnosis (not the league's robot): whichever lets the walk go
faster is the bound that holds it back.

What it showed (type 0, December 2026): both shipped sets walk at their bound
(go-to-target 0.335 m/s, 5 steps/s x 64 mm; sprint 0.392, 6.2 x 63 mm), knee
and ankle pitch commanded at the speed cap 33-41% of cycles. Asked for longer
sprint steps (80, 100, 120 mm), a lower lift (20-35 mm) or another stand height
(175-200 mm), the walk planned up to 0.46 m/s but walked 0.34-0.42 with steps
no longer than 56-67 mm (or fell): slipping stayed 3-9 mm a step. With the
speed cap 1.5x the 80 mm sprint walked 0.467 m/s (75 mm steps); with twice the
torque 0.328. The 6.14 rad/s cap binds: a faster walk has to spend the joints'
speed better (the whole set learned together, as UT Austin Villa did), not ask
for longer steps.

The sprint set learned with its stand free (walk_type0.txt, `optimization/tasks/
sprint_forward.task`) does: 0.588 m/s at 6.2 steps/s x 95 mm, against 0.380
planned (59 mm steps), with both feet off the ground 20% of cycles and never
both down: it runs, and each flight carries it past its planned step. Knee and
ankle pitch sit at the cap 38-44% of cycles, as before. The walk's odometry
(what the world model dead-reckons with) then says 0.38 m/s.

Backward (December 6, 2026): the go-to-target sets then shipped walked backward at their bound
(type 0: 0.115 m/s, 22 mm steps), and a longer backward step walked no faster (backward_factor
0.7: 38 mm planned, 23 mm made, 0.119 m/s). The swing foot landed short: in the torso frame the
feet were 12 mm apart at the swap instead of 38. Hip and knee pitch sat at the speed cap in the
swing's last four cycles, and the hip was 14 deg short of its target at the swap. The swing
ran late in the step (after `fraction_still`, 0.40), where the foot comes down. Lowering the
foot and swinging it back both extend the hip, whereas walking forward the two cancel. With
the backward swing begun at once (`backward_fraction_still` 0), type 0 walked backward at 0.274
m/s with the shipped factor (0.307 at 0.5, 0.370 at 0.7, 0.416 at 1.0 with 18% of cycles in
flight). Types 1-4 went from 0.134/0.131/0.105/0.133 to 0.229/0.245/0.278/0.235 m/s. The robot
then walks about twice the step it plans: the torso pitches back by up to 4 deg over each
stance. Villa walks so since (walk_defaults.txt). Sideways the sets walk at their bound (type
0: 0.281 m/s), and type 2's ankle roll (capped at 3.47 rad/s) sits at its cap 26% of cycles. A
side step of 76 mm tipped type 2 over. With `fraction_still` 0.2 it walked 0.347 m/s, and type
0 0.376 (1.2x and 1.3x the shipped).

Slow (`--input`, type 0, go-to-target, 8 s): asked for 5% of a full step forward (15 mm/s
planned) the robot walks backward at 0.075 m/s; at 30% it makes 0.048 of 0.093 planned, and
30% backward makes 0.10 of 0.038 (0.18 with `backward_fraction_still` 0). Stepping in place,
the swing foot lands 14 mm behind its target: the 40 mm lift's knee and ankle swing at the
speed cap both ways, and the knee is still 9 deg bent when the foot comes down. A lower step
drifts less (30 mm: -0.064 m/s, 25: -0.041, 20: -0.014) and walks slower at full input
(0.319, 0.314, 0.305 against 0.35 m/s; these over 8 s after the first). The drift hides
behind vision and feedback: the particle filter and `walk_toward` correct it.

    python -m benchmarks.walklimits [--types 0,1,2,3,4] [--sets go_to_target,sprint]
                                    [--direction forward] [--input 1] [--seconds 10]
                                    [--params FILE ...]
                                    [--cap-scale K] [--torque-scale K]
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from benchmarks.args import robot_types
from benchmarks.machine import machine
from models import nao
from models.geometry import rotate
from models.messages import SEEN_PARTS, Action
from optimization.robot import new_robot

LOADED = 10.0  # N under a sole before it counts as bearing weight
LEG = tuple(f"lj{i}" for i in range(1, 7))
STAND = 0.5  # s standing before the walk starts
DIRECTIONS = {"forward": (1.0, 0.0), "backward": (-1.0, 0.0), "left": (0.0, 1.0)}  # walk inputs (x, y)


def walk_limits(robot_type: int, set_name: str = "sprint", seconds: float = 10.0,
                params: list[str] | None = None, cap_scale: float = 1.0, torque_scale: float = 1.0,
                direction: str = "forward", amount: float = 1.0) -> dict:
    """One straight walk in `direction` (DIRECTIONS) at `amount` of the full input; the
    figures of the module docstring, speeds and steps along that direction.
    cap_scale, torque_scale: the joints' speed cap and the motors' torque limit scaled,
    for diagnosis (`server.trainer.Trainer.scale_motors`; not the league's robot)."""
    dx, dy = DIRECTIONS[direction]  # unit, torso frame
    ix, iy = amount * dx, amount * dy
    tr, mo = new_robot(robot_type, walk_params=params or [])
    if cap_scale != 1.0 or torque_scale != 1.0:
        tr.scale_motors(cap_scale, torque_scale)
        mo.max_speed = mo.max_speed * cap_scale  # the joint controller's own clamp
        mo.pid.max_speed = mo.pid.max_speed * cap_scale
    world = tr.world
    d, p = world.data, world.players[0]
    names = nao.joint_names(robot_type)
    legs = np.array([i for i, n in enumerate(names) if n[1:] in LEG])
    cap = cap_scale * np.array([j.max_speed for j in nao.joints(robot_type)])[legs]
    act, dof = p.actuators[legs], p.joint_qvel[legs]
    for _ in range(round(STAND / 0.02)):
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0, set_name))})
    height = float(d.xpos[p.torso][2])
    x0, y0, h0 = world.player_pose(0)
    ux, uy = rotate(dx, dy, h0)  # world
    n = round(seconds / 0.02)
    at_cap = np.zeros(len(legs))
    at_limit = np.zeros(len(legs))
    lag = np.zeros(len(legs))
    peak = np.zeros(len(legs))
    steps = double = flight = 0
    factor = odometry = slip = 0.0
    foot_ids = p.parts[[SEEN_PARTS.index("lfoot"), SEEN_PARTS.index("rfoot")]]
    feet_before = d.xpos[foot_ids, :2].copy()
    alone_before = np.zeros(2, dtype=bool)
    swing = mo.walk.swing
    fell = False
    for k in range(n):
        percept = tr.percepts()[0]
        forces = np.asarray(percept.foot_forces, dtype=float)
        feet = (forces[:2] + (forces[2:4] if len(forces) == 4 else 0.0)) > LOADED  # type 4: sole + toe
        double += bool(feet.all())
        flight += not feet.any()
        v = mo.walk_step(percept, ix, iy, 0.0, set_name)
        factor += mo.walk.step_factor
        odometry += dx * mo.last.odometry[0] + dy * mo.last.odometry[1]
        if mo.walk.swing != swing:  # the feet swapped: a new step
            steps, swing = steps + 1, mo.walk.swing
        cmd = np.clip(v[legs], -cap, cap)
        at_cap += np.abs(cmd) >= cap - 1e-9
        tr.step({0: Action(v)})
        at_limit += np.abs(d.actuator_force[act]) >= nao.MAX_MOTOR_TORQUE - 1e-6
        lag += np.abs(d.qvel[dof] - cmd)
        peak = np.maximum(peak, np.abs(d.qvel[dof]))
        feet_now = d.xpos[foot_ids, :2].copy()
        alone = feet & ~feet[::-1]  # the one foot bearing the weight
        for i in np.flatnonzero(alone & alone_before):
            slip += float(np.hypot(*(feet_now[i] - feet_before[i])))
        feet_before, alone_before = feet_now, alone
        if world.torso_up()[0] < 0.5:
            fell, n = True, k + 1
            break
    dt = n * 0.02
    x1, y1, _ = world.player_pose(0)
    distance = (x1 - x0) * ux + (y1 - y0) * uy
    wp = mo.walk.sets[set_name]
    step_bound = {"forward": wp.max_step_size_x, "backward": wp.backward_factor * wp.max_step_size_x,
                  "left": wp.max_step_size_y}[direction]
    joints = {}
    for j in LEG:
        both = [i for i, li in enumerate(legs) if names[li][1:] == j]
        joints[j] = {"at_speed_cap": round(float(at_cap[both].mean()) / n, 3),
                     "at_torque_limit": round(float(at_limit[both].mean()) / n, 3),
                     "lag_rad_s": round(float(lag[both].mean()) / n, 3),
                     "peak_rad_s": round(float(peak[both].max()), 2)}
    return {"type": robot_type, "set": set_name, "direction": direction, "input": amount,
            "seconds": round(dt, 2),
            "fell": fell,
            "speed_m_s": round(distance / dt, 3),
            "planned_m_s": round(odometry / dt, 3), "steps_per_s": round(steps / dt, 2),
            "step_length_m": round(distance / steps, 4) if steps else None,
            "bound_m_s": round(step_bound / wp.phase_length, 3), "step_bound_m": round(step_bound, 4),
            "max_step_size_x_m": round(wp.max_step_size_x, 4), "phase_length_s": round(wp.phase_length, 4),
            "step_factor": round(factor / n, 3),
            "stance_slip_m_per_step": round(slip / steps, 4) if steps else None,
            "double_support": round(double / n, 3), "flight": round(flight / n, 3),
            "stand_height_m": round(height, 4), "cap_scale": cap_scale, "torque_scale": torque_scale,
            "joints": joints}


def table(rows: list[dict]) -> str:
    """Rows as text: one block per type and set, one line per leg joint."""
    out = []
    for r in rows:
        scaled = (f" [cap x{r['cap_scale']:g}, torque x{r['torque_scale']:g}]"
                  if (r["cap_scale"], r["torque_scale"]) != (1.0, 1.0) else "")
        amount = f" x{r['input']:g}" if r["input"] != 1.0 else ""
        out.append(f"type {r['type']} {r['set']} {r['direction']}{amount}{scaled}: {r['speed_m_s']:.3f} m/s "
                   f"(planned {r['planned_m_s']:.3f}, "
                   f"bound {r['bound_m_s']:.3f}), "
                   f"{r['steps_per_s']:.2f} steps/s x {r['step_length_m'] or 0:.3f} m, step factor "
                   f"{r['step_factor']:.2f}, stance slip {1000 * (r['stance_slip_m_per_step'] or 0):.1f} "
                   f"mm/step, double support "
                   f"{100 * r['double_support']:.0f}%, flight {100 * r['flight']:.0f}%, stand "
                   f"{r['stand_height_m']:.3f} m{', FELL' if r['fell'] else ''}")
        out.append("  joint  at speed cap  at torque limit  lag rad/s  peak rad/s")
        for j, s in r["joints"].items():
            out.append(f"  {j}   {100 * s['at_speed_cap']:10.0f}%  {100 * s['at_torque_limit']:14.0f}%  "
                       f"{s['lag_rad_s']:9.2f}  {s['peak_rad_s']:10.2f}")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.walklimits", description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0,1,2,3,4", help="robot types, comma-separated (default all)")
    ap.add_argument("--sets", default="go_to_target,sprint", help="walk sets, comma-separated")
    ap.add_argument("--direction", default="forward", choices=sorted(DIRECTIONS),
                    help="the walk input: full forward, backward or to the left (default forward)")
    ap.add_argument("--input", type=float, default=1.0, metavar="K",
                    help="the walk input's size, 0 < K <= 1 (default 1: full speed)")
    ap.add_argument("--seconds", type=float, default=10.0, help="s of walking (default 10)")
    ap.add_argument("--params", nargs="+", default=[], metavar="FILE",
                    help="walk parameter files loaded after the shipped ones")
    ap.add_argument("--cap-scale", type=float, default=1.0, metavar="K",
                    help="diagnosis: the joints' speed cap times K (not the league's robot)")
    ap.add_argument("--torque-scale", type=float, default=1.0, metavar="K",
                    help="diagnosis: the motors' torque limit times K (not the league's robot)")
    args = ap.parse_args(argv)
    if not 0 < args.input <= 1:
        ap.error(f"--input must be in (0, 1], got {args.input}")
    if args.cap_scale <= 0 or args.torque_scale <= 0:
        ap.error(f"--cap-scale and --torque-scale must be positive, got {args.cap_scale} "
                 f"and {args.torque_scale}")
    types = robot_types(ap, args.types)
    if args.seconds <= 0:
        ap.error(f"--seconds must be positive, got {args.seconds}")
    sets = [s.strip() for s in args.sets.split(",") if s.strip()]
    print(json.dumps({"machine": machine()}), flush=True)
    rows = []
    for t in types:
        for s in sets:
            rows.append(walk_limits(t, s, args.seconds, args.params, args.cap_scale, args.torque_scale,
                                    args.direction, args.input))
            print(json.dumps(rows[-1]), flush=True)
    print()
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Walk benchmark: speeds, falls on a go-to-target course, per robot type.

In physics, from standing, the robot's control reads only its percepts
(`skills.motion.Motion`); the benchmark reads ground truth to measure. One
JSON line per robot type:

* forward, backward, sideways speed (m/s) and turning rate (deg/s) over 10 s with
  the go-to-target walk set, and forward speed with the sprint set (UT's set for
  a target straight ahead, dissertation A.1.4); each the mean over the
  `--speed-runs` runs that did not fall, the first from the plain stand and the
  rest from perturbed joints (one 10 s run varies by about 0.02 m/s: type 4
  sideways gave 0.148 once and 0.223 over six starts), with each run's figure
  and the falls among them beside it;
* the go-to-target course (waypoints and stops modeled on Figure A.1: long
  straight walks, a curve, quick direction changes, stop and go, a spiral),
  walked by dead reckoning on the walk's own odometry: falls, time, how far
  the dead-reckoned pose drifted from the truth; over several runs, the share
  of runs with a fall and its 95% interval, and the falls by course leg (the
  waypoint walked to) and by what the walk did in the second before
  (`fall_motion`: in place, speeding up, steady or slowing, each also while
  turning, or in a getup);
* zigzag (`--zigzag-runs`, `zigzag`): full forward input with the turn input
  swinging left and right every second, 12 s a run; the share of runs with a
  fall. It stresses the course's commonest fall, walking and turning, alone,
  and it does not stand in for the course: the lateral shift at 5-10 mm
  instead of 0 took the zigzag's falls from 53 to 32-36 of 200 runs and the
  course's runs with a fall from 23 to 28-34 of 100 (heading_gain 0 and a turn
  slowdown went the same way), so a change is judged on the course;
* positioning (`--position-runs`, `positioning`): the team's own walk to a position
  (`optimization.position_walk.position_run`: a villa player on its percepts, WalkTo
  targets 0.5-4 m away at any bearing, a new one every 1.5-3 s, drifting), 30 s a run,
  with this benchmark's walk sets: the falls and the distance gained toward the targets.
  It is where most of villa's falls in open play come from (`benchmarks.falls`). With
  `--variant NAME` a villa variant's body walks them (its team features, such as TurnRamp's
  ramped turn input; the walk sets stay this benchmark's). Villa's fast sets
  (`--params skills/data/walk_fast_typeT.txt --position-runs 40`, December 7, 2026): runs
  with a fall 8 and 7 of 40 (types 0 and 1), 5.74 and 5.95 m gained a run; 7 of type 0's 8
  falls came turning in place at full input right after walking forward at full input.
  `--variant TurnRamp`, the turn input ramped over 0.5 s: runs with a fall 8 -> 0, 7 -> 5
  and 5 -> 0 (types 0, 1, 4), ground gained 6-9% less (5.74 -> 5.40, 5.95 -> 5.39, 5.36 ->
  5.01 m);
* getup success and mean time from front and back (`benchmarks.getup`).

Goals for the hand-tuned defaults (issue 3): forward >= 0.3 m/s, sideways
>= 0.15 m/s, turning >= 60 deg/s, no falls on the course. The forward goal is
the sprint set's (`sprint_forward_m_s`, the set for walking straight ahead);
`forward_m_s` is the go-to-target set's, which also turns, side-steps and stops.
Issue 47 asks for 0.70 m/s sprinting and 0.55 going to a target: type 0's sprint set
learned with its stand free (December 2026) walks `sprint_forward_m_s` 0.587
(0.392 before); its go-to-target set 0.333. villa:FastWalk's go-to-target sets, learned
with the stand free on the course plus this benchmark's zigzag, turns and steps
(`optimization/tasks/go_to_target_free.task`; `--params skills/data/walk_fast_typeT.txt`):
type 0 0.465 m/s, type 1 0.407, the course a quarter faster, no falls on it or the zigzag.
Issue 47 also asks 1.3x backward and sideways: backward_factor past about 0.5 walks no faster
backward on types 0, 2 and 3, and side steps of 68 mm with the low step (76 without) tip type 2
over. villa:Agile's sets (`skills/data/walk_agile.txt` after walk_lowstep.txt: a 30 mm step,
backward_factor 0.5, side steps 62-72 mm) walk backward 1.09-1.63x and sideways 1.00-1.33x as
fast, with no falls in 20 course and 20 zigzag runs a type (December 6, 2026). What held
backward walking was the swing's timing (`benchmarks.walklimits --direction backward`): begun
as the step begins (`backward_fraction_still` 0, in walk_defaults.txt since December 6, 2026;
villa:LateBackward walks as before) the sets walk backward 0.277/0.231/0.246/0.280/0.237 m/s
(1.7-2.6x), every other figure the same, no course run with a fall in 100 and one zigzag run
in 100 (type 3).

    python -m benchmarks.walk [--types 0,1,2,3,4] [--seconds 10] [--speed-runs N]
                              [--course-runs N] [--params FILE ...] [--skip-speeds]
                              [--zigzag-runs N] [--position-runs N] [--variant NAME]
                              [--getup-tries N]
"""

from __future__ import annotations

import argparse
import json
import math
import time
from collections import Counter, deque

import numpy as np

from benchmarks.machine import machine
from benchmarks.stats import rate_ci
from models.geometry import wrap
from models.messages import Action
from optimization.phases import ZIGZAG_HALF, ZIGZAG_TURN
from optimization.robot import new_robot as standing_robot
from server.trainer import Trainer
from skills.motion import Motion
from skills.navigate import Odometry, walk_toward
from skills.walk import default_param_files, load_walk_sets

# (x, y, stop seconds) relative to the start, facing +x; stops of 0 are pass-through.
COURSE = [
    (4.0, 0.0, 0.0), (4.0, 2.0, 1.0), (1.0, 2.5, 0.0), (0.0, 0.5, 0.0), (2.0, -1.0, 1.5),
    (3.0, 0.0, 0.0), (2.0, 1.0, 0.0), (1.0, 0.0, 0.0), (2.0, -1.0, 0.0), (3.0, 0.0, 1.0),
    (1.5, 0.0, 0.0), (0.0, 0.0, 1.0),
]
REACHED = 0.2  # m
FALL_LOOKBACK = 1.0  # s of walking before a fall that `fall_motion` looks at
FALL_TURNING = math.radians(5.0)  # turn step (per step) above which `fall_motion` says "turning"
FALL_MOTIONS = tuple(f"{m}{t}" for m in ("in place", "speeding up", "steady", "slowing")
                     for t in ("", ", turning")) + ("getup",)


ZIGZAG_SECONDS = 12.0

POSITION_SECONDS = 30.0  # s, one positioning run
PARAMS: list[str] = []  # walk parameter files loaded after the shipped ones (--params)


def new_robot(t: int, rng: np.random.Generator | None = None) -> tuple[Trainer, Motion]:
    """`optimization.robot.new_robot` with this run's `--params` walk files."""
    return standing_robot(t, rng, PARAMS)


def fallen(tr: Trainer) -> bool:
    return bool(tr.world.torso_up()[0] < 0.5)


def constant_walk(t: int, cmd: tuple[float, float, float], seconds: float,
                  set_name: str = "go_to_target", rng: np.random.Generator | None = None) -> dict:
    """Walk with fixed inputs and walk set; speed along x, y (m/s) and turning (deg/s) in
    the start frame. With `rng`, from perturbed start joints (`new_robot`)."""
    tr, mo = new_robot(t, rng)
    for _ in range(25):  # stand 0.5 s
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
    x0, y0, h0 = tr.world.player_pose(0)
    heading_total = 0.0
    prev = h0
    n = round(seconds / 0.02)
    for k in range(n):
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], *cmd, set_name))})
        h = tr.world.player_pose(0)[2]
        heading_total += wrap(h - prev)
        prev = h
        if fallen(tr):
            n = k + 1
            break
    x, y, _ = tr.world.player_pose(0)
    dt = n * 0.02
    return {"vx": (x - x0) / dt, "vy": (y - y0) / dt, "turn_deg_s": math.degrees(heading_total) / dt,
            "fell": fallen(tr), "seconds": round(dt, 2)}


def course(t: int, limit: float = 240.0, rng: np.random.Generator | None = None) -> dict:
    """Walk the course by dead reckoning; a fallen robot gets up with its getup skills
    (from its percepts) and goes on. Falls count every time the torso tips past 60 deg
    from vertical, whatever the robot was doing (walking, holding still after it sensed
    a fall, a getup that failed); getups started are counted apart. Each fall is told
    by the course leg it happened on (the index of the waypoint walked to) and by what
    the walk did in the second before it (`fall_motion`)."""
    tr, mo = new_robot(t, rng)
    odo = Odometry()
    falls, k, stop_left, cycles, was_down = 0, 0, None, 0, False
    recent: deque[tuple[float, float, bool]] = deque(maxlen=round(FALL_LOOKBACK / 0.02))
    fall_legs: list[int] = []
    fall_motions: list[str] = []
    while k < len(COURSE) and cycles * 0.02 < limit:
        tx, ty, stop = COURSE[k]
        pc = tr.percepts()[0]
        dx, dy = odo.relative(tx, ty)
        if stop_left is not None:
            cmd = (0.0, 0.0, 0.0)
            stop_left -= 0.02
            if stop_left <= 0:
                stop_left, k = None, k + 1
        elif math.hypot(dx, dy) < REACHED:
            if stop > 0:
                stop_left = stop
            else:
                k += 1
            cmd = (0.0, 0.0, 0.0) if stop > 0 else walk_toward(dx, dy, None, mo.walk.params)
        else:
            cmd = walk_toward(dx, dy, None, mo.walk.params)
        v = mo.recover(pc)  # a fallen robot gets up by its getup skills, then walks on
        recent.append((float(mo.walk.step[0]), float(mo.walk.step[2]), v is not None))
        if v is None:
            v = mo.walk_step(pc, *cmd)
            odo.update(*mo.last.odometry)
        tr.step({0: Action(v)})
        cycles += 1
        down = fallen(tr)
        if down and not was_down:
            falls += 1
            fall_legs.append(min(k, len(COURSE) - 1))
            fall_motions.append(fall_motion(list(recent)))
        was_down = down
    x, y, h = tr.world.player_pose(0)
    return {"waypoints": len(COURSE), "reached": k, "falls": falls, "getups_started": mo.getup.count,
            "seconds": round(cycles * 0.02, 1),
            "odometry_error_m": round(math.hypot(x - odo.x, y - odo.y), 3),
            "odometry_heading_error_deg": round(abs(math.degrees(wrap(h - odo.heading))), 1),
            "fall_legs": fall_legs, "fall_motions": fall_motions}


def zigzag(t: int, seconds: float = ZIGZAG_SECONDS, rng: np.random.Generator | None = None) -> dict:
    """Walk forward at the full input while the turn input swings between
    +ZIGZAG_TURN and -ZIGZAG_TURN every ZIGZAG_HALF s, after a 0.5 s stand (as at a
    quick change of direction; with `rng`, from perturbed joints). Returns whether
    and when (s) it fell, the distance walked (m) and the largest turn to either
    side within one half period (deg)."""
    tr, mo = new_robot(t, rng)
    for _ in range(25):
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 0.0, 0.0, 0.0))})
    x0, y0, h0 = tr.world.player_pose(0)
    half = round(ZIGZAG_HALF / 0.02)
    swings = [0.0, 0.0]  # largest left and right turn within a half period (rad)
    fell_at, turned, prev = None, 0.0, h0
    for k in range(round(seconds / 0.02)):
        sign = 1.0 if (k // half) % 2 == 0 else -1.0
        if k % half == 0:
            turned = 0.0
        tr.step({0: Action(mo.walk_step(tr.percepts()[0], 1.0, 0.0, sign * ZIGZAG_TURN))})
        h = tr.world.player_pose(0)[2]
        turned += wrap(h - prev)
        prev = h
        side = 0 if sign > 0 else 1
        swings[side] = max(swings[side], sign * turned)
        if fallen(tr):
            fell_at = round((k + 1) * 0.02, 2)
            break
    x, y, _ = tr.world.player_pose(0)
    return {"fell": fell_at is not None, "fell_at_s": fell_at,
            "distance_m": round(math.hypot(x - x0, y - y0), 3),
            "left_deg": round(math.degrees(swings[0]), 1), "right_deg": round(math.degrees(swings[1]), 1)}


def fall_motion(recent: list[tuple[float, float, bool]]) -> str:
    """What the robot did in the second before a fall, from (forward step (m), turn
    step (rad), in a getup or holding still after a fall) per cycle: "getup", or "in
    place" (forward steps under 10 mm), "slowing", "speeding up" (the forward step
    ended below, or started below, 80% of its largest) or "steady", with ", turning"
    when a turn step passed FALL_TURNING."""
    if any(g for _, _, g in recent):
        return "getup"
    xs = [abs(x) for x, _, _ in recent]
    top = max(xs, default=0.0)
    turning = ", turning" if any(abs(th) > FALL_TURNING for _, th, _ in recent) else ""
    if top < 0.01:
        return "in place" + turning
    if xs[-1] < 0.8 * top:
        return "slowing" + turning
    if xs[0] < 0.8 * top:
        return "speeding up" + turning
    return "steady" + turning


SPEEDS = {  # JSON key: (walk inputs, walk set, what is measured, sign)
    "forward_m_s": ((1.0, 0.0, 0.0), "go_to_target", "vx", 1.0),
    "sprint_forward_m_s": ((1.0, 0.0, 0.0), "sprint", "vx", 1.0),
    "backward_m_s": ((-1.0, 0.0, 0.0), "go_to_target", "vx", -1.0),
    "sideways_m_s": ((0.0, 1.0, 0.0), "go_to_target", "vy", 1.0),
    "turn_deg_s": ((0.0, 0.0, 1.0), "go_to_target", "turn_deg_s", 1.0),
}


def speeds(t: int, seconds: float, runs: int) -> dict:
    """Every `SPEEDS` figure as the mean over `runs` constant walks (the first from the
    plain stand, the rest from perturbed joints, seeded by type) that did not fall (over
    all of them if every one fell), each run's figure in `<key>_runs` (a fallen run's
    up to its fall), and the falls among them."""
    row: dict = {"speed_runs": runs}
    falls: dict[str, int] = {}
    for i, (key, (cmd, set_name, what, sign)) in enumerate(SPEEDS.items()):
        rng = np.random.default_rng([t, i])
        results = [constant_walk(t, cmd, seconds, set_name, None if k == 0 else rng) for k in range(runs)]
        values = [sign * r[what] for r in results]
        upright = [v for v, r in zip(values, results) if not r["fell"]] or values
        digits = 1 if what == "turn_deg_s" else 3
        row[key] = round(float(np.mean(upright)), digits)
        row[key + "_runs"] = [round(v, digits) for v in values]
        falls[key.removesuffix("_m_s").removesuffix("_deg_s")] = sum(r["fell"] for r in results)
    row["falls_in_speed_runs"] = falls
    return row


def positioning(t: int, runs: int, seconds: float = POSITION_SECONDS, variant: str | None = None) -> dict:
    """`runs` seeded runs of the team's positioning walk on this benchmark's walk sets, by
    villa's body or a variant's."""
    from agent.teamconfig import VILLA
    from agent.teamconfig import variant as team_variant
    from optimization.position_walk import position_run

    config = VILLA if variant is None else team_variant(variant)
    sets = load_walk_sets([*default_param_files(t), *PARAMS])
    rs = [position_run(t, np.random.default_rng([t, k]), 1000 * t + k, seconds, config=config, sets=sets)
          for k in range(runs)]
    fell = sum(r.falls > 0 for r in rs)
    return {"runs": runs, "seconds": seconds, "falls": sum(r.falls for r in rs), "runs_with_falls": fell,
            "runs_with_falls_ci95": rate_ci(fell, runs),
            "gained_m": round(float(np.mean([r.gained for r in rs])), 2)}


def getups(t: int, tries: int) -> dict | None:
    from benchmarks.getup import getup_stats
    return getup_stats(t, tries) if tries > 0 else None


def by_motion(runs: list[dict]) -> dict[str, int]:
    """Falls over `runs` by what the walk did in the second before (`fall_motion`)."""
    n = Counter(m for r in runs for m in r["fall_motions"])
    return {m: n[m] for m in FALL_MOTIONS}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--types", default="0,1,2,3,4")
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--speed-runs", type=int, default=4,
                    help="runs averaged for each speed; runs after the first start from perturbed joints")
    ap.add_argument("--getup-tries", type=int, default=20)
    ap.add_argument("--course-runs", type=int, default=20,
                    help="course runs per type; runs after the first start from perturbed joints")
    ap.add_argument("--zigzag-runs", type=int, default=20,
                    help="zigzag runs per type (0: none); runs after the first start from perturbed joints")
    ap.add_argument("--position-runs", type=int, default=20,
                    help=f"positioning runs ({POSITION_SECONDS:g} s each) per type (0: none)")
    ap.add_argument("--variant", default=None,
                    help="the villa variant whose body walks the positioning runs (e.g. TurnRamp)")
    ap.add_argument("--params", nargs="+", default=[], metavar="FILE",
                    help="walk parameter files loaded after the shipped ones (e.g. a CMA-ES best.txt)")
    ap.add_argument("--skip-speeds", action="store_true", help="only the course (and getups)")
    args = ap.parse_args()
    if (args.speed_runs < 1 or args.course_runs < 1 or args.seconds <= 0 or args.zigzag_runs < 0
            or args.position_runs < 0):
        ap.error("--speed-runs and --course-runs must be at least 1, --zigzag-runs and --position-runs "
                 "at least 0, --seconds above 0")
    if args.variant is not None:
        from agent.teamconfig import UnknownVariant
        from agent.teamconfig import variant as team_variant
        try:
            team_variant(args.variant)
        except UnknownVariant as e:
            ap.error(str(e))
    PARAMS[:] = args.params
    for t in (int(v) for v in args.types.split(",")):
        try:  # a bad file fails here, with file:line
            load_walk_sets([*default_param_files(t), *PARAMS])
        except (OSError, ValueError) as err:
            ap.error(str(err))
    info = machine()
    for t in (int(v) for v in args.types.split(",")):
        start = time.perf_counter()
        row: dict = {"benchmark": "walk", "type": t, "params": args.params, "variant": args.variant}
        if not args.skip_speeds:
            row.update(speeds(t, args.seconds, args.speed_runs))
        rng = np.random.default_rng(t)
        runs = [course(t, rng=None if k == 0 else rng) for k in range(args.course_runs)]
        fell = sum(r["falls"] > 0 for r in runs)
        row["course"] = runs[0] if len(runs) == 1 else {
            "runs": len(runs), "falls": [r["falls"] for r in runs],
            "runs_with_falls": fell, "runs_with_falls_ci95": rate_ci(fell, len(runs)),
            "getups_started": [r["getups_started"] for r in runs],
            "reached": [r["reached"] for r in runs], "seconds": [r["seconds"] for r in runs],
            "falls_by_leg": [sum(r["fall_legs"].count(i) for r in runs) for i in range(len(COURSE))],
            "falls_by_motion": by_motion(runs)}
        if args.zigzag_runs:
            zrng = np.random.default_rng([t, 1])
            zz = [zigzag(t, rng=None if k == 0 else zrng) for k in range(args.zigzag_runs)]
            zf = sum(r["fell"] for r in zz)
            row["zigzag"] = {"runs": len(zz), "seconds": ZIGZAG_SECONDS, "runs_with_falls": zf,
                             "runs_with_falls_ci95": rate_ci(zf, len(zz)),
                             "fell_at_s": [r["fell_at_s"] for r in zz if r["fell"]],
                             "distance_m": [r["distance_m"] for r in zz]}
        if args.position_runs:
            row["positioning"] = positioning(t, args.position_runs, variant=args.variant)
        row.update({"getup": getups(t, args.getup_tries),
                    "wall_seconds": round(time.perf_counter() - start, 1), "machine": info})
        print(json.dumps(row), flush=True)


if __name__ == "__main__":
    main()

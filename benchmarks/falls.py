"""Where a team's falls happen: per fall in a match, what the player was doing and who was near.

Plays `--games` matches of `--home` against `--away` (11 vs 11, seeds from `--seed`,
`--seconds` of play from the kickoff each) and, at every fall the referee counts,
notes from the fallen player's own state what it was doing `LOOKBACK` s before (the
body's skill: getup, dive, kick:<kicker state>, or the request it was walking for:
walkto, dribble, kick, stand) and from the ground truth how far the nearest other
robot and the ball were. Printed, per team: falls a player-minute by robot type, the
share by activity, the share with another robot within `NEAR` m (a collision or a
pile-up), and the share that came within LOOKBACK s of a getup (down again at once).

What it showed (villa against villa, `--games 3 --seconds 200`, December 2026): 54
falls in 600 s of play, 27 a team (a whole match's worth); 29 of them (54%) with
another robot within 0.6 m; by activity dribbling 17, walking to a position 14, on
the way to a kick 12, kicking 3, right after a getup 6 (5 of those in a crowd);
per player-minute types 0-2 fell 0.13-0.50 times, types 3 and 4 0.05-0.15.
Of the 54, 9 came in the first 3 s after the kickoff: type 2 robots rocking onto their
heels as they bent from the match's straight legs into the stand, and at the other
team's kickoff the on-ball player and the supporter beamed onto one spot. With the
blend into the stand (`skills.motion.Motion.enter_stand`) and kickoff spots 1 m apart,
the same run: 53 falls, none in the first 3 s (the rest is chaos: the games diverge).

What touched the fallen player within LOOKBACK s (villa against villa, `--games 2
--seconds 200`, seeds 0 and 2, December 6, 2026; contacts sampled once a cycle): of 41
falls, another robot on its legs 23 (56%), on its arms 7, on its trunk 2, the ball 3, and
nothing 18 (44%). Falls are trips over the other's legs more than pushes: in 19 falls of
30 villa-villa duels, feet and shanks touched before nearly every one, the ball before
none (a script outside the repository, 1 s before each fall). Balance steps
(`skills.walk`, villa:Balance) cut falls where robots walk into each other
(`benchmarks.bump`) and in 4 vs 4 games, not measurably in full ones.

Villa on the fast sets (villa against villa, `--games 1 --seconds 300`, seeds 0 and 1,
December 7, 2026): 88 falls in 600 s of play (44 a team-half). 50 with another robot within
0.6 m or touching it, 38 in the open (`open_walk`: no robot near or touching, not right after a
getup). Of those 38 the walk was turning in 14, forward 13, sideways 7, in place 2, backward
2; 26 walking to a position, 9 dribbling; by type 12, 10, 5, 4, 7 (types 0-4). A dribble's own
trips are few: villa:FastDribble, whose dribble falls 13 -> 1 times in 40 `benchmarks.dribble`
tries, tied villa over 40 games.

    python -m benchmarks.falls [--home villa] [--away villa] [--seconds 300] [--seed 0] [--games 1]
"""

from __future__ import annotations

import argparse
import json
from collections import Counter, deque

import numpy as np

from benchmarks.machine import machine
from cli.teams import factory
from models.rules import CYCLE, PlayMode
from server.match import Match, lineup_for
from server.world import World

LOOKBACK = 0.6  # s before the referee counts a fall whose activity is reported
NEAR = 0.6  # m: another robot's torso this near counts as a collision
# What touched a player (bits): the ball, or another robot touching its legs (hips to
# toes), its arms or its trunk (torso, neck, head).
TOUCH = {"ball": 1, "legs": 2, "arms": 4, "trunk": 8}
WALKS = ("forward", "backward", "sideways", "turning", "in place", "still", "")  # `walk_direction`
_ARMS = ("shoulder", "upperarm", "elbow", "lowerarm")
_TRUNK = ("torso", "neck", "head")


def geom_parts(w: World) -> np.ndarray:
    """Per geom, the TOUCH bit of the robot part it belongs to (0 for the rest)."""
    m = w.model
    out = np.zeros(m.ngeom, dtype=np.int64)
    for g in np.nonzero(w.geom_owner >= 0)[0]:
        part = m.body(int(m.geom_bodyid[g])).name.split("/", 1)[1]
        out[g] = TOUCH["trunk"] if part in _TRUNK else TOUCH["arms"] if part[1:] in _ARMS else TOUCH["legs"]
    return out


def touches(w: World, parts: np.ndarray) -> np.ndarray:
    """(n,) TOUCH bits per player from the contacts now: the ball on any of its geoms, and
    another robot on its legs, arms or trunk."""
    d = w.data
    n = d.ncon
    g1, g2 = d.contact.geom1[:n], d.contact.geom2[:n]
    o1, o2 = w.geom_owner[g1], w.geom_owner[g2]
    out = np.zeros(len(w.players), dtype=np.int64)
    robots = (o1 >= 0) & (o2 >= 0) & (o1 != o2)
    np.bitwise_or.at(out, o1[robots], parts[g1[robots]])
    np.bitwise_or.at(out, o2[robots], parts[g2[robots]])
    for mine, other in ((o1, g2), (o2, g1)):
        ball = (other == w.ball_geom) & (mine >= 0)
        out[mine[ball]] |= TOUCH["ball"]
    return out


def activity(agent) -> str:
    """What a player is doing, from its own state: a villa player's body skill, or the
    request it walks for; 'agent' for other agents."""
    body = getattr(agent, "body", None)
    if body is None:
        return "agent"
    if body.down:
        return "getup"
    if body.dive is not None:
        return "dive"
    if body.kicking:
        return f"kick:{body.kicker.state}"
    return type(agent.request).__name__.lower()


def walk_direction(agent) -> str:
    """Where a player's walk was stepping: the largest of its step's x, y and turn as a
    fraction of its walk set's maximum (forward, backward, sideways, turning), "in place"
    if all are under a fifth, "still" when not walking, "" for other agents."""
    body = getattr(agent, "body", None)
    if body is None:
        return ""
    walk = body.motion.walk
    if not walk.walking:
        return "still"
    p = walk.params
    x, y, th = walk.step.tolist()
    f = (x / p.max_step_size_x, abs(y) / p.max_step_size_y, abs(th) / p.max_step_size_angle)
    k = int(np.argmax(np.abs(f)))
    if abs(f[k]) < 0.2:
        return "in place"
    return ("forward" if f[0] > 0 else "backward", "sideways", "turning")[k]


def fall_rows(m: Match, seconds: float) -> list[dict]:
    """Play `seconds` from the kickoff; one row per fall: game time (s), player index, side,
    robot type, activity and walk direction LOOKBACK s before, whether it was getting up within LOOKBACK s,
    the nearest other robot's and the ball's ground distance (m), and what touched it
    within LOOKBACK s (`TOUCH` names; sampled once a cycle)."""
    w, ref = m.world, m.referee
    parts = geom_parts(w)
    while ref.mode == PlayMode.BEFORE_KICK_OFF:
        m.step()
    recent = [deque(maxlen=round(LOOKBACK / CYCLE)) for _ in m.agents]
    touched = [deque(maxlen=round(LOOKBACK / CYCLE)) for _ in m.agents]
    prev = ref.fallen.copy()
    rows = []
    for _ in range(round(seconds / CYCLE)):
        m.step()
        for r, agent in zip(recent, m.agents):
            r.append((activity(agent), walk_direction(agent)))
        for t, bits in zip(touched, touches(w, parts).tolist()):
            t.append(bits)
        new = np.nonzero(ref.fallen & ~prev)[0]
        prev = ref.fallen.copy()
        if not len(new):
            continue
        xy = w.torso_positions()[:, :2]
        ball = w.ball_position()[:2]
        for i in new.tolist():
            d = np.hypot(*(xy - xy[i]).T)
            d[i] = np.inf
            p = w.players[i]
            rows.append({"time": round(float(ref.game_time), 2), "player": i, "side": str(p.side.value),
                         "type": p.robot_type, "activity": recent[i][0][0], "walk": recent[i][0][1],
                         "after_getup": any(a == "getup" for a, _ in recent[i]),
                         "nearest_robot_m": round(float(d.min()), 2),
                         "ball_m": round(float(np.hypot(*(ball - xy[i]))), 2),
                         "touched": _names(np.bitwise_or.reduce(np.array(touched[i], dtype=np.int64)))})
    return rows


def _names(bits: int) -> list[str]:
    return [k for k, b in TOUCH.items() if bits & b]


def summary(rows: list[dict], players: dict[int, int], minutes: float) -> dict:
    """Aggregate of one team's fall rows; `players` counts its players of each robot type
    and `minutes` the minutes of play."""
    n = len(rows)

    def share(k: int) -> float:
        return round(k / n, 2) if n else 0.0

    by_type = Counter(r["type"] for r in rows)
    return {
        "falls": n,
        "per_player_minute": {t: round(by_type[t] / (c * minutes), 3) for t, c in sorted(players.items())},
        "activity": {a: share(k) for a, k in Counter(r["activity"] for r in rows).most_common()},
        "near_robot": share(sum(r["nearest_robot_m"] < NEAR for r in rows)),
        "after_getup": share(sum(r["after_getup"] for r in rows)),
        "ball_within_1m": share(sum(r["ball_m"] < 1.0 for r in rows)),
        # Falls in the open (no robot within NEAR, none touching, not after a getup) by the
        # walk's direction: the walk's own falls.
        "open_walk": {k: share(v) for k, v in Counter(
            r["walk"] for r in rows if r["nearest_robot_m"] >= NEAR and not r["after_getup"]
            and not set(r["touched"]) - {"ball"}).most_common()},
        "touched": {**{k: share(sum(k in r["touched"] for r in rows)) for k in TOUCH},
                    "nothing": share(sum(not r["touched"] for r in rows))},
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--home", default="villa", help="left team (cli.teams name)")
    ap.add_argument("--away", default="villa", help="right team (cli.teams name)")
    ap.add_argument("--seconds", type=float, default=300.0, help="seconds of play from the kickoff a game")
    ap.add_argument("--seed", type=int, default=0, help="first game's seed")
    ap.add_argument("--games", type=int, default=1)
    args = ap.parse_args(argv)
    if not 0 < args.seconds <= 300 or args.games < 1:
        ap.error(f"--seconds must be in (0, 300] and --games >= 1 (got {args.seconds}, {args.games})")
    try:
        teams = {"L": factory(args.home), "R": factory(args.away)}
        lineup = lineup_for(teams["L"], teams["R"], 11, 11, (args.home, args.away))
    except ValueError as e:  # an unknown team (UnknownTeam) or robot types against the rule
        ap.error(str(e))
    rows = []
    for g in range(args.games):
        m = Match(teams["L"], teams["R"], lineup, half_time=300, seed=args.seed + g,
                  team_names=(args.home, args.away))
        game = fall_rows(m, args.seconds)
        print(json.dumps({"game": g, "seed": args.seed + g, "falls": len(game), "rows": game}))
        rows += game
    minutes = args.games * args.seconds / 60.0
    out = {}
    for side, name, types in (("L", args.home, lineup.left), ("R", args.away, lineup.right)):
        out[side] = {"team": name, **summary([r for r in rows if r["side"] == side], Counter(types), minutes)}
    print(json.dumps({"benchmark": "falls", "games": args.games, "seconds": args.seconds, "seed": args.seed,
                      "teams": out, "machine": machine()}))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

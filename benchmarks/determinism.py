"""Same seed, same match: a hash of a short villa match, to compare before and after a change.

Runs 3 vs 3 villa against posture and 3 vs 3 villa against villa for `--seconds`
simulated seconds each (seed `--seed`) and prints, per match, a hash of every
cycle's motor commands, of the final `qpos` and of the referee's events. A change
meant to keep behavior must leave every line identical.

    python -m benchmarks.determinism [--seconds 20] [--seed 0]
"""

from __future__ import annotations

import argparse
import hashlib
import json

from cli.teams import factory
from server.match import Match, lineup_for


def run(home: str, away: str, seconds: float, seed: int, n: int = 3) -> dict:
    left, right = factory(home), factory(away)
    m = Match(left, right, lineup_for(left, right, n, n), half_time=30, seed=seed)
    ctrl_hash = hashlib.sha256()
    step = m.world.step

    def hashed_step(ctrl):
        ctrl_hash.update(ctrl.tobytes())
        return step(ctrl)

    m.world.step = hashed_step
    for _ in range(round(seconds / 0.02)):
        m.step()
    events = json.dumps([e.to_dict() for e in m.referee.events], sort_keys=True)
    return {
        "match": f"{home}-{away} {n}v{n}", "seed": seed, "cycles": m.cycle,
        "ctrl": ctrl_hash.hexdigest()[:16],
        "qpos": hashlib.sha256(m.world.data.qpos.tobytes()).hexdigest()[:16],
        "events": hashlib.sha256(events.encode()).hexdigest()[:16],
        "n_events": len(m.referee.events), "score": dict(m.referee.score),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    for home, away in (("villa", "posture"), ("villa", "villa")):
        print(json.dumps(run(home, away, args.seconds, args.seed)), flush=True)


if __name__ == "__main__":
    main()

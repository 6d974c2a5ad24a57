"""The formations of "Positioning to Win" section 6's variants, made from the default.

* defensive: only the on-ball role and the supporter (directly behind the ball)
  go forward; every other role stays at least DEFENSIVE_GAP behind the ball and is
  pulled a further DEFENSIVE_PULL of the way toward our goal.
* offensive: every role but the goalie's in a close formation behind the ball
  (OFFENSIVE_OFFSETS from the ball, symmetric in y).
* boxes: fixed home positions, one per role, whatever the ball's position (one
  sample; the roles are still assigned dynamically); the on-ball role follows the ball.

    python -m formations.variants        # rewrites formations/data/{defensive,offensive,boxes}.formation
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from formations import field as fld
from formations.delaunay import Formation

DEFENSIVE_GAP = 2.0  # m behind the ball at least
DEFENSIVE_PULL = 0.4  # share of the way from there to 2 m in front of our goal line
OFFENSIVE_OFFSETS = {  # m from the ball
    "supporter": (-1.5, 0.0), "forwardLeft": (-1.0, 2.0), "forwardRight": (-1.0, -2.0),
    "wingLeft": (-2.5, 3.5), "wingRight": (-2.5, -3.5), "midLeft": (-3.0, 1.5), "midRight": (-3.0, -1.5),
    "backLeft": (-4.5, 2.5), "backRight": (-4.5, -2.5),
}
BOXES = {  # home position of each role (m), the center of its box
    "goalie": (-14.4, 0.0), "onBall": (0.0, 0.0), "supporter": (0.0, 0.0),
    "forwardLeft": (8.0, 4.5), "forwardRight": (8.0, -4.5), "wingLeft": (3.0, 7.0), "wingRight": (3.0, -7.0),
    "midLeft": (-3.0, 3.5), "midRight": (-3.0, -3.5), "backLeft": (-9.0, 4.0), "backRight": (-9.0, -4.0),
    "goalieReplacement": (-13.8, 0.0),
}
FORWARD = ("onBall", "supporter")
KEEP = ("goalie", "goalieReplacement", "onBall")


def _clip(f: Formation, p: np.ndarray) -> np.ndarray:
    m = f.margin
    return np.stack([np.clip(p[..., 0], -fld.HALF_LENGTH + m, fld.HALF_LENGTH - m),
                     np.clip(p[..., 1], -fld.HALF_WIDTH + m, fld.HALF_WIDTH - m)], axis=-1)


def defensive(base: Formation) -> Formation:
    pos = base.positions.copy()
    line = -fld.HALF_LENGTH + 2.0
    for j, role in enumerate(base.roles):
        if role in KEEP or role in FORWARD:
            continue
        x = np.minimum(pos[:, j, 0], base.balls[:, 0] - DEFENSIVE_GAP)
        x = x - DEFENSIVE_PULL * np.maximum(x - line, 0.0)
        pos[:, j, 0] = x
    return Formation(base.roles, base.balls, _clip(base, pos), base.follow, base.margin, "defensive")


def offensive(base: Formation) -> Formation:
    pos = base.positions.copy()
    for j, role in enumerate(base.roles):
        if role in OFFENSIVE_OFFSETS:
            pos[:, j] = base.balls + np.array(OFFENSIVE_OFFSETS[role])
    return Formation(base.roles, base.balls, _clip(base, pos), base.follow, base.margin, "offensive")


def boxes(base: Formation) -> Formation:
    pos = np.array([[BOXES[r] for r in base.roles]])
    return Formation(base.roles, np.zeros((1, 2)), pos, base.follow, base.margin, "boxes")


MAKERS = {"defensive": defensive, "offensive": offensive, "boxes": boxes}

HEADER = {
    "defensive": "# Defensive (Positioning to Win section 6): only onBall and the supporter (directly\n"
                 "# behind the ball) go forward; the other roles stay behind the ball, pulled toward\n"
                 "# our goal.\n",
    "offensive": "# Offensive (Positioning to Win section 6): every role but the goalie's in a close\n"
                 "# symmetric formation behind the ball.\n",
    "boxes": "# Boxes (Positioning to Win section 6): fixed home positions whatever the ball's position\n"
             "# (one sample); roles are still assigned dynamically, onBall follows the ball.\n",
}


def main() -> None:
    base = Formation.default()
    out = Path(__file__).resolve().parent / "data"
    for name, make in MAKERS.items():
        made = "# Made from default.formation by `python -m formations.variants`.\n"
        text = HEADER[name] + made + make(base).dumps()
        (out / f"{name}.formation").write_text(text)
        Formation.load(out / f"{name}.formation")
        print(out / f"{name}.formation")


if __name__ == "__main__":
    main()

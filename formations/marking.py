"""Marking with prioritized role assignment (dissertation section 7.3).

Three steps: decide whom to mark, select the formation roles that marking
positions replace (Hungarian, minimum sum of distances), and assign agents to
all targets with prioritized SCRAM (marks P = 100, D = 3 m; the supporter
P = 10000, D = 1.5 m). Two hysteresis rules stop thrashing: a marked opponent
must move 0.25 m beyond a markable position before it is dropped, and a role
selection of the same cardinality is only changed for one whose sum of
distances is at least 1 m smaller.

Field frame, meters; our goal is at x = -15, opponents attack toward -x.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import linear_sum_assignment

from formations import _kernels
from formations import field as fld
from formations import priority as prio

_OWN_GOAL = tuple(fld.OWN_GOAL.tolist())  # (x, y) m
_NONE = np.zeros(0, dtype=bool)  # no opponent marked before


@dataclass
class MarkingParams:
    """Marking thresholds (meters) and priorities."""

    shot_range: float = 9.0  # opponent within this of our goal center can shoot
    min_ball_distance: float = 2.0  # opponents nearer the ball are left to onBall
    max_behind_ball: float = 3.0  # farther than this behind the ball (+x) is ignored
    mark_distance: float = 1.5  # marking position: this far toward our goal
    hysteresis: float = 0.25  # marked opponents keep being marked this far out
    reselect_gain: float = 1.0  # a new role selection must save this much (m)
    mark_priority: float = 100.0
    mark_priority_distance: float = 3.0
    supporter_priority: float = 10000.0
    supporter_priority_distance: float = 1.5


def opponents_to_mark(
    opponents: np.ndarray,
    ball: np.ndarray,
    marked: np.ndarray | None = None,
    params: MarkingParams | None = None,
) -> np.ndarray:
    """Mask over (k, 2) `opponents` of those to mark (section 7.3.1).

    Rules: close enough to shoot, not the opponent closest to the ball, not
    too close to the ball, not too far behind the ball. `marked` (k,) flags
    opponents marked last cycle; their thresholds are relaxed by `hysteresis`.
    """
    p = params or MarkingParams()
    opponents = np.asarray(opponents, dtype=float).reshape(-1, 2)
    k = len(opponents)
    if k == 0:
        return np.zeros(0, dtype=bool)
    bx, by = np.asarray(ball, dtype=float).reshape(2).tolist()
    flags = _NONE if marked is None else np.asarray(marked, bool)
    if flags.shape != (k,) and marked is not None:
        flags = np.ascontiguousarray(np.broadcast_to(flags, (k,)))
    return _kernels.marking_mask(np.ascontiguousarray(opponents), bx, by, *_OWN_GOAL, flags, p.hysteresis,
                                 p.shot_range, p.min_ball_distance, p.max_behind_ball)


def _norms(d: np.ndarray) -> np.ndarray:
    """Lengths of (k, 2) vectors (as np.linalg.norm(d, axis=1) computes them)."""
    x, y = d[:, 0], d[:, 1]
    return np.sqrt(x * x + y * y)


def marking_positions(opponents: np.ndarray, distance: float = 1.5) -> np.ndarray:
    """(k, 2) points `distance` meters from each opponent toward our goal center."""
    opponents = np.asarray(opponents, dtype=float).reshape(-1, 2)
    d = fld.OWN_GOAL - opponents
    norm = _norms(d)[:, None]
    step = np.where(norm > distance, distance / np.maximum(norm, 1e-12), 1.0)
    return fld.clip_to_field(opponents + d * step)


@dataclass
class RoleSelection:
    """Which formation role each marked opponent replaces: {opponent: role index}."""

    pairs: dict[int, int] = field(default_factory=dict)

    def total(self, formation: np.ndarray, marks: dict[int, np.ndarray]) -> float:
        return float(sum(np.linalg.norm(formation[r] - marks[o]) for o, r in self.pairs.items()))


def select_roles(
    formation: np.ndarray,
    replaceable: np.ndarray,
    marks: dict[int, np.ndarray],
    previous: RoleSelection | None = None,
    gain: float = 1.0,
) -> RoleSelection:
    """Formation roles replaced by marking positions (section 7.3.2).

    `formation` (r, 2) role positions; `replaceable` (r,) mask of roles that
    may be given up; `marks` maps opponent id -> marking position (2,). The
    minimum-sum-of-distances matching (Hungarian) pairs marks with roles;
    extra marks stay unassigned. The `previous` selection is kept when it is
    still valid, of the same cardinality, and the new one does not save at
    least `gain` meters.
    """
    formation = np.asarray(formation, dtype=float)
    cand = np.flatnonzero(np.asarray(replaceable, dtype=bool))
    ids = sorted(marks)
    if not ids or cand.size == 0:
        return RoleSelection()
    mpos = np.array([marks[o] for o in ids], dtype=float).reshape(-1, 2)
    cost = np.linalg.norm(mpos[:, None, :] - formation[None, cand, :], axis=-1)
    r, c = linear_sum_assignment(cost)
    new = RoleSelection({ids[i]: int(cand[j]) for i, j in zip(r, c)})
    if previous is not None and previous.pairs:
        valid = (
            len(previous.pairs) == len(new.pairs)
            and all(o in marks for o in previous.pairs)
            and all(r_ in set(cand.tolist()) for r_ in previous.pairs.values())
            and len(set(previous.pairs.values())) == len(previous.pairs)
        )
        if valid and new.total(formation, marks) > previous.total(formation, marks) - gain:
            return RoleSelection(dict(previous.pairs))
    return new


@dataclass
class MarkingPlan:
    """Targets (r, 2) with per-target priority P and distance D, and who marks whom."""

    targets: np.ndarray
    priority: np.ndarray
    priority_distance: np.ndarray
    selection: RoleSelection
    marked: np.ndarray  # (k,) opponents marked this cycle

    def assign(self, agents: np.ndarray, method: str = "mmdr") -> np.ndarray:
        """Prioritized SCRAM of (r, 2) `agents` to the targets (section 7.3.3)."""
        return prio.assign(agents, self.targets, self.priority, self.priority_distance, method)


def plan(
    formation: np.ndarray,
    roles: tuple[str, ...],
    opponents: np.ndarray,
    ball: np.ndarray,
    *,
    marked: np.ndarray | None = None,
    previous: RoleSelection | None = None,
    params: MarkingParams | None = None,
    keep: tuple[str, ...] = ("goalie", "onBall", "supporter", "goalieReplacement"),
    supporter: str = "supporter",
) -> MarkingPlan:
    """Full marking step: whom to mark, which roles they replace, priorities.

    `formation` (r, 2) positions of `roles` for the current ball; roles in
    `keep` are never replaced. Returns the targets for prioritized assignment.
    """
    p = params or MarkingParams()
    formation = np.asarray(formation, dtype=float)
    mask = opponents_to_mark(opponents, ball, marked, p)
    selection = RoleSelection()
    marks: dict[int, np.ndarray] = {}
    if mask.any():
        opponents = np.asarray(opponents, dtype=float).reshape(-1, 2)
        marked_ids = np.flatnonzero(mask)
        spots = marking_positions(opponents[marked_ids], p.mark_distance)  # row by row: a subset is exact
        marks = {int(i): spot for i, spot in zip(marked_ids.tolist(), spots)}
        replaceable = np.array([r not in keep for r in roles], dtype=bool)
        selection = select_roles(formation, replaceable, marks, previous, p.reselect_gain)
    targets = formation.copy()
    pri = np.zeros(len(roles))
    dist = np.zeros(len(roles))
    for o, r in selection.pairs.items():
        targets[r] = marks[o]
        pri[r] = p.mark_priority
        dist[r] = p.mark_priority_distance
    if supporter in roles:
        s = roles.index(supporter)
        pri[s] = p.supporter_priority
        dist[s] = p.supporter_priority_distance
    return MarkingPlan(targets, pri, dist, selection, mask)

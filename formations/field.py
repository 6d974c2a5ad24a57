"""Field constants used by the formation code (SI units, field frame).

Field frame: meters, origin at the center spot, +x toward the opponent goal,
+y to the left. Kept local so that `formations` depends on numpy/scipy only.
"""

from __future__ import annotations

import numpy as np

FIELD_LENGTH = 30.0  # m, along x
FIELD_WIDTH = 20.0  # m, along y
HALF_LENGTH = FIELD_LENGTH / 2.0
HALF_WIDTH = FIELD_WIDTH / 2.0
GOAL_WIDTH = 2.1  # m
PENALTY_DEPTH = 1.8  # m

OWN_GOAL = np.array([-HALF_LENGTH, 0.0])  # center of our goal line, m
OPPONENT_GOAL = np.array([HALF_LENGTH, 0.0])


def field_box(margin: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper (x, y) corners (m) of the field rectangle shrunk by `margin`."""
    return (np.array([-HALF_LENGTH + margin, -HALF_WIDTH + margin]),
            np.array([HALF_LENGTH - margin, HALF_WIDTH - margin]))


def clip_to_field(points: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Clips (..., 2) points to the field rectangle shrunk by `margin` meters."""
    lo, hi = field_box(margin)
    return np.minimum(np.maximum(np.asarray(points, dtype=float), lo), hi)  # = np.clip, faster


def inside_field(points: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """True where (..., 2) points lie in the field shrunk by `margin` meters."""
    points = np.asarray(points, dtype=float)
    return (np.abs(points[..., 0]) <= HALF_LENGTH - margin + 1e-12) & (
        np.abs(points[..., 1]) <= HALF_WIDTH - margin + 1e-12
    )

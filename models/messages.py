"""The messages between the server and an agent, one pair every 20 ms cycle.

Frames: *torso* is the robot's torso body frame (x forward, y left, z up);
*camera* is the head camera frame (x along the line of sight, y left, z up);
polar coordinates are (distance m, horizontal angle rad, vertical angle rad)
in the camera frame, angles positive to the left and up, as SimSpark sends
them (but in SI units: SimSpark sends degrees).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

SEEN_PARTS = ("head", "llowerarm", "rlowerarm", "lfoot", "rfoot")  # other robots' parts in view


# Vision and Percept are read-only by convention, not frozen: the server builds 22 of
# each every (vision) cycle, and a frozen dataclass takes four times as long to build
# (2.0 against 0.5 us a Percept).
@dataclass(slots=True)
class Vision:
    """One vision percept (every third cycle): everything inside the 120 deg cone.

    All positions are polar (distance, horizontal, vertical) in the camera frame.
    Other robots' parts come as parallel arrays: part k belongs to the robot of
    `player_unum[k]` on our team if `player_ours[k]`, and is
    `SEEN_PARTS[player_part[k]]`.
    """

    landmark_names: tuple[str, ...]  # flags and posts in view (F1L, G2R, ...)
    landmarks: np.ndarray  # (k, 3) polar, one row per name
    ball: np.ndarray | None  # (3,) polar, or None when out of view
    lines: np.ndarray  # (n, 2, 3) polar end points of the visible parts of field lines
    player_ours: np.ndarray  # (p,) bool
    player_unum: np.ndarray  # (p,) uniform numbers
    player_part: np.ndarray  # (p,) index into SEEN_PARTS
    players: np.ndarray  # (p, 3) polar

    def landmark(self, name: str) -> np.ndarray | None:
        """Polar position of landmark `name`, or None when it is not in view."""
        try:
            return self.landmarks[self.landmark_names.index(name)]
        except ValueError:
            return None


@dataclass(slots=True)
class HeardMessage:
    """A message heard this cycle (read-only by convention: 60 of them a cycle)."""

    time: float  # s, server time when it was said
    team: str  # "self" (own message), "ours" or "theirs"
    direction: float  # rad, horizontal direction of the speaker in the torso frame (0 for self)
    text: str


@dataclass(slots=True)
class Percept:
    """What one agent is told at the start of a cycle.

    joints, in the league's order for the robot type (`models.nao.joint_names`),
    are angles in rad; gyro is the torso's angular velocity (rad/s, torso frame);
    accel the specific force (m/s^2, torso frame: about +9.81 on z when upright
    and still); foot_forces the normal force (N) under each sole of
    `models.robot.sole_names`.
    """

    time: float  # s, server time
    game_time: float  # s, game clock
    play_mode: str  # a `models.rules.PlayMode` value
    score_left: int
    score_right: int
    side: str  # "L" (plays toward +x of the field frame) or "R"
    unum: int
    robot_type: int
    joints: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    foot_forces: np.ndarray
    vision: Vision | None = None
    heard: tuple[HeardMessage, ...] = ()
    warnings: tuple[str, ...] = ()  # e.g. why the last say was dropped


@dataclass
class Action:
    """What an agent answers.

    joint_velocities: target angular velocity per joint (rad/s, league order),
    clamped by the server at each joint's maximum speed. say: at most 20
    characters of `models.rules.SAY_ALPHABET`. beam: (x, y, heading) in the
    team's own field frame (own goal at -x; m, m, rad), honored only before
    kickoff and after a goal.
    """

    joint_velocities: np.ndarray
    say: str | None = None
    beam: tuple[float, float, float] | None = None
    annotations: dict = field(default_factory=dict)  # for the match log, e.g. "target": (x, y)

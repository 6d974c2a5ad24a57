"""A whole match scene: the field, both goals, the ball and any line-up.

Robots are named by team side and uniform number: bodies of the left team's
number 3 are `L3/torso`, `L3/lfoot`, ... Collision filtering keeps only the
contacts that matter (robot-floor, robot-ball, robot-robot, robot-goal,
ball-floor, ball-goal): every robot gets a bit of its own, so its parts never
touch each other but touch every other robot.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from models import field, nao, robot
from models.rules import PHYSICS_DT, TEAM_SIZE, Side

FLOOR_BIT = 1 << 0
BALL_BIT = 1 << 1
GOAL_BIT = 1 << 2
FIRST_ROBOT_BIT = 3
ALL_ROBOTS = sum(1 << (FIRST_ROBOT_BIT + i) for i in range(2 * TEAM_SIZE))


def default_types(n: int) -> tuple[int, ...]:
    """The robot types of a team of n that does not choose its own: 0-4 in turn."""
    return tuple(i % 5 for i in range(n))


@dataclass(frozen=True)
class Lineup:
    """Robot types of each team, index i is uniform number i + 1.

    A match needs 1 to 11 a side; training worlds (skills, optimization) may
    leave one side empty.
    """

    left: tuple[int, ...]
    right: tuple[int, ...]

    def __post_init__(self) -> None:
        for team, types in (("left", self.left), ("right", self.right)):
            if not 0 <= len(types) <= TEAM_SIZE:
                raise ValueError(f"the {team} team has {len(types)} players; it needs 1 to 11")
            for t in types:
                nao.robot_type(t)
        if not self.left and not self.right:
            raise ValueError("a line-up needs at least one player")

    @classmethod
    def default(cls, n_left: int = TEAM_SIZE, n_right: int = TEAM_SIZE) -> Lineup:
        """A legal heterogeneous line-up: types 0-4 in turn, goalie type 0."""
        return cls(default_types(n_left), default_types(n_right))

    def players(self) -> list[tuple[Side, int, int]]:
        """(side, uniform number, type) of every player, left team first."""
        return [(Side.LEFT, i + 1, t) for i, t in enumerate(self.left)] + [
            (Side.RIGHT, i + 1, t) for i, t in enumerate(self.right)]


def prefix(side: str, unum: int) -> str:
    """Name prefix of a player's bodies, joints and sensors."""
    return f"{side}{unum}/"


def start_pose(side: str, unum: int, robot_type: int) -> tuple[float, float, float, float]:
    """(x, y, z, yaw) off the field by the own half's touch line, before anyone beams."""
    s = -1.0 if side == Side.LEFT else 1.0
    x = s * (1.0 + 1.2 * (unum - 1))
    return (x, -field.HALF_WIDTH - 0.6, nao.standing_height(robot_type),
            0.0 if side == Side.LEFT else 3.141592653589793)


def static_bodies(world: ET.Element) -> None:
    """Move every colliding geom of an MJCF worldbody into a static body of its own.

    MuJoCo collides bodies pairwise. Kept in the world body, the floor, the goal
    frames and the (visual) lines make one many-geom body that meets every robot
    link through a bounding-volume tree walk at each step, about 13 % of a step
    with 22 robots. A body per geom makes floor-link a plain geom pair and lets the
    broadphase drop far goals. The contacts, and so the physics, stay the same.
    """
    for k, el in enumerate(list(world)):
        if el.tag == "geom" and el.get("contype", "1") != "0":
            body = ET.Element("body", name="static/" + el.get("name", f"geom{k}"))
            body.append(el)
            world[k] = body


def scene_mjcf(lineup: Lineup, timestep: float = PHYSICS_DT) -> str:
    """MJCF of the field, ball and every robot of `lineup`."""
    root = ET.Element("mujoco", model="soccer")
    robot.mjcf_options(root, timestep)
    asset = ET.SubElement(root, "asset")
    ET.SubElement(asset, "texture", name="sky", type="skybox", builtin="gradient",
                  rgb1="0.5 0.7 0.9", rgb2="0.1 0.1 0.2", width="64", height="64")
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", pos="0 0 20", dir="0 0 -1", directional="true",
                  castshadow="false")
    field.field_xml(world, floor_bits=(FLOOR_BIT, 0), goal_bits=(GOAL_BIT, 0))
    static_bodies(world)
    field.ball_xml(world, contype=BALL_BIT, conaffinity=FLOOR_BIT | GOAL_BIT)
    actuators = ET.SubElement(root, "actuator")
    sensors = ET.SubElement(root, "sensor")
    for i, (side, unum, t) in enumerate(lineup.players()):
        bit = 1 << (FIRST_ROBOT_BIT + i)
        x, y, z, yaw = start_pose(side, unum, t)
        parts = robot.robot_xml(t, prefix(side, unum), pos=(x, y, z), yaw=yaw, contype=bit,
                                conaffinity=FLOOR_BIT | BALL_BIT | GOAL_BIT | (ALL_ROBOTS & ~bit))
        world.append(parts.body)
        actuators.extend(parts.actuators)
        sensors.extend(parts.sensors)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")

"""MJCF for one Nao-like robot, generated from the table in `models.nao`.

Body frames sit at each link's center, axes as the project's robot frame
(x forward, y left, z up) when every joint is at zero. Names carry a prefix
(`"L3/"` for the left team's number 3) so that many robots share one scene.

Each robot carries:
  * one velocity actuator per joint, named by its effector (`lle4`), whose
    control is the target angular velocity in rad/s, clamped at the joint's
    maximum speed and realized with a torque limit, like SimSpark's motors;
  * sensors: `jointpos` per joint, `gyro` and `accelerometer` at the torso's
    `imu` site (torso frame), a `touch` sensor under each foot (and toe), and a
    `camera` site at the head center (x forward along the line of sight).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from models import nao

# Motor model. SimSpark's ODE motors track the commanded velocity almost exactly
# within their force limit; a stiff velocity servo with an implicit integrator
# does the same in MuJoCo.
# The servo must not chatter at its force limit: MuJoCo's implicit step treats a servo at
# the limit as a constant force, and when kv * dt exceeds twice the joint's inertia, one
# step at the limit overshoots the target speed by more than the servo's force band, so
# the next step is at the opposite limit, and the pair repeats. The armature (the rotor's
# inertia seen through the gears) alone is over kv * dt / 2 = 0.025 kg m^2 for the 5 ms
# step, whatever the link. With kv 20 and armature 0.01 (until December 2026) the ankles,
# knees and hips of a walking robot sat at +-10 N m flipping sign within a control cycle
# (ankle roll: 55% of substeps; tests/models/test_motors.py), a stance foot had no
# contact in 23% of its substeps, and 23 of 100 runs of the walk course had a fall (none
# with these values). kv 20 with armature 0.05 also stops it, but slowed the keyframe
# kicks' swings out of their tuning (four kick tests failed).
MOTOR_KV = 10.0  # N m s / rad
JOINT_ARMATURE = 0.03  # kg m^2, reflected rotor inertia
JOINT_DAMPING = 0.05  # N m s / rad
FOOT_FRICTION = 1.0

TEAM_RGBA = {"L": "0.15 0.35 0.9 1", "R": "0.9 0.2 0.15 1", "": "0.75 0.75 0.75 1"}


def _f(*v: float) -> str:
    return " ".join(f"{x:.6g}" for x in v)


@dataclass
class RobotXml:
    """The parts of one robot that go into a scene."""

    body: ET.Element
    actuators: list[ET.Element] = field(default_factory=list)
    sensors: list[ET.Element] = field(default_factory=list)


def robot_xml(
    robot_type: int,
    prefix: str = "",
    pos: tuple[float, float, float] | None = None,
    yaw: float = 0.0,
    contype: int = 1,
    conaffinity: int = 1,
    rgba: str | None = None,
) -> RobotXml:
    """Build the body tree, actuators and sensors of one robot.

    pos is the torso center in the world frame (m); yaw its heading (rad).
    contype/conaffinity go on every colliding geom of the robot.
    """
    import math

    team_rgba = rgba or TEAM_RGBA.get(prefix[:1], TEAM_RGBA[""])
    table = nao.links(robot_type)
    specs = {j.name: j for j in nao.joints(robot_type)}
    if pos is None:
        pos = (0.0, 0.0, nao.standing_height(robot_type))
    elements: dict[str, ET.Element] = {}
    out = RobotXml(body=ET.Element("body"))
    for ln in table:
        if ln.parent == "":
            el = out.body
            el.set("name", prefix + ln.name)
            el.set("pos", _f(*pos))
            el.set("quat", _f(math.cos(yaw / 2), 0, 0, math.sin(yaw / 2)))
            ET.SubElement(el, "freejoint", name=prefix + "root")
            ET.SubElement(el, "site", name=prefix + "imu", size="0.01", rgba="0 0 0 0")
        else:
            el = ET.SubElement(elements[ln.parent], "body", name=prefix + ln.name,
                               pos=_f(*nao.to_project(ln.pos)))
        elements[ln.name] = el
        if ln.joint:
            spec = specs[ln.joint]
            ET.SubElement(el, "joint", name=prefix + ln.joint, type="hinge",
                          pos=_f(*nao.to_project(ln.anchor)), axis=_f(*spec.axis),
                          range=_f(spec.lower, spec.upper), armature=_f(JOINT_ARMATURE),
                          damping=_f(JOINT_DAMPING))
        geom = ET.SubElement(el, "geom", name=prefix + ln.name, mass=_f(ln.mass))
        if ln.shape == "box":
            geom.set("type", "box")
            geom.set("size", _f(*(s / 2 for s in nao.size_to_project(ln.size))))
        elif ln.shape == "sphere":
            geom.set("type", "sphere")
            geom.set("size", _f(ln.size[0]))
        else:
            geom.set("type", "capsule")
            geom.set("size", _f(ln.size[0], ln.size[1] / 2))
        if ln.collides:
            geom.set("contype", str(contype))
            geom.set("conaffinity", str(conaffinity))
            geom.set("friction", _f(FOOT_FRICTION, 0.005, 0.0001))
        else:
            geom.set("contype", "0")
            geom.set("conaffinity", "0")
        light = ln.name in ("torso", "head") or "arm" in ln.name or "thigh" in ln.name
        geom.set("rgba", team_rgba if light else "0.85 0.85 0.85 1")
        if ln.name == "head":
            ET.SubElement(el, "site", name=prefix + "camera", size="0.005", rgba="0 0 0 0")
            ET.SubElement(el, "camera", name=prefix + "eye", pos="0.06 0 0",
                          xyaxes="0 -1 0 0 0 1", fovy="120")
        if ln.name in ("lfoot", "rfoot", "ltoe", "rtoe"):
            sx, sy, sz = nao.size_to_project(ln.size)
            ET.SubElement(el, "site", name=prefix + ln.name + "_sole", type="box",
                          pos=_f(0, 0, -sz / 2), size=_f(sx / 2 + 0.002, sy / 2 + 0.002, 0.006),
                          rgba="0 0 0 0")
    for spec in specs.values():
        out.actuators.append(ET.Element(
            "velocity", name=prefix + spec.effector, joint=prefix + spec.name, kv=_f(MOTOR_KV),
            ctrlrange=_f(-spec.max_speed, spec.max_speed),
            forcerange=_f(-nao.MAX_MOTOR_TORQUE, nao.MAX_MOTOR_TORQUE)))
    for spec in specs.values():
        out.sensors.append(ET.Element("jointpos", name=prefix + spec.name,
                                      joint=prefix + spec.name))
    out.sensors.append(ET.Element("gyro", name=prefix + "gyro", site=prefix + "imu"))
    out.sensors.append(ET.Element("accelerometer", name=prefix + "acc", site=prefix + "imu"))
    for foot in sole_names(robot_type):
        out.sensors.append(ET.Element("touch", name=prefix + foot, site=prefix + foot + "_sole"))
    return out


def sole_names(robot_type: int) -> list[str]:
    """Links with a force sensor under them: the feet, and type 4's toes."""
    return ["lfoot", "rfoot"] + (["ltoe", "rtoe"] if nao.robot_type(robot_type).toe else [])


def mjcf_options(root: ET.Element, timestep: float) -> None:
    """Simulator options shared by the robot and scene models."""
    ET.SubElement(root, "compiler", angle="radian", autolimits="true")
    ET.SubElement(root, "option", timestep=_f(timestep), integrator="implicitfast",
                  cone="pyramidal", iterations="20", ls_iterations="8")
    size = ET.SubElement(root, "visual")
    ET.SubElement(size, "global", offwidth="1280", offheight="720")


def robot_mjcf(robot_type: int, timestep: float = 0.005) -> str:
    """A whole MJCF document with one robot standing on a floor (for the viewer)."""
    root = ET.Element("mujoco", model=f"nao_type{robot_type}")
    mjcf_options(root, timestep)
    world = ET.SubElement(root, "worldbody")
    ET.SubElement(world, "light", pos="0 0 3", dir="0 0 -1", directional="true")
    ET.SubElement(world, "geom", name="floor", type="plane", size="5 5 0.1",
                  rgba="0.2 0.55 0.2 1", contype="1", conaffinity="2")
    parts = robot_xml(robot_type, contype=2, conaffinity=1)  # floor only, no self-collision
    world.append(parts.body)
    ET.SubElement(root, "actuator").extend(parts.actuators)
    ET.SubElement(root, "sensor").extend(parts.sensors)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode")

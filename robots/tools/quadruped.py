#!/usr/bin/env python3
"""Writes robots/quadruped/quadruped.urdf: a quadruped modelled on the Unitree A1, for the
floating-base and tree tests (the trunk is the root link; the URDF itself has no floating joint).

Every number is Unitree's, from the A1 description in Unitree's public repository
github.com/unitreerobotics/unitree_ros:
  robots/a1_description/urdf/a1.urdf (commit d8c05bfd006f21048f278bec21b6d71fd35c019f):
      trunk inertial; the front-left hip, thigh and calf inertials (the other legs are their
      mirror images, with the signs the file itself writes for FR, RL and RR); the joint origins;
      effort and velocity limits.
  robots/a1_description/xacro/const.xacro (from which a1.urdf is generated): the position limits
      in degrees (hip -46..46, thigh -60..240, calf -154.5..-52.5), converted here with
      math.radians; the lengths (leg_offset_x 0.1805, leg_offset_y 0.047, thigh_offset 0.0838,
      thigh_length 0.2, calf_length 0.2).
Left out: the source's visual/collision/meshes/transmissions/gazebo elements, its `base` link and
`floating_base` fixed joint (the trunk is the root here), `imu_link` (0.001 kg) and the collision
link `<leg>_thigh_shoulder`; the foot is a massless point (the source's foot is a 0.06 kg sphere).
See robots/README.md, section 6.

Usage: quadruped.py [out.urdf]   (default: robots/quadruped/quadruped.urdf)
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "quadruped", "quadruped.urdf")

# Lengths [m] (const.xacro "kinematic value" / "leg offset from trunk center value").
LEG_OFFSET_X = 0.1805
LEG_OFFSET_Y = 0.047
THIGH_OFFSET = 0.0838
THIGH_LENGTH = 0.2
CALF_LENGTH = 0.2

# Limits: position [deg] (const.xacro), effort [N m], velocity [rad/s] (a1.urdf, const.xacro).
LIMITS = {
    "hip": (-46, 46, 33.5, 21),
    "thigh": (-60, 240, 33.5, 21),
    "calf": (-154.5, -52.5, 33.5, 21),
}
AXES = {"hip": "1 0 0", "thigh": "0 1 0", "calf": "0 1 0"}

# Inertials as a1.urdf writes them: mass [kg], COM [m], (ixx, ixy, ixz, iyy, iyz, izz) [kg m^2]
# about the COM in the link frame's axes.
TRUNK = (6.0, (0.0, 0.0041, -0.0005), (0.0158533, -3.66e-05, -6.11e-05, 0.0377999, -2.75e-05, 0.0456542))
# Front-left leg (a1.urdf FL_hip, FL_thigh, FL_calf).
HIP = (0.696, (-0.003311, 0.000635, 3.1e-05), (0.000469246, -9.409e-06, -3.42e-07, 0.00080749, -4.66e-07, 0.000552929))
THIGH = (1.013, (-0.003237, -0.022327, -0.027326), (0.005529065, 4.825e-06, 0.000343869, 0.005139339, 2.2448e-05, 0.001367788))
CALF = (0.166, (0.006435, 0.0, -0.107388), (0.002997972, 0.0, -0.000141163, 0.003014022, 0.0, 3.2426e-05))

# (name, sx, sy): sx = +1 front / -1 rear, sy = +1 left / -1 right.
LEGS = (("FL", 1, 1), ("FR", 1, -1), ("RL", -1, 1), ("RR", -1, -1))


def num(value):
    """Shortest round-trip text; zero (of either sign) as 0."""
    return "0" if value == 0 else repr(value)


def mirrored(inertial, sx, sy):
    """The inertial mirrored through the x-z plane (sy = -1) and/or the y-z plane (sx = -1):
    COM x, y and the products of inertia change sign as a1.urdf's FR, RL and RR links show."""
    mass, (cx, cy, cz), (ixx, ixy, ixz, iyy, iyz, izz) = inertial
    return mass, (sx * cx, sy * cy, cz), (ixx, sx * sy * ixy, sx * ixz, iyy, sy * iyz, izz)


def add_link(robot, name, inertial=None):
    link = ET.SubElement(robot, "link", name=name)
    if inertial is None:
        return
    mass, com, tensor = inertial
    element = ET.SubElement(link, "inertial")
    ET.SubElement(element, "origin", xyz=" ".join(num(c) for c in com), rpy="0 0 0")
    ET.SubElement(element, "mass", value=num(mass))
    ET.SubElement(element, "inertia", **dict(zip(("ixx", "ixy", "ixz", "iyy", "iyz", "izz"), (num(i) for i in tensor))))


def add_joint(robot, name, kind, parent, child, xyz, part=None):
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    ET.SubElement(joint, "origin", xyz=" ".join(num(c) for c in xyz), rpy="0 0 0")
    if part is not None:
        lower, upper, effort, velocity = LIMITS[part]
        ET.SubElement(joint, "axis", xyz=AXES[part])
        ET.SubElement(joint, "limit", lower=repr(math.radians(lower)), upper=repr(math.radians(upper)),
                      effort=num(effort), velocity=num(velocity))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    robot = ET.Element("robot", name="quadruped")
    robot.append(ET.Comment(
        " Written by robots/tools/quadruped.py: a quadruped modelled on the Unitree A1, every number from"
        " Unitree's a1_description (github.com/unitreerobotics/unitree_ros, urdf/a1.urdf and xacro/const.xacro);"
        " sources and omissions in ../README.md. "))
    # The tree for the fuzzers' seed run (fuzz/fuzz_entries.cpp, read_chain_directive).
    robot.append(ET.Comment(" chain root=trunk tip=FL_foot branch=FR_foot branch=RL_foot branch=RR_foot floating "))
    add_link(robot, "trunk", TRUNK)
    for leg, sx, sy in LEGS:
        add_joint(robot, leg + "_hip_joint", "revolute", "trunk", leg + "_hip",
                  (sx * LEG_OFFSET_X, sy * LEG_OFFSET_Y, 0.0), "hip")
        add_link(robot, leg + "_hip", mirrored(HIP, sx, sy))
        add_joint(robot, leg + "_thigh_joint", "revolute", leg + "_hip", leg + "_thigh",
                  (0.0, sy * THIGH_OFFSET, 0.0), "thigh")
        add_link(robot, leg + "_thigh", mirrored(THIGH, 1, sy))  # a1.urdf: RL = FL, RR = FR
        add_joint(robot, leg + "_calf_joint", "revolute", leg + "_thigh", leg + "_calf",
                  (0.0, 0.0, -THIGH_LENGTH), "calf")
        add_link(robot, leg + "_calf", CALF)  # a1.urdf: the same for all four legs
        add_joint(robot, leg + "_foot_fixed", "fixed", leg + "_calf", leg + "_foot", (0.0, 0.0, -CALF_LENGTH))
        add_link(robot, leg + "_foot")
    ET.indent(robot, space="  ")
    with open(out, "w") as f:
        f.write('<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n")


if __name__ == "__main__":
    main()

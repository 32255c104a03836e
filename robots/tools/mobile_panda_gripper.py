#!/usr/bin/env python3
"""Writes robots/mobile_panda_gripper/mobile_panda_gripper.urdf: the mobile Panda
(robots/tools/mobile_panda.py, every number and source as cited there) with the Franka Hand's two
fingers as Franka's own description ships them, the second a <mimic> of the first.

The fingers are those of franka_description (github.com/frankaemika/franka_ros):
  * kinematics and limits from robots/common/franka_hand.xacro: panda_finger_joint1 (prismatic,
    child panda_leftfinger) and panda_finger_joint2 (child panda_rightfinger), both at
    xyz (0, 0, 0.0584) m in panda_hand, axes +y and -y, limits 0 to 0.04 m, effort 100 N,
    velocity 0.2 m/s; joint 2 carries <mimic joint="panda_finger_joint1"/> (multiplier 1,
    offset 0): the fingers open symmetrically. Franka's <dynamics damping="0.3"/> is left out,
    as in every file here (robots/README.md, rules).
  * inertials from robots/common/inertial.yaml (leftfinger, and rightfinger = the same): mass
    0.015 kg, COM at the finger frame's origin, I = diag(2.375e-6, 2.375e-6, 7.5e-7) kg m^2.
The hand keeps panda.urdf's inertial (inertial.yaml's `hand` entry, without the fingers).

Usage: mobile_panda_gripper.py [out.urdf]   (default: robots/mobile_panda_gripper/mobile_panda_gripper.urdf)
"""
import os
import sys
import xml.etree.ElementTree as ET

sys.dont_write_bytecode = True  # no __pycache__ in robots/tools from the imports below
from dual_panda import write_urdf  # noqa: E402
from mobile_panda import mobile_panda  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "mobile_panda_gripper", "mobile_panda_gripper.urdf")

FINGER_MASS = 0.015  # kg
FINGER_INERTIA = ("2.375e-06", "2.375e-06", "7.5e-07")  # kg m^2: ixx, iyy, izz about the COM
FINGER_Z = "0.0584"  # m: the finger joints' origin in panda_hand


def finger(robot, joint, link, axis, mimic):
    """A prismatic finger `joint` moving `link` along `axis` in panda_hand, a <mimic> of `mimic` if given."""
    element = ET.SubElement(robot, "joint", name=joint, type="prismatic")
    ET.SubElement(element, "parent", link="panda_hand")
    ET.SubElement(element, "child", link=link)
    ET.SubElement(element, "origin", xyz="0 0 " + FINGER_Z, rpy="0 0 0")
    ET.SubElement(element, "axis", xyz=axis)
    ET.SubElement(element, "limit", lower="0.0", upper="0.04", effort="100", velocity="0.2")
    if mimic:
        ET.SubElement(element, "mimic", joint=mimic, multiplier="1", offset="0")
    inertial = ET.SubElement(ET.SubElement(robot, "link", name=link), "inertial")
    ET.SubElement(inertial, "origin", xyz="0 0 0", rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=repr(FINGER_MASS))
    ixx, iyy, izz = FINGER_INERTIA
    ET.SubElement(inertial, "inertia", ixx=ixx, ixy="0", ixz="0", iyy=iyy, iyz="0", izz=izz)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    robot = mobile_panda("mobile_panda_gripper")
    robot.insert(1, ET.Comment(
        " Written by robots/tools/mobile_panda_gripper.py: the Franka Hand's fingers from franka_description"
        " (sources in ../README.md), panda_finger_joint2 a <mimic> of panda_finger_joint1. "))
    # The tree for the fuzzers' seed run (fuzz/fuzz_entries.cpp, read_chain_directive).
    robot.insert(2, ET.Comment(" chain root=mobile_base tip=panda_leftfinger branch=panda_rightfinger floating "))
    finger(robot, "panda_finger_joint1", "panda_leftfinger", "0 1 0", None)
    finger(robot, "panda_finger_joint2", "panda_rightfinger", "0 -1 0", "panda_finger_joint1")
    write_urdf(robot, out)


if __name__ == "__main__":
    main()

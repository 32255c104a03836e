#!/usr/bin/env python3
"""Writes robots/dual_panda/dual_panda.urdf: two Panda arms (robots/panda/panda.urdf, every
parameter and its source as cited there) on a torso that turns about the vertical, a kinematic
tree with a shared trunk for the tree and constraint-set tests and the bundled dual-arm scene.

The torso is written for this project, not a product: a 15 kg box 0.3 m x 0.3 m x 0.6 m on a
yaw joint, its inertia that of a uniform box (I = m/12 (b^2 + c^2) about the centre). Each arm's
names get a prefix (left_, right_); its base panda_link0 is fixed to the torso 0.5 m up and
0.2 m to the side, rolled by -/+ 90 degrees so that the arms reach out sideways.

Usage: dual_panda.py [out.urdf]   (default: robots/dual_panda/dual_panda.urdf)
"""
import os
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
PANDA = os.path.join(HERE, "..", "panda", "panda.urdf")
OUT = os.path.join(HERE, "..", "dual_panda", "dual_panda.urdf")
HALF_PI = "1.5707963267948966"

TORSO_MASS = 15.0
TORSO_SIZE = (0.3, 0.3, 0.6)


def box_inertia(mass, size):
    a, b, c = size
    return (mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c), mass / 12 * (a * a + b * b))


def arm(prefix):
    """The Panda's links and joints with prefixed names."""
    robot = ET.parse(PANDA).getroot()
    elements = []
    for element in robot:
        if element.tag not in ("link", "joint"):
            continue
        element.set("name", prefix + element.get("name"))
        for tag in ("parent", "child"):
            for ref in element.findall(tag):
                ref.set("link", prefix + ref.get("link"))
        elements.append(element)
    return elements


def write_urdf(robot, out):
    """Writes the <robot> element to `out`, indented by two spaces."""
    ET.indent(robot, space="  ")
    with open(out, "w") as f:
        f.write('<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    robot = ET.Element("robot", name="dual_panda")
    robot.append(ET.Comment(
        " Written by robots/tools/dual_panda.py from ../panda/panda.urdf (parameters and sources"
        " cited there); the torso is this project's: a uniform 15 kg box on a yaw joint. "))
    # The tree for the fuzzers' seed run (fuzz/fuzz_entries.cpp, read_chain_directive).
    robot.append(ET.Comment(" chain root=station tip=left_panda_hand branch=right_panda_hand "))
    ET.SubElement(robot, "link", name="station")
    torso_joint = ET.SubElement(robot, "joint", name="torso_joint", type="revolute")
    ET.SubElement(torso_joint, "parent", link="station")
    ET.SubElement(torso_joint, "child", link="torso")
    ET.SubElement(torso_joint, "origin", xyz="0 0 0.4", rpy="0 0 0")
    ET.SubElement(torso_joint, "axis", xyz="0 0 1")
    ET.SubElement(torso_joint, "limit", lower="-2.9", upper="2.9", effort="200", velocity="1.5")
    torso = ET.SubElement(robot, "link", name="torso")
    inertial = ET.SubElement(torso, "inertial")
    ET.SubElement(inertial, "origin", xyz="0 0 %r" % (TORSO_SIZE[2] / 2), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=repr(TORSO_MASS))
    ixx, iyy, izz = box_inertia(TORSO_MASS, TORSO_SIZE)
    ET.SubElement(inertial, "inertia", ixx=repr(ixx), ixy="0", ixz="0", iyy=repr(iyy), iyz="0", izz=repr(izz))
    for prefix, side, roll in (("left_", "0.2", "-" + HALF_PI), ("right_", "-0.2", HALF_PI)):
        mount = ET.SubElement(robot, "joint", name=prefix + "mount", type="fixed")
        ET.SubElement(mount, "parent", link="torso")
        ET.SubElement(mount, "child", link=prefix + "panda_link0")
        ET.SubElement(mount, "origin", xyz="0 %s 0.5" % side, rpy="%s 0 0" % roll)
        for element in arm(prefix):
            robot.append(element)
    write_urdf(robot, out)


if __name__ == "__main__":
    main()

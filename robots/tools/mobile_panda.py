#!/usr/bin/env python3
"""Writes robots/mobile_panda/mobile_panda.urdf: the Panda arm (robots/panda/panda.urdf, every
parameter and its source as cited there, all names kept) standing on a wheeled omnidirectional
base, a mobile manipulator for the tests.

The base `mobile_base` (the root link) is one rigid box the size and mass of a Clearpath Ridgeback:
  * length 0.960 m, width 0.793 m, height 0.311 m, ground clearance 0.018 m: Clearpath Robotics,
    "Ridgeback User Manual", System Specifications
    (docs.clearpathrobotics.com; source github.com/clearpathrobotics/cpr-documentation,
    docs_robots/indoor_robots/ridgeback/user_manual_ridgeback.mdx);
  * mass 125 kg: the weight Clearpath gave at the Ridgeback's launch, as reported by IEEE Spectrum
    (2015) and quoted in "The Robot That's Going to Steal Your Job Just Got Wheels", Motherboard
    (motherboard.vice.com/read/the-robot-thats-going-to-steal-your-job-just-got-wheels).
The box spans the body from the ground clearance to the top (0.293 m = 0.311 - 0.018 m); its
inertia is that of a uniform box about its centre, I = m/12 (b^2 + c^2). The wheels are not
modelled (the base is the fixed root here). The base frame lies on the floor under the centre of the
platform; panda_link0 stands on the centre of the top plate, 0.311 m up, facing forward (our
choice of mount). See robots/README.md, section 7.

Usage: mobile_panda.py [out.urdf]   (default: robots/mobile_panda/mobile_panda.urdf)
"""
import os
import sys
import xml.etree.ElementTree as ET

sys.dont_write_bytecode = True  # no __pycache__ in robots/tools from the import below
from dual_panda import arm, box_inertia, write_urdf  # noqa: E402  (robots/tools/dual_panda.py: the Panda's links and joints)

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "mobile_panda", "mobile_panda.urdf")

BASE_MASS = 125.0  # kg
BASE_SIZE = (0.96, 0.793, 0.293)  # m: length, width, height 0.311 - clearance 0.018
BASE_COM_Z = 0.1645  # m: 0.018 + 0.293 / 2, the box centre above the floor
MOUNT_Z = 0.311  # m: the top plate (the Ridgeback's height)


def mobile_panda(name):
    """The <robot> element: the base, its mount and the Panda's links and joints."""
    robot = ET.Element("robot", name=name)
    robot.append(ET.Comment(
        " Written by robots/tools/mobile_panda.py from ../panda/panda.urdf (parameters and sources cited"
        " there); the base is a uniform box the size and mass of a Clearpath Ridgeback (sources in ../README.md). "))
    base = ET.SubElement(robot, "link", name="mobile_base")
    inertial = ET.SubElement(base, "inertial")
    ET.SubElement(inertial, "origin", xyz="0 0 %r" % BASE_COM_Z, rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=repr(BASE_MASS))
    ixx, iyy, izz = box_inertia(BASE_MASS, BASE_SIZE)
    ET.SubElement(inertial, "inertia", ixx=repr(ixx), ixy="0", ixz="0", iyy=repr(iyy), iyz="0", izz=repr(izz))
    mount = ET.SubElement(robot, "joint", name="panda_mount", type="fixed")
    ET.SubElement(mount, "parent", link="mobile_base")
    ET.SubElement(mount, "child", link="panda_link0")
    ET.SubElement(mount, "origin", xyz="0 0 %r" % MOUNT_Z, rpy="0 0 0")
    for element in arm(""):
        robot.append(element)
    return robot


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    write_urdf(mobile_panda("mobile_panda"), out)


if __name__ == "__main__":
    main()

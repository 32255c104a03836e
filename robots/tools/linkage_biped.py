#!/usr/bin/env python3
"""Writes robots/linkage_biped/linkage_biped.urdf: a two-legged robot whose knees are driven through
four-bar linkages, for the closed-chain scenes on a floating base (robots/README.md, section 11).

Not a product. The trunk and the two legs are the Unitree A1's trunk and front legs, every number
as robots/tools/quadruped.py takes it from Unitree's a1_description (cited there). Added here, our
own: each knee is moved by a motor at the hip, coaxial with the thigh joint, through a parallelogram
linkage as many legged robots drive their knees: a crank of 0.04 m (0.05 kg) on the hip link, a rod
of 0.2 m (the thigh's length, 0.08 kg) from the crank's end to a lever point 0.04 m behind the knee
on the calf. The URDF is the spanning tree (the rod hangs from the crank); the scene
linkage_biped_stance.yaml closes each loop with a set between the rod's end and the calf's lever
point (the pin's two in-plane forces) and holds the feet on the ground. With the crank's angle
θ_c, the thigh's θ_t and the calf's θ_k, the loop closes at θ_k = θ_c − θ_t and the rod's joint at
θ_t − θ_c. Rods are thin: I = m l^2 / 12 across, 1e-6 kg m^2 along (our own value).

Usage: linkage_biped.py [out.urdf]   (default: robots/linkage_biped/linkage_biped.urdf)
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import quadruped as a1  # noqa: E402  (the A1's numbers and the URDF helpers)

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "linkage_biped", "linkage_biped.urdf")

CRANK_LENGTH, CRANK_MASS = 0.04, 0.05
ROD_LENGTH, ROD_MASS = a1.THIGH_LENGTH, 0.08
ALONG = 1e-6


def rod(length, mass, direction):
    """A thin rod from the link origin along `direction` (a unit axis as a tuple)."""
    across = mass * length * length / 12
    com = tuple(length / 2 * d for d in direction)
    moments = tuple(ALONG if d else across for d in direction)
    return mass, com, (moments[0], 0.0, 0.0, moments[1], 0.0, moments[2])


def joint_with_limits(robot, name, parent, child, xyz, lower, upper, effort, velocity):
    joint = ET.SubElement(robot, "joint", name=name, type="revolute")
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    ET.SubElement(joint, "origin", xyz=" ".join(a1.num(c) for c in xyz), rpy="0 0 0")
    ET.SubElement(joint, "axis", xyz="0 1 0")
    ET.SubElement(joint, "limit", lower=repr(lower), upper=repr(upper), effort=a1.num(effort), velocity=a1.num(velocity))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    robot = ET.Element("robot", name="linkage_biped")
    robot.append(ET.Comment(
        " Written by robots/tools/linkage_biped.py: the Unitree A1's trunk and front legs (numbers from Unitree's"
        " a1_description, as robots/tools/quadruped.py cites them) with each knee driven from the hip through a"
        " parallelogram linkage of our own; the scene closes the loops. Sources: ../README.md. "))
    robot.append(ET.Comment(" chain root=trunk tip=FL_foot branch=FR_foot branch=FL_rod branch=FR_rod floating "))
    a1.add_link(robot, "trunk", a1.TRUNK)
    for leg, sx, sy in a1.LEGS[:2]:
        a1.add_joint(robot, leg + "_hip_joint", "revolute", "trunk", leg + "_hip",
                     (sx * a1.LEG_OFFSET_X, sy * a1.LEG_OFFSET_Y, 0.0), "hip")
        a1.add_link(robot, leg + "_hip", a1.mirrored(a1.HIP, sx, sy))
        a1.add_joint(robot, leg + "_thigh_joint", "revolute", leg + "_hip", leg + "_thigh",
                     (0.0, sy * a1.THIGH_OFFSET, 0.0), "thigh")
        a1.add_link(robot, leg + "_thigh", a1.mirrored(a1.THIGH, 1, sy))
        a1.add_joint(robot, leg + "_calf_joint", "revolute", leg + "_thigh", leg + "_calf",
                     (0.0, 0.0, -a1.THIGH_LENGTH), "calf")
        a1.add_link(robot, leg + "_calf", a1.CALF)
        a1.add_joint(robot, leg + "_foot_fixed", "fixed", leg + "_calf", leg + "_foot", (0.0, 0.0, -a1.CALF_LENGTH))
        a1.add_link(robot, leg + "_foot")
        # The knee's drive: crank (the knee motor, coaxial with the thigh joint) and rod (passive).
        joint_with_limits(robot, leg + "_knee_crank_joint", leg + "_hip", leg + "_knee_crank",
                          (0.0, sy * a1.THIGH_OFFSET, 0.0), -math.pi, math.pi, 33.5, 21)
        a1.add_link(robot, leg + "_knee_crank", rod(CRANK_LENGTH, CRANK_MASS, (-1.0, 0.0, 0.0)))
        joint_with_limits(robot, leg + "_knee_rod_joint", leg + "_knee_crank", leg + "_rod",
                          (-CRANK_LENGTH, 0.0, 0.0), -math.pi, math.pi, 1, 21)
        a1.add_link(robot, leg + "_rod", rod(ROD_LENGTH, ROD_MASS, (0.0, 0.0, -1.0)))
    ET.indent(robot, space="  ")
    with open(out, "w") as f:
        f.write('<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n")


if __name__ == "__main__":
    main()

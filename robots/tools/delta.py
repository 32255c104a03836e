#!/usr/bin/env python3
"""Writes robots/delta/delta.urdf: a delta robot (Clavel's parallel arm: three arms on a fixed base
carry a platform that only translates) as the spanning tree sweepgen loads; the scene
delta_loops.yaml closes its three loops.

Not a product: the geometry and masses are our own round numbers, of the size of small pick-and-
place deltas. The tree:
  - each arm i (i = 0, 1, 2, at 120 degree steps about z): a shoulder (revolute, axis tangential)
    at 0.2 m from the centre, an upper arm of 0.25 m, an elbow of two revolute joints (a universal
    joint: about the shoulder's axis, then about the arm's own z) with a 10 g cross between, a
    forearm of 0.5 m. Real deltas use a parallelogram of two rods per forearm; one rod with a ball
    at each end moves the platform the same way and is what we model.
  - the platform (0.5 kg, radius 0.05 m) on three prismatic joints x, y, z through two 10 g
    carriages: the platform's three translations, which it has (it does not turn: the arms' loops
    and the missing rotations keep it level, as the parallelograms do).
Each loop closes at a ball: the forearm's end against a point of the platform 0.05 m from its
centre towards arm i (three linear directions). The passive joints (elbows, the platform's
translations) carry no motor: their effort limit of 1 is nominal (only a saturating policy reads
it). Rods are thin: I = m l^2 / 12 about the centre
across the rod, 1e-4 kg m^2 along it (our own small value for the thickness); the platform a disk,
I = m r^2 / 4 across and m r^2 / 2 about z.

Usage: delta.py [out.urdf]   (default: robots/delta/delta.urdf)
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "..", "delta", "delta.urdf")

BASE_RADIUS, UPPER_ARM, FOREARM, PLATFORM_RADIUS = 0.2, 0.25, 0.5, 0.05
UPPER_ARM_MASS, FOREARM_MASS, CROSS_MASS, PLATFORM_MASS = 0.3, 0.2, 0.01, 0.5
THIN = 1e-4


def inertial(mass, com, ixx, iyy, izz):
    return (f'    <inertial>\n      <origin xyz="{com[0]!r} {com[1]!r} {com[2]!r}" rpy="0 0 0"/>\n'
            f'      <mass value="{mass!r}"/>\n'
            f'      <inertia ixx="{ixx!r}" ixy="0" ixz="0" iyy="{iyy!r}" iyz="0" izz="{izz!r}"/>\n    </inertial>\n')


def rod(name, length, mass):
    across = mass * length * length / 12
    return f'  <link name="{name}">\n' + inertial(mass, (length / 2, 0.0, 0.0), THIN, across, across) + '  </link>\n'


def small(name):
    i = CROSS_MASS * 1e-4
    return f'  <link name="{name}">\n' + inertial(CROSS_MASS, (0.0, 0.0, 0.0), i, i, i) + '  </link>\n'


def joint(name, kind, parent, child, xyz, rpy, axis, lower, upper, effort, velocity):
    return (f'  <joint name="{name}" type="{kind}">\n    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
            f'    <origin xyz="{xyz[0]!r} {xyz[1]!r} {xyz[2]!r}" rpy="{rpy[0]!r} {rpy[1]!r} {rpy[2]!r}"/>\n'
            f'    <axis xyz="{axis[0]} {axis[1]} {axis[2]}"/>\n'
            f'    <limit lower="{lower!r}" upper="{upper!r}" effort="{effort!r}" velocity="{velocity!r}"/>\n  </joint>\n')


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    parts = ['<?xml version="1.0"?>\n<robot name="delta">\n',
             '  <!-- Written by robots/tools/delta.py: a delta robot as a spanning tree (arms and the platform\'s\n'
             '       translations); its three loops are closed by robots/delta/delta_loops.yaml. Sources: ../README.md. -->\n',
             '  <!-- chain root=base tip=platform branch=forearm_0 branch=forearm_1 branch=forearm_2 -->\n',
             '  <link name="base">\n' + inertial(2.0, (0.0, 0.0, 0.0), 0.02, 0.02, 0.04) + '  </link>\n']
    for i in range(3):
        phi = 2 * math.pi * i / 3
        parts.append(rod(f"upper_arm_{i}", UPPER_ARM, UPPER_ARM_MASS))
        parts.append(small(f"elbow_cross_{i}"))
        parts.append(rod(f"forearm_{i}", FOREARM, FOREARM_MASS))
        parts.append(joint(f"shoulder_{i}", "revolute", "base", f"upper_arm_{i}",
                           (BASE_RADIUS * math.cos(phi), BASE_RADIUS * math.sin(phi), 0.0), (0.0, 0.0, phi),
                           (0, 1, 0), -1.5, 2.5, 40.0, 10.0))
        parts.append(joint(f"elbow_{i}_swing", "revolute", f"upper_arm_{i}", f"elbow_cross_{i}", (UPPER_ARM, 0.0, 0.0),
                           (0.0, 0.0, 0.0), (0, 1, 0), -3.0, 3.0, 1.0, 20.0))
        parts.append(joint(f"elbow_{i}_tilt", "revolute", f"elbow_cross_{i}", f"forearm_{i}", (0.0, 0.0, 0.0),
                           (0.0, 0.0, 0.0), (0, 0, 1), -1.0, 1.0, 1.0, 20.0))
    parts.append(small("carriage_x"))
    parts.append(small("carriage_y"))
    across, about_z = PLATFORM_MASS * PLATFORM_RADIUS ** 2 / 4, PLATFORM_MASS * PLATFORM_RADIUS ** 2 / 2
    parts.append('  <link name="platform">\n' + inertial(PLATFORM_MASS, (0.0, 0.0, 0.0), across, across, about_z) + '  </link>\n')
    for name, parent, child, axis in (("platform_x", "base", "carriage_x", (1, 0, 0)),
                                      ("platform_y", "carriage_x", "carriage_y", (0, 1, 0)),
                                      ("platform_z", "carriage_y", "platform", (0, 0, 1))):
        parts.append(joint(name, "prismatic", parent, child, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), axis, -1.0, 1.0, 1.0, 5.0))
    parts.append('</robot>\n')
    with open(out, "w") as f:
        f.write("".join(parts))


if __name__ == "__main__":
    main()

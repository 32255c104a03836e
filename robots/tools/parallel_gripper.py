#!/usr/bin/env python3
"""Writes robots/parallel_gripper/parallel_gripper.urdf: the UR5 (robots/ur5/ur5.urdf, every
parameter and its source as cited there, all names kept) carrying a Robotiq 2F-85 adaptive
gripper as Robotiq's own description ships it, its six finger joints one driven joint and five
<mimic>s of it, a kinematic tree for the tests of coupled joints and the bundled pinch scene.

The gripper is that of ROS-Industrial's robotiq repository (github.com/ros-industrial/robotiq,
now ros-industrial-attic/robotiq; last change to these files 06416e18, 2019-02-01), package
robotiq_2f_85_gripper_visualization, files urdf/robotiq_arg2f_85_model_macro.xacro (the fingers)
and urdf/robotiq_arg2f.xacro (the base link), with prefix "" as robotiq_arg2f_85_model.xacro
instantiates it. All names are Robotiq's. From those files:
  * robotiq_arg2f_base_link (robotiq_arg2f.xacro): mass 0.22652 kg, COM (8.625e-8, -4.6583e-6,
    0.03145) m, I = (ixx 0.00020005, ixy -4.2442e-10, ixz -2.9069e-10, iyy 0.00017832,
    iyz -3.4402e-8, izz 0.00013478) kg m^2. z points from the mounting face towards the fingers.
  * finger_joint (revolute, child left_outer_knuckle): xyz (0, -0.0306011, 0.054904) m,
    rpy (0, 0, pi) in the base link, axis +x, limits 0 to 0.8 rad (0 open, 0.8 closed).
  * right_outer_knuckle_joint (child right_outer_knuckle): xyz (0, 0.0306011, 0.054904) m,
    rpy 0, axis +x, <mimic joint="finger_joint" multiplier="1" offset="0"/>.
  * <side>_outer_finger_joint (fixed, outer knuckle -> <side>_outer_finger): xyz (0, 0.0315, -0.0041) m.
  * <side>_inner_knuckle_joint (revolute, base link -> <side>_inner_knuckle): xyz (0, -0.0127, 0.06142)
    m with yaw pi (left), (0, 0.0127, 0.06142) m with yaw 0 (right): Robotiq's
    xyz (0, reflect * -0.0127, 0.06142), rpy (0, 0, (1 + reflect) * pi / 2), reflect = 1 left,
    -1 right; axis +x; <mimic joint="finger_joint" multiplier="1" offset="0"/>.
  * <side>_inner_finger_joint (revolute, outer finger -> <side>_inner_finger): xyz (0, 0.0061, 0.0471)
    m, rpy 0, axis +x, <mimic joint="finger_joint" multiplier="-1" offset="0"/>.
  * <side>_inner_finger_pad_joint (fixed, inner finger -> <side>_inner_finger_pad):
    xyz (0, -0.0220203446692936, 0.03242) m, rpy 0. The pad is Robotiq's box 0.022 x 0.00635 x
    0.0375 m (visual and collision only, no <inertial> in the source): thin along y, its face
    towards the other finger is its -y side.
  * inertials of the outer knuckle, outer finger, inner knuckle and inner finger: the values
    Robotiq's file carries for each link, commented out there (<!--<inertial> ... </inertial> -->,
    the CAD export's mass properties), the same for left and right (one macro for both sides):
      outer_knuckle: 0.00853198276973456 kg, COM (-0.000200000000003065, 0.0199435877845359,
        0.0292245259211331) m, ixx 2.89328108496468e-6, ixy -1.57935047237397e-19,
        ixz -1.93980378593255e-19, iyy 1.86719750325683e-6, iyz -1.21858577871576e-6,
        izz 1.21905238907251e-6 kg m^2;
      outer_finger: 0.022614240507152 kg, COM (0.00030115855001899, 0.0373907951953854,
        -0.0208027427000385) m, ixx 1.52518312458174e-5, ixy 9.76583423954399e-10,
        ixz -5.43838577022588e-10, iyy 6.17694243867776e-6, iyz 6.78636130740228e-6,
        izz 1.16494917907219e-5 kg m^2;
      inner_knuckle: 0.0271177346495152 kg, COM (0.000123011831763771, 0.0507850843201817,
        0.00103968640075166) m, ixx 2.61910379223783e-5, ixy -2.43616858946494e-7,
        ixz -6.37789906117123e-9, iyy 2.8270243746167e-6, iyz -5.37200748039765e-7,
        izz 2.83695868220296e-5 kg m^2;
      inner_finger: 0.0104003125914103 kg, COM (0.000299999999999317, 0.0160078233491243,
        -0.0136945669206257) m, ixx 2.71909453810972e-6, ixy 1.35402465472579e-21,
        ixz -7.1817349065269e-22, iyy 7.69100314106116e-07, iyz 6.74715432769696e-07,
        izz 2.30315190420171e-06 kg m^2.
    All are positive definite and meet the triangle inequalities (robots/tools/check_inertia.py).
    The gripper's links weigh 0.364 kg together.
  * velocity 2.0 rad/s on every finger joint (Robotiq's <limit velocity>).

What is ours, not Robotiq's:
  * The mount: robotiq_arg2f_base_link fixed to the UR5's flange frame tool0 (the last link of
    ur5.urdf, z out of the flange) by gripper_mount, xyz 0, rpy 0: the base link's mounting face on
    the flange, its z along tool0's. Robotiq's coupling plate has no URDF element and is left out.
  * Effort 20 N m on every finger joint. Robotiq writes effort="1000", a placeholder. Robotiq's
    2F-85 specification gives a grip force of up to 235 N; at the pad the force along the pad normal
    acts 0.07542 m (-0.0041 + 0.0471 + 0.03242, along the knuckle's z) from finger_joint's axis,
    235 N x 0.07542 m = 17.7 N m, rounded up to 20.
  * The mimics' limits: each the image of its source's range through its multiplier and offset
    (Robotiq writes 0 to 0.8757 rad for the inner knuckles and inner fingers, and 0 to 0.81 rad for
    right_outer_knuckle_joint, ranges that do not match finger_joint's 0 to 0.8 rad and, for the
    inner fingers, multiplier -1). Here: inner and outer knuckles 0 to 0.8 rad, left_inner_finger_joint
    -0.8 to 0 rad.
  * right_inner_finger_joint is a <mimic> of right_inner_knuckle_joint (multiplier -1, offset
    0.05 rad), not of finger_joint as in Robotiq's file: a chain of mimics (right_inner_finger_joint
    -> right_inner_knuckle_joint -> finger_joint) with an offset, so that a reader must resolve it to
    its root source, q = -1 (1 q_finger) + 0.05 = 0.05 - q_finger; its limits -0.75 to 0.05 rad (the
    image of 0 to 0.8). The right pad thus stands 0.05 rad (about its x axis) off parallel to the left.
  * The pads carry no <inertial> (as in Robotiq's file): contact frames, like tool0.
Robotiq's <transmission> and the meshes are left out, as in every file here (robots/README.md, rules).
See robots/README.md, section 12.

Usage: parallel_gripper.py [out.urdf]   (default: robots/parallel_gripper/parallel_gripper.urdf)
"""
import os
import sys
import xml.etree.ElementTree as ET

sys.dont_write_bytecode = True  # no __pycache__ in robots/tools from the import below
from dual_panda import write_urdf  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
UR5 = os.path.join(HERE, "..", "ur5", "ur5.urdf")
OUT = os.path.join(HERE, "..", "parallel_gripper", "parallel_gripper.urdf")
PI = "3.141592653589793"

FLANGE = "tool0"  # ur5.urdf's last link (flange frame)
BASE = "robotiq_arg2f_base_link"
EFFORT = "20"  # N m: our estimate (docstring)
VELOCITY = "2.0"  # rad/s: Robotiq's
FINGER_UPPER = 0.8  # rad: finger_joint's upper limit (Robotiq's)
INNER_FINGER_OFFSET = 0.05  # rad: right_inner_finger_joint's <mimic> offset (ours)

# Inertials as Robotiq's files write them: mass [kg], COM [m], (ixx, ixy, ixz, iyy, iyz, izz) [kg m^2].
INERTIALS = {
    "base_link": ("0.22652", ("8.625E-08", "-4.6583E-06", "0.03145"),
                  ("0.00020005", "-4.2442E-10", "-2.9069E-10", "0.00017832", "-3.4402E-08", "0.00013478")),
    "outer_knuckle": ("0.00853198276973456",
                      ("-0.000200000000003065", "0.0199435877845359", "0.0292245259211331"),
                      ("2.89328108496468E-06", "-1.57935047237397E-19", "-1.93980378593255E-19",
                       "1.86719750325683E-06", "-1.21858577871576E-06", "1.21905238907251E-06")),
    "outer_finger": ("0.022614240507152",
                     ("0.00030115855001899", "0.0373907951953854", "-0.0208027427000385"),
                     ("1.52518312458174E-05", "9.76583423954399E-10", "-5.43838577022588E-10",
                      "6.17694243867776E-06", "6.78636130740228E-06", "1.16494917907219E-05")),
    "inner_knuckle": ("0.0271177346495152",
                      ("0.000123011831763771", "0.0507850843201817", "0.00103968640075166"),
                      ("2.61910379223783E-05", "-2.43616858946494E-07", "-6.37789906117123E-09",
                       "2.8270243746167E-06", "-5.37200748039765E-07", "2.83695868220296E-05")),
    "inner_finger": ("0.0104003125914103",
                     ("0.000299999999999317", "0.0160078233491243", "-0.0136945669206257"),
                     ("2.71909453810972E-06", "1.35402465472579E-21", "-7.1817349065269E-22",
                      "7.69100314106116E-07", "6.74715432769696E-07", "2.30315190420171E-06")),
}


def link(robot, name, inertial_key):
    """A link, with Robotiq's inertial `inertial_key` (none if None)."""
    element = ET.SubElement(robot, "link", name=name)
    if inertial_key is None:
        return
    mass, com, tensor = INERTIALS[inertial_key]
    inertial = ET.SubElement(element, "inertial")
    ET.SubElement(inertial, "origin", xyz=" ".join(com), rpy="0 0 0")
    ET.SubElement(inertial, "mass", value=mass)
    ixx, ixy, ixz, iyy, iyz, izz = tensor
    ET.SubElement(inertial, "inertia", ixx=ixx, ixy=ixy, ixz=ixz, iyy=iyy, iyz=iyz, izz=izz)


def joint(robot, name, kind, parent, child, xyz, yaw="0", limits=None, mimic=None):
    """A joint; `limits` (lower, upper) for a revolute one about +x, `mimic` (joint, multiplier, offset)."""
    element = ET.SubElement(robot, "joint", name=name, type=kind)
    ET.SubElement(element, "parent", link=parent)
    ET.SubElement(element, "child", link=child)
    ET.SubElement(element, "origin", xyz=xyz, rpy="0 0 " + yaw)
    if kind == "revolute":
        ET.SubElement(element, "axis", xyz="1 0 0")
        lower, upper = limits
        ET.SubElement(element, "limit", lower=repr(lower), upper=repr(upper), effort=EFFORT, velocity=VELOCITY)
    if mimic:
        source, multiplier, offset = mimic
        ET.SubElement(element, "mimic", joint=source, multiplier=repr(multiplier), offset=repr(offset))


def image(limits, multiplier, offset):
    """The range of multiplier * q + offset for q in `limits`."""
    ends = sorted(multiplier * q + offset for q in limits)
    return tuple(0.0 if e == 0 else e for e in ends)  # no -0.0


def finger(robot, side, knuckle_joint, knuckle_xyz, knuckle_yaw, knuckle_mimic, inner_knuckle_xyz,
           inner_knuckle_yaw, inner_finger_mimic):
    """One side's links and joints, in Robotiq's layout; `*_mimic` None or (source, multiplier, offset)."""
    drive = (0.0, FINGER_UPPER)  # finger_joint's range, the root source of every mimic
    knuckle_range = drive if knuckle_mimic is None else image(drive, *knuckle_mimic[1:])
    link(robot, side + "_outer_knuckle", "outer_knuckle")
    joint(robot, knuckle_joint, "revolute", BASE, side + "_outer_knuckle", knuckle_xyz, knuckle_yaw,
          knuckle_range, knuckle_mimic)
    link(robot, side + "_outer_finger", "outer_finger")
    joint(robot, side + "_outer_finger_joint", "fixed", side + "_outer_knuckle", side + "_outer_finger",
          "0 0.0315 -0.0041")
    inner_knuckle_mimic = ("finger_joint", 1.0, 0.0)
    inner_knuckle_range = image(drive, *inner_knuckle_mimic[1:])
    link(robot, side + "_inner_knuckle", "inner_knuckle")
    joint(robot, side + "_inner_knuckle_joint", "revolute", BASE, side + "_inner_knuckle", inner_knuckle_xyz,
          inner_knuckle_yaw, inner_knuckle_range, inner_knuckle_mimic)
    source = {"finger_joint": drive, side + "_inner_knuckle_joint": inner_knuckle_range}[inner_finger_mimic[0]]
    link(robot, side + "_inner_finger", "inner_finger")
    joint(robot, side + "_inner_finger_joint", "revolute", side + "_outer_finger", side + "_inner_finger",
          "0 0.0061 0.0471", "0", image(source, *inner_finger_mimic[1:]), inner_finger_mimic)
    link(robot, side + "_inner_finger_pad", None)
    joint(robot, side + "_inner_finger_pad_joint", "fixed", side + "_inner_finger", side + "_inner_finger_pad",
          "0 -0.0220203446692936 0.03242")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else OUT
    ur5 = ET.parse(UR5).getroot()
    robot = ET.Element("robot", name="parallel_gripper")
    robot.append(ET.Comment(
        " Written by robots/tools/parallel_gripper.py from ../ur5/ur5.urdf (parameters and sources cited"
        " there) and Robotiq's 2F-85 description (ros-industrial/robotiq, sources in ../README.md). "))
    robot.append(ET.Comment(
        " finger_joint drives the fingers; the five other finger joints are <mimic>s, right_inner_finger_joint"
        " one of right_inner_knuckle_joint (multiplier -1, offset 0.05), itself one of finger_joint. "))
    # The tree for the fuzzers' seed run (fuzz/fuzz_entries.cpp, read_chain_directive).
    robot.append(ET.Comment(
        " chain root=base_link tip=left_inner_finger_pad branch=right_inner_finger_pad"
        " branch=left_inner_knuckle branch=right_inner_knuckle "))
    for element in ur5:
        if element.tag in ("link", "joint"):
            robot.append(element)
    if robot.find("link[@name='%s']" % FLANGE) is None:
        sys.exit("parallel_gripper.py: no link %s in %s" % (FLANGE, UR5))
    mount = ET.SubElement(robot, "joint", name="gripper_mount", type="fixed")
    ET.SubElement(mount, "parent", link=FLANGE)
    ET.SubElement(mount, "child", link=BASE)
    ET.SubElement(mount, "origin", xyz="0 0 0", rpy="0 0 0")
    link(robot, BASE, "base_link")
    finger(robot, "left", "finger_joint", "0 -0.0306011 0.054904", PI, None,
           "0 -0.0127 0.06142", PI, ("finger_joint", -1.0, 0.0))
    finger(robot, "right", "right_outer_knuckle_joint", "0 0.0306011 0.054904", "0", ("finger_joint", 1.0, 0.0),
           "0 0.0127 0.06142", "0", ("right_inner_knuckle_joint", -1.0, INNER_FINGER_OFFSET))
    write_urdf(robot, out)


if __name__ == "__main__":
    main()

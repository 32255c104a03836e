// Small URDFs written by the tests that need a robot of one joint.
#pragma once

#include <string>

namespace sweepgen::test {

// A one-joint robot: a massless base and a 1 kg arm, joined by `joint` (a URDF <joint> element).
inline std::string one_joint_robot(const std::string& joint) {
  return R"(<robot name="one_joint">
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/><origin xyz="0.2 0 0"/>
    <inertia ixx="0.01" iyy="0.02" izz="0.02" ixy="0" ixz="0" iyz="0"/></inertial></link>
  )" + joint + "\n</robot>";
}

// The arm turning freely about the base's z axis: set free (a floating base), the massless base
// cannot turn about z, so that coordinate is locked at every state (J1).
inline std::string massless_base_turning_arm() {
  return one_joint_robot(
      R"(<joint name="turn" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>)");
}

}  // namespace sweepgen::test

// A serial robot as plain data, and its URDF text: what `sweepgen family` writes
// (robots/family/README.md). Numbers are printed with 17 significant digits, so the loader
// reads back exactly the doubles the family computed.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace sweepgen::family {

using Vec3 = std::array<double, 3>;

struct LinkSpec {
  std::string name;
  bool has_inertial = true;  // false: no <inertial> element (a massless link)
  double mass = 0;
  Vec3 com{0, 0, 0};         // <inertial><origin xyz>, link frame
  Vec3 com_rpy{0, 0, 0};     // <inertial><origin rpy>: the inertial frame's orientation
  // ixx, ixy, ixz, iyy, iyz, izz about the COM, in the inertial frame.
  std::array<double, 6> inertia{0, 0, 0, 0, 0, 0};
};

enum class JointKind { revolute, continuous, prismatic };

struct JointSpec {
  std::string name;
  JointKind kind = JointKind::revolute;
  Vec3 xyz{0, 0, 0}, rpy{0, 0, 0};  // <origin>: pose of the child link in the parent link
  Vec3 axis{0, 0, 1};               // unit vector in the child link frame
  double lower = 0, upper = 0;      // ignored for continuous joints
  double effort = 0, velocity = 0;
};

// links[0] is the root; joint i connects links[i] (parent) to links[i + 1] (child).
struct RobotSpec {
  std::string name;
  std::vector<LinkSpec> links;
  std::vector<JointSpec> joints;
};

std::string urdf_text(const RobotSpec& robot);

}  // namespace sweepgen::family

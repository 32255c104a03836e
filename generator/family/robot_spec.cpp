#include "family/robot_spec.hpp"

#include <cstdio>
#include <stdexcept>

namespace sweepgen::family {
namespace {

std::string number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}
std::string triple(const Vec3& v) { return number(v[0]) + " " + number(v[1]) + " " + number(v[2]); }

const char* kind_name(JointKind kind) {
  switch (kind) {
    case JointKind::revolute: return "revolute";
    case JointKind::continuous: return "continuous";
    case JointKind::prismatic: return "prismatic";
  }
  return "";
}

}  // namespace

std::string urdf_text(const RobotSpec& robot) {
  if (robot.joints.size() + 1 != robot.links.size())
    throw std::logic_error("family robot " + robot.name + ": needs one more link than joints");
  std::string t = "<?xml version=\"1.0\"?>\n<!-- Written by `sweepgen family` (robots/family/README.md). -->\n";
  t += "<robot name=\"" + robot.name + "\">\n";
  for (const LinkSpec& l : robot.links) {
    if (!l.has_inertial) {
      t += "  <link name=\"" + l.name + "\"/>\n";
      continue;
    }
    const auto& I = l.inertia;
    t += "  <link name=\"" + l.name + "\">\n    <inertial>\n      <origin xyz=\"" + triple(l.com) + "\" rpy=\"" +
         triple(l.com_rpy) + "\"/>\n      <mass value=\"" + number(l.mass) + "\"/>\n      <inertia ixx=\"" +
         number(I[0]) + "\" ixy=\"" + number(I[1]) + "\" ixz=\"" + number(I[2]) + "\" iyy=\"" + number(I[3]) +
         "\" iyz=\"" + number(I[4]) + "\" izz=\"" + number(I[5]) + "\"/>\n    </inertial>\n  </link>\n";
  }
  for (std::size_t i = 0; i < robot.joints.size(); ++i) {
    const JointSpec& j = robot.joints[i];
    t += "  <joint name=\"" + j.name + "\" type=\"" + kind_name(j.kind) + "\">\n    <parent link=\"" +
         robot.links[i].name + "\"/>\n    <child link=\"" + robot.links[i + 1].name + "\"/>\n    <origin xyz=\"" +
         triple(j.xyz) + "\" rpy=\"" + triple(j.rpy) + "\"/>\n    <axis xyz=\"" + triple(j.axis) + "\"/>\n    <limit ";
    if (j.kind != JointKind::continuous) t += "lower=\"" + number(j.lower) + "\" upper=\"" + number(j.upper) + "\" ";
    t += "effort=\"" + number(j.effort) + "\" velocity=\"" + number(j.velocity) + "\"/>\n  </joint>\n";
  }
  return t + "</robot>\n";
}

}  // namespace sweepgen::family

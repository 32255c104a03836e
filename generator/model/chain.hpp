// The kinematic chain that every sweep runs on: bodies 0..N, body 0 the fixed base (the root
// link's frame), joint i moving body i relative to body i-1. Fixed joints are lumped: their
// child links' inertias are added to the moving body before them, and their frames stay
// addressable through `frames` (external forces, the tip/constraint frame).
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "spatial/spatial.hpp"

namespace sweepgen::model {

using Vec3 = spatial::Vec3<double>;
using Mat3 = spatial::Mat3<double>;
using Transform = spatial::Transform<double>;
using Inertia = spatial::Inertia<double>;

enum class JointType { revolute, prismatic };

struct Joint {
  std::string name;
  JointType type = JointType::revolute;
  bool continuous = false;
  Vec3 axis = Vec3::UnitZ();  // unit vector in the joint frame (= the child body frame)
  Transform tree_transform;   // X_T: motion transform from body i-1's frame to the joint frame
  double rotor_inertia = 0;   // d_i, armature reflected to the joint [kg m^2 or kg]
  double effort_limit = std::numeric_limits<double>::infinity();  // [N m or N]
  double velocity_limit = std::numeric_limits<double>::infinity();
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

struct Body {
  std::string link;                      // URDF link whose frame is the body frame
  std::vector<std::string> lumped_links; // links behind fixed joints merged into this body
  Inertia inertia;                       // M_i about the body frame origin, in the body frame
  double mass = 0;
};

// A URDF link's frame on the chain: rigidly attached to `body`, with `X` the motion
// transform from that body's frame to the link's frame.
struct Frame {
  std::size_t body = 0;
  Transform X;
};

struct Chain {
  std::string source;      // file the chain was read from, for messages
  std::string root_link;
  std::string tip_link;
  std::vector<Body> bodies;    // 0..N, bodies[0] is the base
  std::vector<Joint> joints;   // 0..N, joints[0] is unused (the base does not move)
  std::map<std::string, Frame> frames;  // every link on the chain, lumped ones included

  std::size_t dof() const { return bodies.size() - 1; }
  const Frame& tip() const { return frames.at(tip_link); }
  // Index (1..N) of the joint named `name`, or 0 if there is none.
  std::size_t joint_index(const std::string& name) const;
};

}  // namespace sweepgen::model

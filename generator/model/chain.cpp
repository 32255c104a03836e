#include "model/chain.hpp"

#include <Eigen/Geometry>
#include <sstream>
#include <stdexcept>

#include "model/inert_text.hpp"

namespace sweepgen::model {

std::size_t Chain::joint_index(const std::string& name) const {
  for (std::size_t i = 1; i < joints.size(); ++i)
    if (joints[i].name == name) return i;
  return 0;
}

const JointCoupling* coupling_of(const std::vector<JointCoupling>& couplings, std::size_t i) {
  for (const JointCoupling& coupling : couplings)
    if (coupling.joint == i) return &coupling;
  return nullptr;
}

const JointCoupling* Chain::coupling_of(std::size_t i) const { return model::coupling_of(couplings, i); }

std::string Chain::extent() const {
  std::string text = (branch_tips.empty() ? "the chain from " : "the tree from ") + quote_name(root_link) + " to " +
                     quote_name(tip_link);
  for (const std::string& tip : branch_tips) text += ", " + quote_name(tip);
  return text;
}

bool Chain::is_chain() const {
  for (std::size_t i = 1; i < parent.size(); ++i)
    if (parent[i] != i - 1) return false;
  return true;
}

Transform origin_transform(const Vec3& xyz, const Vec3& rpy) {
  const Mat3 R = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
                     .toRotationMatrix();
  Transform X;
  X.E = R.transpose();
  X.r = xyz;
  return X;
}

bool supports(const std::vector<std::size_t>& parent, std::size_t ancestor, std::size_t body) {
  while (body > ancestor) body = parent[body];
  return body == ancestor;
}

bool Chain::supports(std::size_t ancestor, std::size_t body) const { return model::supports(parent, ancestor, body); }

const std::vector<std::string>& floating_base_joint_names() {
  static const std::vector<std::string> names = {"floating_base_rx", "floating_base_ry", "floating_base_rz",
                                                 "floating_base_px", "floating_base_py", "floating_base_pz"};
  return names;
}

void add_floating_base(Chain& chain, const Inertia& root_inertia, double root_mass) {
  if (chain.bodies.size() != 1) throw std::logic_error("add_floating_base: the chain must hold only its base");
  chain.floating_base = true;
  chain.bodies[0].link = "world (where " + inert_text(chain.root_link) + " is now)";
  for (std::size_t k = 0; k < 6; ++k) {
    Joint joint;
    joint.name = floating_base_joint_names()[k];
    joint.type = k < 3 ? JointType::revolute : JointType::prismatic;
    joint.continuous = k < 3;
    joint.axis = Vec3::Unit(static_cast<Eigen::Index>(k % 3));
    joint.floating_base_coordinate = true;
    chain.joints.push_back(joint);
    const bool root = k == 5;
    chain.bodies.push_back(Body{chain.root_link, {}, root ? root_inertia : Inertia{}, root ? root_mass : 0.0});
    chain.parent.push_back(k);
  }
  chain.frames[chain.root_link] = Frame{6, Transform::identity()};
}

std::vector<std::string> lumping_summary(const Chain& chain) {
  std::vector<std::string> lines;
  const auto line = [&lines](auto&&... parts) {
    std::ostringstream text;
    (text << ... << parts);
    lines.push_back(text.str());
  };
  if (chain.floating_base)
    line("floating base: joints 1..6 (floating_base_rx .. floating_base_pz) are the coordinates [omega; v] of ",
         inert_text(chain.root_link), "'s twist in its own frame; bodies 1..5 are massless");
  // "M kg = link m kg + lumped a ma kg, b mb kg": a body's mass and where it comes from.
  const auto composition = [](const Body& body) {
    double own = body.mass;
    for (const auto& lumped : body.lumped_links) own -= lumped.mass;
    std::ostringstream text;
    text << body.mass << " kg = " << inert_text(body.link) << " " << own << " kg";
    for (std::size_t k = 0; k < body.lumped_links.size(); ++k) {
      const LumpedLink& lumped = body.lumped_links[k];
      text << (k == 0 ? " + lumped " : ", ") << inert_text(lumped.link) << " " << lumped.mass << " kg"
           << (lumped.locked_joint.empty() ? "" : " behind locked joint " + inert_text(lumped.locked_joint));
    }
    return text.str();
  };
  if (!chain.floating_base) line("base (fixed, moves nothing): ", composition(chain.bodies[0]));
  for (std::size_t i = 1 + (chain.floating_base ? 5 : 0); i <= chain.dof(); ++i)
    line("body ", i, " (joint ", inert_text(chain.joints[i].name), "): ", composition(chain.bodies[i]));
  for (const auto& locked : chain.locked_joints)
    line("locked joint ", inert_text(locked.name), " at ", locked.position, (locked.from_scene ? " (scene)" : " (default)"),
         ", carried by ", inert_text(chain.bodies[locked.body].link));
  for (const auto& link : chain.left_out) line("left out ", inert_text(link.link), " ", link.mass, " kg: ", link.reason);
  return lines;
}

}  // namespace sweepgen::model

// KDL's inverse dynamics of a whole URDF tree (kdl_parser's KDL::Tree, KDL's TreeIdSolver_RNE,
// every segment, fixed ones included), addressed by sweepgen's joints: an oracle that shares no
// code with sweepgen's loader. Moving joints sweepgen does not model (locked off-chain ones) are
// held at given positions, at rest.
//
// A floating base (F5): KDL has none, so the tree gets one here from KDL's own joints: six
// segments (RotX, RotY, RotZ, TransX, TransY, TransZ, named as sweepgen's coordinates, at q = 0)
// between a world root and the URDF's tree, the last carrying the root link's inertial read with
// urdfdom (kdl_parser drops a root link's inertia). As real joints their q̈ carries the
// velocity-product terms the free joint does not have: q̈_KDL = a − Σ_k Ẋ_k × S_k q̇_k with a the
// base's spatial acceleration (sweepgen's q̈_1..6) and Ẋ_k = Σ_{j≤k} S_j q̇_j; their τ is the
// wrench on the base.
//
// Conventions: TreeIdSolver_RNE takes f_ext per segment in that segment's frame (= the URDF link
// frame) as wrenches acting on the segment, as sweepgen's external forces and α; KDL's Wrench is
// (force, torque), sweepgen's Force [moment; force]; `gravity` is the gravity vector in the root
// frame, as SolverOptions::gravity.
#pragma once

#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "oracle/kdl_convention.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::test {

inline KDL::Wrench to_kdl(const spatial::Force<double>& f) {
  return KDL::Wrench(oracle::kdl_vector(f.force), oracle::kdl_vector(f.moment));
}

class KdlTreeDynamics {
 public:
  KdlTreeDynamics(const model::Chain& chain, const Eigen::Vector3d& gravity,
                  const std::map<std::string, double>& locks = {})
      : tree_(read_tree(chain)), gravity_(gravity), locked_(tree_.getNrOfJoints()),
        root_link_(chain.root_link), base_coordinates_(chain.base_coordinates()) {
    std::map<std::string, unsigned> index;  // KDL's joint index (q_nr) of every moving joint, by name
    for (const auto& [name, element] : tree_.getSegments()) {
      const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
      if (joint.getType() != KDL::Joint::None) index[joint.getName()] = GetTreeElementQNr(element);
    }
    for (const auto& [name, position] : locks) locked_(index.at(name)) = position;
    for (std::size_t i = 1; i <= chain.dof(); ++i) tree_index_.push_back(index.at(chain.joints[i].name));
  }

  const KDL::Tree& tree() const { return tree_; }

  // τ at sweepgen's joints = RNE of the whole tree at (q, q̇, q̈) with `wrenches` (per link, its
  // frame, acting on it). A floating base: `base_rotation` (world_R_base) turns gravity; q_1..6
  // are not read; a wrench on the root link acts on the last of the six segments.
  Eigen::VectorXd inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   KDL::WrenchMap wrenches, const Eigen::Matrix3d& base_rotation = Eigen::Matrix3d::Identity()) {
    KDL::JntArray kq = locked_, kqd(locked_.rows()), kqdd(locked_.rows()), torques(locked_.rows());
    const Eigen::VectorXd qdd_kdl = joint_accelerations(qd, qdd);
    for (std::size_t i = 0; i < tree_index_.size(); ++i) {
      kq(tree_index_[i]) = i < base_coordinates_ ? 0.0 : q[static_cast<Eigen::Index>(i)];
      kqd(tree_index_[i]) = qd[static_cast<Eigen::Index>(i)];
      kqdd(tree_index_[i]) = qdd_kdl[static_cast<Eigen::Index>(i)];
    }
    if (base_coordinates_ > 0 && wrenches.count(root_link_) != 0) {
      wrenches[floating_base_segment()] += wrenches.at(root_link_);
      wrenches.erase(root_link_);
    }
    const Eigen::Vector3d gravity = base_coordinates_ > 0 ? Eigen::Vector3d(base_rotation.transpose() * gravity_) : gravity_;
    KDL::TreeIdSolver_RNE inverse_dynamics(tree_, oracle::kdl_vector(gravity));
    if (inverse_dynamics.CartToJnt(kq, kqd, kqdd, wrenches, torques) < 0) throw std::runtime_error("KDL tree RNE failed");
    Eigen::VectorXd tau(static_cast<Eigen::Index>(tree_index_.size()));
    for (std::size_t i = 0; i < tree_index_.size(); ++i) tau[static_cast<Eigen::Index>(i)] = torques(tree_index_[i]);
    return tau;
  }

 private:
  static const std::string& floating_base_segment() { return model::floating_base_joint_names().back(); }

  // sweepgen's q̈ as KDL's joints take it: a floating base's six with their velocity-product terms
  // taken out (see the top of this file).
  Eigen::VectorXd joint_accelerations(const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) const {
    Eigen::VectorXd out = qdd;
    if (base_coordinates_ == 0) return out;
    spatial::Motion<double> velocity;
    for (int k = 0; k < 6; ++k) {
      spatial::Motion<double> joint;  // S_k q̇_k: unit axis k of [ω; v]
      (k < 3 ? joint.angular[k] : joint.linear[k - 3]) = qd[k];
      velocity.angular += joint.angular;
      velocity.linear += joint.linear;
      const spatial::Motion<double> bias = spatial::cross_motion(velocity, joint);
      out.head(3) -= bias.angular;
      out.segment(3, 3) -= bias.linear;
    }
    return out;
  }

  static KDL::Tree read_tree(const model::Chain& chain) {
    KDL::Tree urdf_tree;
    if (!kdl_parser::treeFromFile(chain.source, urdf_tree)) throw std::runtime_error("kdl_parser cannot read " + chain.source);
    if (!chain.floating_base) return urdf_tree;
    const urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(chain.source);
    if (!model) throw std::runtime_error("urdfdom cannot read " + chain.source);
    const auto inertial = model->getLink(chain.root_link)->inertial;
    KDL::RigidBodyInertia root_inertia = KDL::RigidBodyInertia::Zero();
    if (inertial) {  // as kdl_parser converts a link's inertial (tensor about the COM, in the inertial frame)
      const urdf::Pose& o = inertial->origin;
      const KDL::Frame origin(KDL::Rotation::Quaternion(o.rotation.x, o.rotation.y, o.rotation.z, o.rotation.w),
                              KDL::Vector(o.position.x, o.position.y, o.position.z));
      root_inertia = origin.M * KDL::RigidBodyInertia(inertial->mass, origin.M.Inverse(origin.p),
                                                      KDL::RotationalInertia(inertial->ixx, inertial->iyy, inertial->izz,
                                                                             inertial->ixy, inertial->ixz, inertial->iyz));
    }
    KDL::Tree tree("world");
    const KDL::Joint::JointType types[6] = {KDL::Joint::RotX, KDL::Joint::RotY, KDL::Joint::RotZ,
                                            KDL::Joint::TransX, KDL::Joint::TransY, KDL::Joint::TransZ};
    std::string parent = "world";
    for (int k = 0; k < 6; ++k) {
      const std::string& name = model::floating_base_joint_names()[static_cast<std::size_t>(k)];
      tree.addSegment(KDL::Segment(name, KDL::Joint(name, types[k]), KDL::Frame::Identity(),
                                   k == 5 ? root_inertia : KDL::RigidBodyInertia::Zero()),
                      parent);
      parent = name;
    }
    if (!tree.addTree(urdf_tree, parent)) throw std::runtime_error("cannot hang the URDF's tree on the floating base");
    return tree;
  }

  KDL::Tree tree_;
  Eigen::Vector3d gravity_;
  KDL::JntArray locked_;              // every tree joint: the locks, 0 elsewhere
  std::string root_link_;
  std::size_t base_coordinates_ = 0;
  std::vector<unsigned> tree_index_;  // KDL's index of sweepgen's joint i + 1
};

}  // namespace sweepgen::test

// KDL's inverse dynamics of a whole URDF tree (kdl_parser's KDL::Tree, KDL's TreeIdSolver_RNE,
// every segment, fixed ones included), addressed by sweepgen's joints: an oracle that shares no
// code with sweepgen's loader. Moving joints sweepgen does not model (locked off-chain ones) are
// held at given positions, at rest.
//
// Conventions: TreeIdSolver_RNE takes f_ext per segment in that segment's frame (= the URDF link
// frame) as wrenches acting on the segment, as sweepgen's external forces and α; KDL's Wrench is
// (force, torque), sweepgen's Force [moment; force]; `gravity` is the gravity vector in the root
// frame, as SolverOptions::gravity.
#pragma once

#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "report/kdl_convention.hpp"

namespace sweepgen::test {

inline KDL::Wrench to_kdl(const spatial::Force<double>& f) {
  return KDL::Wrench(report::kdl_vector(f.force), report::kdl_vector(f.moment));
}

class KdlTreeDynamics {
 public:
  KdlTreeDynamics(const model::Chain& chain, const Eigen::Vector3d& gravity,
                  const std::map<std::string, double>& locks = {})
      : tree_(read_tree(chain.source)), inverse_dynamics_(tree_, report::kdl_vector(gravity)), locked_(tree_.getNrOfJoints()) {
    std::map<std::string, unsigned> index;  // KDL's joint index (q_nr) of every moving joint, by name
    for (const auto& [name, element] : tree_.getSegments()) {
      const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
      if (joint.getType() != KDL::Joint::None) index[joint.getName()] = GetTreeElementQNr(element);
    }
    for (const auto& [name, position] : locks) locked_(index.at(name)) = position;
    for (std::size_t i = 1; i <= chain.dof(); ++i) tree_index_.push_back(index.at(chain.joints[i].name));
  }
  KdlTreeDynamics(const KdlTreeDynamics&) = delete;  // the solver holds a reference to tree_

  const KDL::Tree& tree() const { return tree_; }

  // τ at sweepgen's joints = RNE of the whole tree at (q, q̇, q̈) with `wrenches` (per link, its
  // frame, acting on it).
  Eigen::VectorXd inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   const KDL::WrenchMap& wrenches) {
    KDL::JntArray kq = locked_, kqd(locked_.rows()), kqdd(locked_.rows()), torques(locked_.rows());
    for (std::size_t i = 0; i < tree_index_.size(); ++i) {
      kq(tree_index_[i]) = q[static_cast<Eigen::Index>(i)];
      kqd(tree_index_[i]) = qd[static_cast<Eigen::Index>(i)];
      kqdd(tree_index_[i]) = qdd[static_cast<Eigen::Index>(i)];
    }
    if (inverse_dynamics_.CartToJnt(kq, kqd, kqdd, wrenches, torques) < 0) throw std::runtime_error("KDL tree RNE failed");
    Eigen::VectorXd tau(static_cast<Eigen::Index>(tree_index_.size()));
    for (std::size_t i = 0; i < tree_index_.size(); ++i) tau[static_cast<Eigen::Index>(i)] = torques(tree_index_[i]);
    return tau;
  }

 private:
  static KDL::Tree read_tree(const std::string& urdf) {
    KDL::Tree tree;
    if (!kdl_parser::treeFromFile(urdf, tree)) throw std::runtime_error("kdl_parser cannot read " + urdf);
    return tree;
  }

  KDL::Tree tree_;
  KDL::TreeIdSolver_RNE inverse_dynamics_;
  KDL::JntArray locked_;              // every tree joint: the locks, 0 elsewhere
  std::vector<unsigned> tree_index_;  // KDL's index of sweepgen's joint i + 1
};

}  // namespace sweepgen::test

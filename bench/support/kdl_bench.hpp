// KDL 1.5.1's ChainHdSolver_Vereshchagin on a bundled robot (kdl_targets()), on the random
// problems of that robot's Nc = 6 scene (bench/support/inputs.hpp): the same q, qd and feed-forward
// torque (the sum of the scene's torque instances), each external-force instance on its link's
// segment, the first Nc of the scene's directions alpha (random unit directions, or the scene's
// fixed ones) and setpoints beta. KDL's chain ends at the robot's last moving link (its solver
// crashes on chains with fixed joints, so not up to the scenes' tips); loads on links behind it go
// to its last segment. The wrenches and directions are passed to KDL as numbers without the frame
// translation of tests/test_reference_kdl.cpp (KDL wants them in base orientation): the cost of
// the solver does not depend on which frame the random numbers were meant in, and external forces
// are always processed by KDL (a zero wrench costs the same).
#pragma once

#include <kdl/chain.hpp>
#include <kdl/chainhdsolver_vereshchagin.hpp>
#include <kdl/tree.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/inputs.hpp"

namespace sweepgen::bench {

// The robots KDL is measured on: scene (Nc = 6), root and last moving link.
struct KdlTarget {
  std::string robot, scene, root, last_moving_link;
};
inline const std::vector<KdlTarget>& kdl_targets() {
  static const std::vector<KdlTarget> targets = {
      {"panda", "robots/panda/panda_nc6.yaml", "panda_link0", "panda_link7"},
      {"iiwa14", "robots/iiwa14/iiwa14_nc6.yaml", "lbr_iiwa_link_0", "lbr_iiwa_link_7"},
      {"ur5", "robots/ur5/ur5_nc6.yaml", "base_link", "wrist_3_link"},
  };
  return targets;
}

class KdlBench {
 public:
  KdlBench(const std::string& robot, unsigned nc) : nc_(nc) {
    const auto target = std::find_if(kdl_targets().begin(), kdl_targets().end(),
                                     [&](const KdlTarget& t) { return t.robot == robot; });
    if (target == kdl_targets().end()) throw std::runtime_error("KDL bench: no robot " + robot);
    const SceneInputs s = make_inputs(std::string(SWEEPGEN_SOURCE_DIR) + "/" + target->scene);
    KDL::Tree tree;
    if (!kdl_parser::treeFromFile(s.scene.chain.urdf, tree))
      throw std::runtime_error("kdl_parser cannot read " + s.scene.chain.urdf);
    if (!tree.getChain(target->root, target->last_moving_link, chain_))
      throw std::runtime_error("KDL has no chain " + target->root + " -> " + target->last_moving_link);
    const unsigned n = chain_.getNrOfJoints();
    if (s.dof != n || s.constraints != 6 || nc > 6) throw std::logic_error(target->scene + " does not match the KDL chain");
    // Root acceleration: minus gravity (tests/test_reference_kdl.cpp).
    const Eigen::Vector3d g = s.scene.gravity;
    solver_ = std::make_unique<KDL::ChainHdSolver_Vereshchagin>(chain_, KDL::Twist(KDL::Vector(-g.x(), -g.y(), -g.z()), KDL::Vector::Zero()), nc);
    std::vector<unsigned> load_segment;  // per external-force instance
    for (const auto& ext : s.scene.layout.external_forces) {
      unsigned segment = chain_.getNrOfSegments() - 1;
      for (unsigned k = 0; k < chain_.getNrOfSegments(); ++k)
        if (chain_.getSegment(k).getName() == ext.link) segment = k;
      load_segment.push_back(segment);
    }
    for (const auto& in : s.problems) {
      Problem p{KDL::JntArray(n), KDL::JntArray(n), KDL::JntArray(n), KDL::JntArray(nc), KDL::Jacobian(nc),
                KDL::Wrenches(chain_.getNrOfSegments(), KDL::Wrench::Zero())};
      p.q.data = in.q;
      p.qd.data = in.qd;
      for (const auto& tau : in.torques) p.tau.data += tau;
      for (std::size_t e = 0; e < load_segment.size(); ++e) {  // [moment; force] -> Wrench(force, torque)
        const auto& w = in.wrenches[e];
        p.f_ext[load_segment[e]] = KDL::Wrench(KDL::Vector(w.force.x(), w.force.y(), w.force.z()),
                                               KDL::Vector(w.moment.x(), w.moment.y(), w.moment.z()));
      }
      for (unsigned k = 0; k < nc; ++k)
        for (int r = 0; r < 3; ++r) {
          p.alfa(r, k) = in.alpha[k].force[r];  // KDL rows: force, then moment
          p.alfa(3 + r, k) = in.alpha[k].moment[r];
        }
      for (unsigned k = 0; k < nc; ++k) p.beta(k) = in.beta[k];
      problems_.push_back(std::move(p));
    }
    qdd_ = KDL::JntArray(n);
    torques_ = KDL::JntArray(n);
  }
  std::size_t count() const { return problems_.size(); }
  unsigned constraints() const { return nc_; }

  // One CartToJnt call on problem i; returns qdd(0) (throws on a KDL error).
  double call(std::size_t i) {
    Problem& p = problems_[i];
    const int status = solver_->CartToJnt(p.q, p.qd, qdd_, p.alfa, p.beta, p.f_ext, p.tau, torques_);
    if (status != 0) throw std::runtime_error("KDL CartToJnt failed: " + std::to_string(status));
    return qdd_(0);
  }

 private:
  struct Problem {
    KDL::JntArray q, qd, tau, beta;
    KDL::Jacobian alfa;
    KDL::Wrenches f_ext;
  };
  unsigned nc_;
  KDL::Chain chain_;
  std::unique_ptr<KDL::ChainHdSolver_Vereshchagin> solver_;
  std::vector<Problem> problems_;
  KDL::JntArray qdd_, torques_;
};

// What the benchmarks measure: the Panda at Nc = 0, 3, 6; the others at Nc = 6.
inline std::vector<std::pair<std::string, unsigned>> kdl_cases() {
  return {{"panda", 0}, {"panda", 3}, {"panda", 6}, {"iiwa14", 6}, {"ur5", 6}};
}

}  // namespace sweepgen::bench

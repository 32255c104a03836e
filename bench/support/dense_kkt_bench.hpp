// The dense KKT solve of `sweepgen report`'s "dense KKT" row (generator/report/dense_dynamics.hpp:
// M(q) by inverse dynamics column by column, the constraint Jacobian of each direction's link,
// one LDLᵀ of the KKT system) on a scene's prepared inputs: what sweepgen's recursion is
// measured against on trees and floating bases (issue 16: >= 10x fewer instructions).
#pragma once

#include <string>
#include <vector>

#include "report/dense_dynamics.hpp"
#include "support/inputs.hpp"

namespace sweepgen::bench {

class DenseKktBench {
 public:
  using Dynamics = report::DenseDynamics<double>;

  explicit DenseKktBench(const std::string& scene_path)
      : inputs_(make_inputs(scene_path)), links_(solver::direction_links(inputs_.scene.layout, inputs_.chain)) {
    const solver::DriverLayout& layout = inputs_.scene.layout;
    for (const auto& p : inputs_.problems) {
      // One oracle per state: a floating base's gravity is turned by the state's base rotation.
      dynamics_.emplace_back(inputs_.chain, inputs_.chain.floating_base
                                                ? model::Vec3(p.base_rotation.transpose() * inputs_.scene.gravity)
                                                : inputs_.scene.gravity);
      Eigen::VectorXd tau = Eigen::VectorXd::Zero(p.q.size());
      for (const auto& t : p.torques) tau += t;
      tau_.push_back(tau);
      std::vector<Dynamics::ExternalWrench> wrenches;
      for (std::size_t e = 0; e < p.wrenches.size(); ++e) {
        Dynamics::Six w;
        w << p.wrenches[e].moment, p.wrenches[e].force;
        wrenches.push_back({layout.external_forces[e].link, w});
      }
      wrenches_.push_back(wrenches);
      Dynamics::Mat alpha(6, static_cast<Eigen::Index>(layout.constraints));
      for (std::size_t k = 0; k < layout.constraints; ++k)
        alpha.col(static_cast<Eigen::Index>(k)) << p.alpha[k].moment, p.alpha[k].force;
      alpha_.push_back(alpha);
    }
  }
  std::size_t count() const { return inputs_.problems.size(); }

  // One dense solve of problem i; returns q̈_0 (a checksum term).
  double call(std::size_t i) const {
    const auto& p = inputs_.problems[i];
    return dynamics_[i].solve_kkt(p.q, p.qd, tau_[i], wrenches_[i], links_, alpha_[i], p.beta).qdd[0];
  }

 private:
  SceneInputs inputs_;
  std::vector<std::string> links_;
  std::vector<Dynamics> dynamics_;
  std::vector<Eigen::VectorXd> tau_;
  std::vector<std::vector<Dynamics::ExternalWrench>> wrenches_;
  std::vector<Dynamics::Mat> alpha_;
};

// The scenes whose dense KKT solve is counted: the trees and floating bases, and the Panda's
// 6-D tip scene as the chain's point of comparison.
inline bool counts_dense_kkt(const SceneInputs& inputs) {
  return !inputs.chain.is_chain() || inputs.chain.floating_base || inputs.scene.solver == "panda_nc6";
}

}  // namespace sweepgen::bench

// ReferenceSolver<double> (generator/solver/reference_solver.hpp, the generic templated
// solver) on a scene's prepared inputs: the same kStates random problems as the generated code.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "support/inputs.hpp"

namespace sweepgen::bench {

class ReferenceBench {
 public:
  explicit ReferenceBench(const std::string& scene_path)
      : inputs_(make_inputs(scene_path)) {
    for (std::size_t i = 0; i < count(); ++i) {
      // One solver per state, so that re-solves can cycle through decomposed states.
      solvers_.push_back(std::make_unique<solver::ReferenceSolver<double>>(inputs_.chain, inputs_.scene.layout,
                                                                           inputs_.scene.solver_options()));
      new_beta_.emplace_back(Eigen::Map<const Eigen::VectorXd>(inputs_.new_beta[i].data(),
                                                               static_cast<Eigen::Index>(inputs_.new_beta[i].size())));
    }
  }
  std::size_t count() const { return inputs_.problems.size(); }
  const SceneInputs& inputs() const { return inputs_; }

  // outward + drivers + decompose + solve of problem i (one solver object for all).
  const solver::Solution<double>& full(std::size_t i, solver::Policy policy) {
    return solvers_[0]->run(inputs_.problems[i], policy);  // same sizes: copies, no allocation
  }
  // Runs outward + decompose (and a solve) for every problem on its own solver (before re-solves).
  void decompose_all() {
    for (std::size_t i = 0; i < count(); ++i) solvers_[i]->run(inputs_.problems[i], solver::Policy::original);
  }
  // solve only, with other setpoints, on problem i's decomposed state (after decompose_all()).
  const solver::Solution<double>& resolve(std::size_t i, solver::Policy policy) {
    return solvers_[i]->solve(policy, new_beta_[i]);
  }

 private:
  SceneInputs inputs_;
  std::vector<std::unique_ptr<solver::ReferenceSolver<double>>> solvers_;
  std::vector<solver::ConstraintVector<double>> new_beta_;
};

}  // namespace sweepgen::bench

// The dense KKT solve of `sweepgen report`'s "dense KKT" row (generator/oracle/dense_dynamics.hpp:
// M(q) by inverse dynamics column by column, the constraint Jacobian of each direction's link,
// one LDLᵀ of the KKT system) on a scene's prepared inputs: what sweepgen's recursion is
// measured against on trees and floating bases (bench/README.md, "KDL and the dense KKT solve").
#pragma once

#include <string>
#include <vector>

#include "oracle/dense_kkt.hpp"
#include "support/inputs.hpp"

namespace sweepgen::bench {

class DenseKktBench {
 public:
  explicit DenseKktBench(const std::string& scene_path) : inputs_(make_inputs(scene_path)) {
    for (const auto& p : inputs_.problems) posed_.emplace_back(inputs_.scene, inputs_.chain, p);
  }
  std::size_t count() const { return inputs_.problems.size(); }

  // One dense solve of problem i; returns q̈_0 (a checksum term).
  double call(std::size_t i) const { return posed_[i].solve(inputs_.problems[i]).qdd[0]; }

 private:
  SceneInputs inputs_;
  std::vector<oracle::DenseKktProblem> posed_;
};

// The scenes whose dense KKT solve is counted: the trees and floating bases, and the Panda's
// 6-D tip scene as the chain's point of comparison.
inline bool counts_dense_kkt(const SceneInputs& inputs) {
  return !inputs.chain.is_chain() || inputs.chain.floating_base || inputs.scene.solver == "panda_nc6";
}

}  // namespace sweepgen::bench

// How far a model's rotations (joints' tree transforms, links' frames, the sets' offsets), held in
// double, are from orthogonal, max |E^T E − 1| in binary128: where they are not exactly, the solver
// (E^T as the inverse of a composed transform) and the dense oracle (poses composed from the base)
// treat a slightly different mechanism, by that much (the binary128 comparisons' δ).
#pragma once

#include <algorithm>
#include <cmath>

#include "model/chain.hpp"
#include "solver/drivers.hpp"
#include "solver/quad_scalar.hpp"

namespace sweepgen::test {

inline double non_orthogonality(const model::Chain& chain, const solver::DriverLayout& layout) {
  using Q = solver::Quad;
  double worst = 0;
  const auto judge = [&](const model::Mat3& E) {
    const Eigen::Matrix<Q, 3, 3> e = E.cast<Q>();
    const Eigen::Matrix<Q, 3, 3> gap = e.transpose() * e - Eigen::Matrix<Q, 3, 3>::Identity();
    for (int i = 0; i < 9; ++i) worst = std::max(worst, std::abs(static_cast<double>(gap(i / 3, i % 3))));
  };
  for (std::size_t i = 1; i <= chain.dof(); ++i) judge(chain.joints[i].tree_transform.E);
  for (const auto& [name, frame] : chain.frames) judge(frame.X.E);
  for (const solver::ConstraintSet& set : layout.sets) judge(set.at.E), judge(set.relative_at.E);
  return worst;
}

}  // namespace sweepgen::test

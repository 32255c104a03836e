#include "solver/flat_layout.hpp"

#include <stdexcept>

namespace sweepgen::solver {

std::vector<double> generated_positions(const JointVector<double>& q, const spatial::Mat3<double>& base_rotation,
                                        bool floating_base) {
  if (!floating_base) return {q.data(), q.data() + q.size()};
  std::vector<double> generated;
  for (Eigen::Index r = 0; r < 3; ++r)
    for (Eigen::Index c = 0; c < 3; ++c) generated.push_back(base_rotation(r, c));  // row-major
  generated.insert(generated.end(), q.data() + 6, q.data() + q.size());
  return generated;
}

std::vector<double> flat_input(const SolveInputs<double>& inputs, const FlatLayout& layout) {
  std::vector<double> flat;
  flat.reserve(layout.in_size());
  const auto append = [&flat](const auto& v) { flat.insert(flat.end(), v.data(), v.data() + v.size()); };
  const std::vector<double> q = generated_positions(inputs.q, inputs.base_rotation, layout.floating_base);
  flat.insert(flat.end(), q.begin(), q.end());
  append(inputs.qd);
  for (const auto& tau : inputs.torques) append(tau);
  for (const auto& w : inputs.wrenches) {
    append(w.moment);
    append(w.force);
  }
  for (std::size_t k : layout.input_directions) {
    append(inputs.alpha.at(k).moment);
    append(inputs.alpha.at(k).force);
  }
  append(inputs.beta);
  if (flat.size() != layout.in_size())
    throw std::logic_error("flat_input: " + std::to_string(flat.size()) + " values for a layout of " +
                           std::to_string(layout.in_size()));
  return flat;
}

}  // namespace sweepgen::solver

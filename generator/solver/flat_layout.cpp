#include "solver/flat_layout.hpp"

#include <stdexcept>

namespace sweepgen::solver {

std::vector<double> flat_input(const SolveInputs<double>& inputs, const FlatLayout& layout) {
  std::vector<double> flat;
  flat.reserve(layout.in_size());
  const auto append = [&flat](const auto& v) { flat.insert(flat.end(), v.data(), v.data() + v.size()); };
  append(inputs.q);
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

// Graph::evaluate: runs the recorded expressions in any floating-point type.
#pragma once

#include <algorithm>
#include <cmath>

#include "solver/scalar_ops.hpp"

namespace sweepgen::symbolic {

template <class Scalar>
std::vector<Scalar> Graph::evaluate(const std::vector<Scalar>& input_values) const {
  std::vector<Scalar> v(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    const auto a = [&](int k) { return v[n.args[k]]; };
    switch (n.op) {
      case Op::constant: v[i] = Scalar(n.value); break;
      case Op::input: v[i] = input_values.at(n.input); break;
      case Op::add: v[i] = a(0) + a(1); break;
      case Op::sub: v[i] = a(0) - a(1); break;
      case Op::mul: v[i] = a(0) * a(1); break;
      case Op::div: v[i] = a(0) / a(1); break;
      case Op::neg: v[i] = -a(0); break;
      case Op::sin: v[i] = std::sin(a(0)); break;
      case Op::cos: v[i] = std::cos(a(0)); break;
      case Op::abs: v[i] = std::abs(a(0)); break;
      case Op::sqrt: v[i] = std::sqrt(a(0)); break;
      case Op::atan2: v[i] = std::atan2(a(0), a(1)); break;
      case Op::min: v[i] = std::min(a(0), a(1)); break;
      case Op::max: v[i] = std::max(a(0), a(1)); break;
      case Op::select_greater:
      case Op::select_path: v[i] = a(0) > a(1) ? a(2) : a(3); break;
      case Op::equilibration_scale: v[i] = solver::equilibration_scale(a(0)); break;
    }
  }
  return v;
}

}  // namespace sweepgen::symbolic

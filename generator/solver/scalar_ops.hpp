// The few data-dependent operations the sweeps need, written branch-free so that a symbolic
// scalar can trace them (it overloads these names; calls are unqualified so ADL finds them).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace sweepgen::solver {

// a > b ? if_greater : otherwise
template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar select_greater(const Scalar& a, const Scalar& b, const Scalar& if_greater, const Scalar& otherwise) {
  return a > b ? if_greater : otherwise;
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar minimum(const Scalar& a, const Scalar& b) {
  return std::min(a, b);
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar maximum(const Scalar& a, const Scalar& b) {
  return std::max(a, b);
}

template <class Scalar, std::enable_if_t<std::is_floating_point_v<Scalar>, int> = 0>
Scalar abs_value(const Scalar& a) {
  return std::abs(a);
}

// x clamped to [-limit, limit].
template <class Scalar>
Scalar clamp_symmetric(const Scalar& x, const Scalar& limit) {
  return minimum(maximum(x, Scalar(-limit)), limit);
}

}  // namespace sweepgen::solver

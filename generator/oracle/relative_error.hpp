// The error measure of every comparison against an answer, in the report, the stability
// suite and the tests: ‖a − b‖∞ / max(1, ‖b‖∞) of a result a against the answer b, computed in
// Scalar (absolute where the answer is below 1, relative above). A result holding NaN or Inf,
// or of another length than the answer, is infinitely wrong. a and b: std::vector or Eigen
// vector expressions of any floating-point type Scalar can be built from.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace sweepgen::oracle {
namespace detail {

template <class Scalar, class V>
Eigen::Matrix<Scalar, Eigen::Dynamic, 1> as_column(const V& v) {
  if constexpr (std::is_base_of_v<Eigen::EigenBase<V>, V>) {
    return v.eval().template cast<Scalar>();
  } else {
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1> column(static_cast<Eigen::Index>(v.size()));
    for (Eigen::Index i = 0; i < column.size(); ++i) column[i] = Scalar(v[static_cast<std::size_t>(i)]);
    return column;
  }
}

}  // namespace detail

template <class Scalar = double, class A, class B>
Scalar relative_error(const A& result, const B& answer) {
  using std::abs;
  using std::isfinite;
  const auto a = detail::as_column<Scalar>(result);
  const auto b = detail::as_column<Scalar>(answer);
  if (a.size() != b.size()) return std::numeric_limits<Scalar>::infinity();
  Scalar diff = 0, scale = 1;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    if (!isfinite(a[i])) return std::numeric_limits<Scalar>::infinity();
    diff = std::max(diff, Scalar(abs(a[i] - b[i])));
    scale = std::max(scale, Scalar(abs(b[i])));
  }
  return diff / scale;
}

}  // namespace sweepgen::oracle

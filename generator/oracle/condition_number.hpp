// Condition numbers of the constraint-space matrix E^A_cstr,0 (docs/stability.md, "Errors and
// condition numbers"), computed in the matrix's own scalar: binary128 measures them up to ~1e30,
// double up to ~1e15.
#pragma once

#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace sweepgen::oracle {

// cond_2(E): 1 for an empty matrix, infinite for a singular one.
template <class Derived>
double condition_number(const Eigen::MatrixBase<Derived>& E) {
  using Scalar = typename Derived::Scalar;
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  if (E.rows() == 0) return 1;
  const Eigen::Matrix<Scalar, Eigen::Dynamic, 1> sv = Eigen::JacobiSVD<Matrix>(Matrix(E)).singularValues();
  return sv(sv.size() - 1) > Scalar(0) ? static_cast<double>(sv(0) / sv(sv.size() - 1))
                                        : std::numeric_limits<double>::infinity();
}

// cond_s(E) = cond_2 of diag(E)^-1/2 E diag(E)^-1/2: the condition the equilibrated, pivoted
// factorisation sees, invariant under the units of each direction; infinite when a diagonal entry
// is not positive.
template <class Derived>
double scaled_condition_number(const Eigen::MatrixBase<Derived>& E) {
  using Scalar = typename Derived::Scalar;
  using std::sqrt;
  Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic> S = E;
  for (Eigen::Index k = 0; k < E.rows(); ++k)
    if (!(E(k, k) > Scalar(0))) return std::numeric_limits<double>::infinity();
  for (Eigen::Index r = 0; r < E.rows(); ++r)
    for (Eigen::Index c = 0; c < E.cols(); ++c) S(r, c) = E(r, c) / sqrt(E(r, r) * E(c, c));
  return condition_number(S);
}

}  // namespace sweepgen::oracle

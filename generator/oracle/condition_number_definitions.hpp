// The condition numbers of oracle/condition_number.hpp, included only by the files that instantiate
// them: condition_number_quad.cpp (binary128 and long double: the report, the tests) and
// condition_number_double.cpp (double: the tests). Apart, the two compile side by side, and the
// report's build compiles only the first.
#pragma once

#include "oracle/condition_number.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace sweepgen::oracle {

// E is square (E^A_cstr,0, M): the SVD without a QR preconditioner, which Eigen applies only to a
// matrix with more rows than columns or more columns than rows, so the same singular values bit for
// bit (6 000 random square matrices, double and long double) and a tenth of the compile
// (condition_number_double.cpp 20.4 -> 3.5 s of g++ -O2).
template <class Scalar>
double condition_number_of(const DenseMatrix<Scalar>& E) {
  if (E.rows() != E.cols()) throw std::invalid_argument("condition_number_of: E is not square");
  if (E.rows() == 0) return 1;
  const Eigen::Matrix<Scalar, Eigen::Dynamic, 1> sv =
      Eigen::JacobiSVD<DenseMatrix<Scalar>, Eigen::NoQRPreconditioner>(E).singularValues();
  return sv(sv.size() - 1) > Scalar(0) ? static_cast<double>(sv(0) / sv(sv.size() - 1))
                                        : std::numeric_limits<double>::infinity();
}

template <class Scalar>
double scaled_condition_number_of(const DenseMatrix<Scalar>& E) {
  using std::sqrt;
  DenseMatrix<Scalar> S = E;
  for (Eigen::Index k = 0; k < E.rows(); ++k)
    if (!(E(k, k) > Scalar(0))) return std::numeric_limits<double>::infinity();
  for (Eigen::Index r = 0; r < E.rows(); ++r)
    for (Eigen::Index c = 0; c < E.cols(); ++c) S(r, c) = E(r, c) / sqrt(E(r, r) * E(c, c));
  return condition_number_of<Scalar>(S);
}

}  // namespace sweepgen::oracle

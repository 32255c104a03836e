// Condition numbers of the constraint-space matrix E^A_cstr,0 (docs/stability.md, "Errors and
// condition numbers"), computed in the matrix's own scalar: binary128 measures them up to ~1e30,
// double up to ~1e15. The SVD behind them is compiled once per scalar the report and the tests
// use: binary128 (solver::Quad) and long double in condition_number_quad.cpp, double in
// condition_number_double.cpp.
#pragma once

#include <Eigen/Core>

namespace sweepgen::oracle {

template <class Scalar>
using DenseMatrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;

// cond_2(E) of a square E (std::invalid_argument otherwise): 1 for an empty matrix, infinite for a
// singular one.
template <class Scalar>
double condition_number_of(const DenseMatrix<Scalar>& E);

// cond_s(E) = cond_2 of diag(E)^-1/2 E diag(E)^-1/2: the condition the equilibrated, pivoted
// factorisation sees, invariant under the units of each direction; infinite when a diagonal entry
// is not positive.
template <class Scalar>
double scaled_condition_number_of(const DenseMatrix<Scalar>& E);

// The same for any matrix expression, evaluated into a dense matrix of its scalar.
template <class Derived>
double condition_number(const Eigen::MatrixBase<Derived>& E) {
  return condition_number_of<typename Derived::Scalar>(E);
}
template <class Derived>
double scaled_condition_number(const Eigen::MatrixBase<Derived>& E) {
  return scaled_condition_number_of<typename Derived::Scalar>(E);
}

}  // namespace sweepgen::oracle

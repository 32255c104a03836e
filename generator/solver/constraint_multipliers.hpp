// ν = (E^A_cstr,0)^-1 r  for the symmetric positive semi-definite Nc x Nc matrix E^A_cstr,0
// (docs/derivation.md, "Singular constraints").
//
// Policy: LDL^T without pivoting, branch-free. A pivot d_k <= tol * max_j E_jj is treated
// as zero: its multiplier is set to 0 and its column of L to 0, so that direction of the
// constraint is not enforced and no NaN/Inf can arise. The tolerance is relative, hence
// invariant under any scaling of the robot's units. The number of dropped pivots is returned
// (the caller raises status_constraint_rank_deficient). For a PSD matrix a vanishing pivot
// implies a vanishing column below it, so the remaining directions are solved exactly.
#pragma once

#include "solver/scalar_ops.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

template <class Scalar>
ConstraintVector<Scalar> solve_constraint_multipliers(const ConstraintMatrix<Scalar>& E,
                                                      const ConstraintVector<Scalar>& rhs, const Scalar& tolerance,
                                                      Scalar& dropped_pivots) {
  const Eigen::Index nc = rhs.size();
  dropped_pivots = Scalar(0);
  if (nc == 0) return ConstraintVector<Scalar>(0);

  Scalar scale = E(0, 0);
  for (Eigen::Index k = 1; k < nc; ++k) scale = maximum(scale, E(k, k));
  const Scalar threshold = tolerance * scale;

  // E = L diag(pivot) L^T; a dropped pivot has pivot = 0, inverse_pivot = 0 and a zero column of L.
  ConstraintMatrix<Scalar> L = ConstraintMatrix<Scalar>::Identity(nc, nc);
  ConstraintVector<Scalar> pivot(nc), inverse_pivot(nc);
  for (Eigen::Index k = 0; k < nc; ++k) {
    Scalar d = E(k, k);
    for (Eigen::Index j = 0; j < k; ++j) d -= L(k, j) * L(k, j) * pivot[j];
    const Scalar kept = select_greater(d, threshold, Scalar(1), Scalar(0));
    dropped_pivots += Scalar(1) - kept;
    pivot[k] = kept * d;
    inverse_pivot[k] = kept / select_greater(d, threshold, d, Scalar(1));
    for (Eigen::Index i = k + 1; i < nc; ++i) {
      Scalar e = E(i, k);
      for (Eigen::Index j = 0; j < k; ++j) e -= L(i, j) * L(k, j) * pivot[j];
      L(i, k) = e * inverse_pivot[k];
    }
  }
  // Forward substitution L y = rhs, scaling y_k = y_k / d_k, back substitution L^T ν = y.
  ConstraintVector<Scalar> y = rhs;
  for (Eigen::Index k = 0; k < nc; ++k)
    for (Eigen::Index j = 0; j < k; ++j) y[k] -= L(k, j) * y[j];
  for (Eigen::Index k = 0; k < nc; ++k) y[k] *= inverse_pivot[k];
  for (Eigen::Index k = nc - 1; k >= 0; --k)
    for (Eigen::Index j = k + 1; j < nc; ++j) y[k] -= L(j, k) * y[j];
  return y;
}

}  // namespace sweepgen::solver

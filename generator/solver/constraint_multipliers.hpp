// ν = (E^A_cstr,0)^-1 r  for the symmetric positive semi-definite Nc x Nc matrix E^A_cstr,0
// (docs/derivation.md, "Singular constraints").
//
// Policy: LDL^T with diagonal (symmetric) pivoting, branch-free. Step k first moves the
// largest remaining diagonal entry of the Schur complement to position k (a tournament of
// conditional swaps), then takes it as the pivot. A pivot d_k <= tol * max_j E_jj is treated
// as zero: its multiplier is set to 0 and its column of L to 0, so that direction of the
// constraint is not enforced and no NaN/Inf can arise. The tolerance is relative, hence
// invariant under any scaling of the robot's units. The number of dropped pivots is returned
// (the caller raises status_constraint_rank_deficient). Because every pivot is the largest
// remaining diagonal entry, a dropped pivot bounds the whole remaining Schur complement of
// the PSD matrix (|S_ij| <= sqrt(S_ii S_jj) <= tol * max E_jj): all later pivots are dropped
// as well and the kept directions are solved to that tolerance. Without pivoting, a zero pivot
// computed after an ill-conditioned leading block can come out far above any tolerance (the
// rounding of E amplified by that block's condition number), and redundant constraints would
// be enforced with multipliers of 1e16.
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

  // P E P^T = L diag(pivot) L^T with P the product of the conditional swaps; A holds the Schur
  // complement (rows and columns >= k are live), y the permuted right-hand side.
  ConstraintMatrix<Scalar> A = E;
  ConstraintMatrix<Scalar> L = ConstraintMatrix<Scalar>::Identity(nc, nc);
  ConstraintMatrix<Scalar> swapped = ConstraintMatrix<Scalar>::Zero(nc, nc);  // 1 where step k swapped k and j
  ConstraintVector<Scalar> pivot(nc), inverse_pivot(nc);
  ConstraintVector<Scalar> y = rhs;
  const auto conditional_swap = [](const Scalar& s, Scalar& a, Scalar& b) {
    const Scalar a0 = a;
    a = select_greater(s, Scalar(0.5), b, a0);
    b = select_greater(s, Scalar(0.5), a0, b);
  };
  for (Eigen::Index k = 0; k < nc; ++k) {
    for (Eigen::Index j = k + 1; j < nc; ++j) {
      const Scalar s = select_greater(A(j, j), A(k, k), Scalar(1), Scalar(0));
      swapped(k, j) = s;
      for (Eigen::Index c = k; c < nc; ++c) conditional_swap(s, A(k, c), A(j, c));  // rows
      for (Eigen::Index r = k; r < nc; ++r) conditional_swap(s, A(r, k), A(r, j));  // columns
      for (Eigen::Index c = 0; c < k; ++c) conditional_swap(s, L(k, c), L(j, c));
      conditional_swap(s, y[k], y[j]);
    }
    const Scalar d = A(k, k);
    const Scalar threshold = tolerance * E(k, k);
    const Scalar kept = select_greater(d, threshold, Scalar(1), Scalar(0));
    dropped_pivots += Scalar(1) - kept;
    pivot[k] = kept * d;
    inverse_pivot[k] = kept / select_greater(d, threshold, d, Scalar(1));
    for (Eigen::Index i = k + 1; i < nc; ++i) L(i, k) = A(i, k) * inverse_pivot[k];
    for (Eigen::Index i = k + 1; i < nc; ++i)
      for (Eigen::Index j = k + 1; j < nc; ++j) A(i, j) -= L(i, k) * A(k, j);
  }
  // Forward substitution L z = y, scaling z_k = z_k / d_k, back substitution L^T x = z,
  // then ν = P^T x (the swaps undone in reverse order).
  for (Eigen::Index k = 0; k < nc; ++k)
    for (Eigen::Index j = 0; j < k; ++j) y[k] -= L(k, j) * y[j];
  for (Eigen::Index k = 0; k < nc; ++k) y[k] *= inverse_pivot[k];
  for (Eigen::Index k = nc - 1; k >= 0; --k)
    for (Eigen::Index j = k + 1; j < nc; ++j) y[k] -= L(j, k) * y[j];
  for (Eigen::Index k = nc - 1; k >= 0; --k)
    for (Eigen::Index j = nc - 1; j > k; --j) conditional_swap(swapped(k, j), y[k], y[j]);
  return y;
}

}  // namespace sweepgen::solver

// ν = (E^A_cstr,0)^-1 r  (S2) for the symmetric positive semi-definite Nc x Nc matrix E^A_cstr,0
// (docs/derivation.md, section 4: equilibration (C1), pivoted LDL^T (C2), damped (C3)).
//
// Policy: LDL^T with diagonal (symmetric) pivoting, branch-free, judged relative to each
// direction's own diagonal entry. Step k first moves the remaining direction with the largest
// ratio of Schur-complement diagonal to original diagonal, S_jj / E_jj, to position k (a
// tournament of conditional swaps), then takes it as the pivot. A pivot d_k <= tol * E_kk
// (E_kk the original diagonal entry of that direction) is treated as zero: its multiplier is
// set to 0 and its column of L to 0, so that direction of the constraint is not enforced and
// no NaN/Inf can arise. Ratios and threshold are invariant under scaling each direction, so
// moment and force directions and any unit system get the same rank decision. The number of
// dropped pivots is returned (the caller raises status_constraint_rank_deficient).
// Equilibration first: the factorisation works on Ê = S E S, r̂ = S r with s_j =
// equilibration_scale(E_jj) (scalar_ops.hpp), the power of two that brings Ê_jj into [1, 4), and
// returns ν = S x̂. Powers of two scale without rounding, so in exact arithmetic and in floating
// point this is the same solve; what it removes is under- and overflow: in float a direction
// with E_jj ~ 1e-42 (subnormal) made the threshold tol · E_jj underflow to 0, kept a subnormal
// pivot and overflowed 1/d to Inf (a thin rod spun about its own axis near a singularity,
// tests/test_stability.cpp). After it, every kept pivot is > tol and every threshold is >= tol.
// Damped alternative (ConstraintFactorisation::damped, docs/stability.md): the same equilibrated
// Ê, plus tol on its diagonal, factorised without pivoting (Ê + tol I is positive definite, every
// pivot >= tol in exact arithmetic): ν = S (Ê + tol I)^-1 S r. Every direction is kept and the
// result is biased by ~tol cond_s(E) relatively, boundedly so at singularities. Since
// Ê x̂ − r̂ = −tol x̂, tol |x̂_j| is exactly how far direction j misses its setpoint; it is counted
// like a dropped pivot (status_constraint_rank_deficient) when that exceeds sqrt(tol) times the
// largest setpoint term max_i |r̂_i| (tested squared, tol x̂_j² > max_i r̂_i², without a square
// root): the damping visibly held that multiplier back. A redundant direction that asks for a
// compatible motion is met and raises nothing; one that asks for the impossible raises it.
// r̂_j = r_j / sqrt(E_jj) up to a power of two has the same units in every direction, so the
// rule, like the pivoted one, does not depend on units.
// Why pivot: once the largest remaining ratio S_jj / E_jj is at most tol, so is every remaining
// one (and |S_ij| <= sqrt(S_ii S_jj) in the PSD Schur complement): the kept directions are
// solved to that tolerance and the dropped ones are redundant to it. Without pivoting, a pivot
// that is zero in exact arithmetic (a redundant direction) computed after an ill-conditioned
// leading block comes out as the rounding of E amplified by that block's condition number,
// often far above the tolerance: the redundant constraint was then enforced with multipliers
// of 1e16 and q̈ wrong by 100%, with no status raised (tests/test_dense_oracle.cpp).
#pragma once

#include "solver/scalar_ops.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

template <class Scalar>
ConstraintVector<Scalar> solve_constraint_multipliers(const ConstraintMatrix<Scalar>& E,
                                                      const ConstraintVector<Scalar>& rhs,
                                                      ConstraintFactorisation factorisation, const Scalar& tolerance,
                                                      Scalar& dropped_pivots) {
  const bool damped = factorisation == ConstraintFactorisation::damped;
  const Eigen::Index nc = rhs.size();
  dropped_pivots = Scalar(0);
  if (nc == 0) return ConstraintVector<Scalar>(0);

  // P E P^T = L diag(pivot) L^T with P the product of the conditional swaps; A holds the Schur
  // complement (rows and columns >= k are live), y the permuted right-hand side. E and every
  // Schur complement are symmetric: only the lower triangle of A (i >= j) is read or written,
  // and only E's lower triangle is read (the generated code never computes the upper one).
  ConstraintVector<Scalar> scale(nc);  // s_j: Ê = S E S, r̂ = S r, ν = S x̂
  for (Eigen::Index j = 0; j < nc; ++j) scale[j] = equilibration_scale(E(j, j));
  ConstraintMatrix<Scalar> A = ConstraintMatrix<Scalar>::Zero(nc, nc);
  for (Eigen::Index i = 0; i < nc; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) A(i, j) = scale[i] * E(i, j) * scale[j];
  ConstraintMatrix<Scalar> L = ConstraintMatrix<Scalar>::Identity(nc, nc);
  ConstraintMatrix<Scalar> swapped = ConstraintMatrix<Scalar>::Zero(nc, nc);  // 1 where step k swapped k and j
  ConstraintVector<Scalar> pivot(nc), inverse_pivot(nc);
  if (damped)
    for (Eigen::Index j = 0; j < nc; ++j) A(j, j) += tolerance;
  ConstraintVector<Scalar> y(nc);
  for (Eigen::Index j = 0; j < nc; ++j) y[j] = scale[j] * rhs[j];
  ConstraintVector<Scalar> own = A.diagonal();  // Ê_jj of the direction now at position j
  Scalar largest_setpoint_squared(0);             // max_i r̂_i² (damped status rule)
  for (Eigen::Index j = 0; damped && j < nc; ++j) largest_setpoint_squared = maximum(largest_setpoint_squared, y[j] * y[j]);
  const auto conditional_swap = [](const Scalar& s, Scalar& a, Scalar& b) {
    const Scalar a0 = a;
    a = select_greater(s, Scalar(0.5), b, a0);
    b = select_greater(s, Scalar(0.5), a0, b);
  };
  for (Eigen::Index k = 0; k < nc; ++k) {
    // At k = 0 every ratio is E_jj / E_jj: no swap can happen (the products below are equal).
    for (Eigen::Index j = k + 1; !damped && k > 0 && j < nc; ++j) {
      // S_jj / E_jj > S_kk / E_kk, without dividing (E_jj >= 0).
      const Scalar s = select_greater(A(j, j) * own[k], A(k, k) * own[j], Scalar(1), Scalar(0));
      swapped(k, j) = s;
      // The symmetric swap of k and j in the lower triangle of the live block: the diagonal
      // entries, (c, k) with (j, c) for k < c < j, (c, k) with (c, j) for c > j; (j, k) stays.
      conditional_swap(s, A(k, k), A(j, j));
      for (Eigen::Index c = k + 1; c < j; ++c) conditional_swap(s, A(c, k), A(j, c));
      for (Eigen::Index c = j + 1; c < nc; ++c) conditional_swap(s, A(c, k), A(c, j));
      for (Eigen::Index c = 0; c < k; ++c) conditional_swap(s, L(k, c), L(j, c));
      conditional_swap(s, y[k], y[j]);
      conditional_swap(s, own[k], own[j]);
    }
    const Scalar d = A(k, k);
    if (damped) {
      pivot[k] = d;
      inverse_pivot[k] = Scalar(1) / d;
    } else {
      const Scalar threshold = tolerance * own[k];
      const Scalar kept = select_greater(d, threshold, Scalar(1), Scalar(0));
      dropped_pivots += Scalar(1) - kept;
      pivot[k] = kept * d;
      inverse_pivot[k] = kept / select_greater(d, threshold, d, Scalar(1));
    }
    for (Eigen::Index i = k + 1; i < nc; ++i) L(i, k) = A(i, k) * inverse_pivot[k];
    for (Eigen::Index i = k + 1; i < nc; ++i)
      for (Eigen::Index j = k + 1; j <= i; ++j) A(i, j) -= L(i, k) * A(j, k);  // A(k, j) = A(j, k)
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
  for (Eigen::Index j = 0; damped && j < nc; ++j)
    dropped_pivots += select_greater(tolerance * y[j] * y[j], largest_setpoint_squared, Scalar(1), Scalar(0));
  for (Eigen::Index j = 0; j < nc; ++j) y[j] *= scale[j];
  return y;
}

}  // namespace sweepgen::solver

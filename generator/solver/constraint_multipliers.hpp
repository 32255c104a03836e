// ν = (E^A_cstr,0)^-1 r  (S2) for the symmetric positive semi-definite Nc x Nc matrix E^A_cstr,0
// (docs/derivation.md, section 4: equilibration (C1), pivoted LDL^T (C2), damped (C3), the
// natural-order path (C4) and its test by a block-diagonal lower bound (C5)).
//
// Paths (C4): the pivoted factorisation below is the fallback. First an LDL^T in the natural
// order (no swaps) is formed; where the diagonal of Ê^-1 from its factors shows that the pivoted
// order would drop no direction (kNaturalOrderMargin), its solution is the answer, and the generated code
// computes only that path (select_path: the pivoted one runs inside the `else` of an if). Ranks
// and statuses are those of the pivoted path on every state; both paths are exact solves of
// the same equilibrated system, so they differ by rounding only.
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
// Equilibration first (on the pivoted and the damped path; the natural path (C4) is the same solve
// to the bit without it, within a range of E_jj it checks): the factorisation works on Ê = S E S,
// r̂ = S r with s_j = equilibration_scale(E_jj) (scalar_ops.hpp), the power of two that brings Ê_jj
// into [1, 4), and returns ν = S x̂. Powers of two scale without rounding, so in exact arithmetic
// and in floating point this is the same solve; what it removes is under- and overflow: in float a direction
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

#include <utility>
#include <vector>

#include "solver/scalar_ops.hpp"
#include "solver/solver_model.hpp"
#include "solver/state.hpp"

namespace sweepgen::solver {

// (C4)'s margin M: the natural order is taken where M tol Σ_j Ê_jj (Ê^-1)_jj < 1. In exact
// arithmetic, whatever the order, direction j reaches its pivot with some set K of the others
// eliminated, and its pivot is the Schur complement S_jj(K) >= S_jj(all others) = 1 / (Ê^-1)_jj
// (eliminating more directions of a positive semi-definite matrix only lowers a Schur diagonal):
// every ratio d / Ê_jj of (C2)'s order is >= 1 / (Ê_jj (Ê^-1)_jj) > M tol, so (C2) drops nothing.
// (The first version's rule, Π d_k > M tol Π Ê_kk, is weaker by up to the product of the other
// Nc − 1 ratios: with two 6-D sets, Nc = 12, it sent most states to the pivoted path.) Computed,
// each quantity is that of Ê perturbed by its own rounding (~(Nc + 1) ε per entry, the backward
// error of a Cholesky-type factorisation); the margin keeps the states where that could tip a
// decision, within a factor M of the tolerance, on the pivoted path, which decides as before
// (tests/test_constraint_factorisation.cpp asserts equal decisions on near-singular systems).
inline constexpr double kNaturalOrderMargin = 4;

// (C1): Ê = S E S (lower triangle), r̂ = S r, with s_j = equilibration_scale(E_jj).
template <class Scalar>
struct EquilibratedSystem {
  ConstraintVector<Scalar> scale;  // s_j
  ConstraintMatrix<Scalar> A;      // Ê, lower triangle (i >= j); the upper one is 0
  ConstraintVector<Scalar> y;      // r̂
};

template <class Scalar>
EquilibratedSystem<Scalar> equilibrate(const ConstraintMatrix<Scalar>& E, const ConstraintVector<Scalar>& rhs) {
  const Eigen::Index nc = rhs.size();
  EquilibratedSystem<Scalar> sys{ConstraintVector<Scalar>(nc), ConstraintMatrix<Scalar>::Zero(nc, nc), ConstraintVector<Scalar>(nc)};
  for (Eigen::Index j = 0; j < nc; ++j) sys.scale[j] = equilibration_scale(E(j, j));
  for (Eigen::Index i = 0; i < nc; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) sys.A(i, j) = sys.scale[i] * E(i, j) * sys.scale[j];
  for (Eigen::Index j = 0; j < nc; ++j) sys.y[j] = sys.scale[j] * rhs[j];
  return sys;
}

// L z = y, z_k = z_k / d_k, L^T x = z, in place on y: the substitutions of (C2) and (C4).
template <class Scalar>
void substitute(const ConstraintMatrix<Scalar>& L, const ConstraintVector<Scalar>& inverse_pivot, ConstraintVector<Scalar>& y) {
  const Eigen::Index nc = y.size();
  for (Eigen::Index k = 0; k < nc; ++k)
    for (Eigen::Index j = 0; j < k; ++j) y[k] -= L(k, j) * y[j];
  for (Eigen::Index k = 0; k < nc; ++k) y[k] *= inverse_pivot[k];
  for (Eigen::Index k = nc - 1; k >= 0; --k)
    for (Eigen::Index j = k + 1; j < nc; ++j) y[k] -= L(j, k) * y[j];
}

// (C2), (C3): x̂ with Ê x̂ = r̂, pivoted (or damped); `dropped_pivots` as the header says.
template <class Scalar>
ConstraintVector<Scalar> pivoted_solve(EquilibratedSystem<Scalar> sys, bool damped, const Scalar& tolerance,
                                       Scalar& dropped_pivots) {
  const Eigen::Index nc = sys.y.size();
  dropped_pivots = Scalar(0);
  // P Ê P^T = L diag(pivot) L^T with P the product of the conditional swaps; A holds the Schur
  // complement (rows and columns >= k are live), y the permuted right-hand side. Ê and every
  // Schur complement are symmetric: only the lower triangle of A (i >= j) is read or written.
  ConstraintMatrix<Scalar>& A = sys.A;
  ConstraintVector<Scalar>& y = sys.y;
  ConstraintMatrix<Scalar> L = ConstraintMatrix<Scalar>::Identity(nc, nc);
  ConstraintMatrix<Scalar> swapped = ConstraintMatrix<Scalar>::Zero(nc, nc);  // 1 where step k swapped k and j
  ConstraintVector<Scalar> inverse_pivot(nc);
  if (damped)
    for (Eigen::Index j = 0; j < nc; ++j) A(j, j) += tolerance;
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
      inverse_pivot[k] = Scalar(1) / d;
    } else {
      const Scalar threshold = tolerance * own[k];
      const Scalar kept = select_greater(d, threshold, Scalar(1), Scalar(0));
      dropped_pivots += Scalar(1) - kept;
      inverse_pivot[k] = kept / select_greater(d, threshold, d, Scalar(1));
    }
    for (Eigen::Index i = k + 1; i < nc; ++i) L(i, k) = A(i, k) * inverse_pivot[k];
    for (Eigen::Index i = k + 1; i < nc; ++i)
      for (Eigen::Index j = k + 1; j <= i; ++j) A(i, j) -= L(i, k) * A(j, k);  // A(k, j) = A(j, k)
  }
  // The substitutions, then x = P^T x (the swaps undone in reverse order).
  substitute(L, inverse_pivot, y);
  for (Eigen::Index k = nc - 1; k >= 0; --k)
    for (Eigen::Index j = nc - 1; j > k; --j) conditional_swap(swapped(k, j), y[k], y[j]);
  for (Eigen::Index j = 0; damped && j < nc; ++j)
    dropped_pivots += select_greater(tolerance * y[j] * y[j], largest_setpoint_squared, Scalar(1), Scalar(0));
  return y;
}

// (C4): LDL^T of the lower triangle of A in the natural order (no swaps). A pivot d_k below
// floor_k (the natural order broke down; the caller passes tol / 2 times the direction's own
// diagonal entry) is read as floor_k: its term in weighted_inverse_diagonal is then far above the
// rule's bound and (C2) decides; where the rule holds, every d_k > M tol E_kk, so the natural
// solution used the true pivots (and the floor, relative and so the same in every unit system,
// decided nothing).
template <class Scalar>
struct NaturalFactors {
  ConstraintMatrix<Scalar> L;             // unit lower triangular
  ConstraintVector<Scalar> inverse_pivot;  // 1 / d_k
};

template <class Scalar>
NaturalFactors<Scalar> natural_factors(ConstraintMatrix<Scalar> A, const ConstraintVector<Scalar>& floor) {
  const Eigen::Index nc = A.rows();
  NaturalFactors<Scalar> f{ConstraintMatrix<Scalar>::Identity(nc, nc), ConstraintVector<Scalar>(nc)};
  ConstraintMatrix<Scalar>& L = f.L;
  for (Eigen::Index k = 0; k < nc; ++k) {
    for (Eigen::Index j = 0; j < k; ++j) A(k, k) -= L(k, j) * A(k, j);  // d_k = E_kk − Σ_{j<k} L_kj (L_kj d_j)
    f.inverse_pivot[k] = Scalar(1) / maximum(A(k, k), floor[k]);
    // Column k below the pivot: A(i, k) becomes L_ik d_k = E_ik − Σ_{j<k} L_ij (L_kj d_j) and stays
    // so (the rows below read it as L_ik d_k: the left-looking form), L_ik = A(i, k) / d_k.
    for (Eigen::Index i = k + 1; i < nc; ++i)
      for (Eigen::Index j = 0; j < k; ++j) A(i, k) -= L(i, j) * A(k, j);
    for (Eigen::Index i = k + 1; i < nc; ++i) L(i, k) = A(i, k) * f.inverse_pivot[k];
  }
  return f;
}

// tol / 2 times each direction's own diagonal entry of E: natural_factors' floors.
template <class Scalar>
ConstraintVector<Scalar> pivot_floors(const ConstraintMatrix<Scalar>& E, const Scalar& tolerance) {
  ConstraintVector<Scalar> floor(E.rows());
  for (Eigen::Index k = 0; k < E.rows(); ++k) floor[k] = Scalar(0.5) * tolerance * E(k, k);
  return floor;
}

// Σ_j w_j (A^-1)_jj, (A^-1)_jj = Σ_{m>=j} (L^-1)_mj² / d_m from A's natural factors, with w_j = E_jj:
// what the rules of (C4) (A = E) and (C5) (A = B) bound. A sum of positive terms (an Inf or NaN is
// never lost), each invariant under scaling its direction (tr E^-1 alone is not: a robot scaled by
// powers of two crossed the threshold differently with it, tests/test_stability.cpp). A zero
// direction (E_jj = 0) has the floor 0 and the term 0 · Inf, NaN: the rule fails, as it must (the
// direction is dropped).
template <class Scalar>
Scalar weighted_inverse_diagonal(const NaturalFactors<Scalar>& f, const ConstraintVector<Scalar>& w) {
  const Eigen::Index nc = w.size();
  Scalar sum(0);
  // Column j of L^-1 (unit lower triangular): v_j = 1, v_m = −Σ_{j<=l<m} L_ml v_l for m > j.
  for (Eigen::Index j = 0; j < nc; ++j) {
    ConstraintVector<Scalar> v = ConstraintVector<Scalar>::Zero(nc);
    v[j] = Scalar(1);
    Scalar inverse_diagonal = f.inverse_pivot[j];  // (A^-1)_jj
    for (Eigen::Index m = j + 1; m < nc; ++m) {
      for (Eigen::Index l = j; l < m; ++l) v[m] -= f.L(m, l) * v[l];
      inverse_diagonal += v[m] * v[m] * f.inverse_pivot[m];
    }
    sum += w[j] * inverse_diagonal;
  }
  return sum;
}

// (C4): ν with E ν = r from E's natural factors, and `coupling` = Σ_j E_jj (E^-1)_jj from the same
// factors, what the rule of (C4) bounds. On E itself: within the range that the caller checks,
// (C1)'s powers of two would scale every quantity here without rounding, so this is (C1)'s solve to
// the bit, without forming Ê.
template <class Scalar>
ConstraintVector<Scalar> natural_order_solve(const ConstraintMatrix<Scalar>& E, ConstraintVector<Scalar> rhs,
                                             const Scalar& tolerance, Scalar& coupling) {
  const NaturalFactors<Scalar> f = natural_factors(E, pivot_floors(E, tolerance));
  coupling = weighted_inverse_diagonal(f, ConstraintVector<Scalar>(E.diagonal()));
  substitute(f.L, f.inverse_pivot, rhs);
  return rhs;
}

// (C5): B, block-diagonal with B ⪯ E^A_cstr,0 (E − B positive semi-definite): per block, the
// directions it holds (first, count) and, in `energy`, its lower triangle (the rest 0). The inward
// sweep forms it where the constraint sets reach the base through joints of their own
// (decomposition_sweep.hpp, SolverModel::private_top): each set's block is the sum of the terms
// (I3) of the joints that carry that set alone, E the same sum plus the shared joints' terms.
template <class Scalar>
struct BlockLowerBound {
  ConstraintMatrix<Scalar> energy;
  std::vector<std::pair<Eigen::Index, Eigen::Index>> blocks;
};

// (C5): Σ_j E_jj (B^-1)_jj, block by block: at least (C4)'s sum, since B ⪯ E gives E^-1 ⪯ B^-1
// and so (E^-1)_jj <= (B^-1)_jj. A block with fewer than its count of independent joints is
// singular: its floored pivots (natural_factors) fail the rule.
template <class Scalar>
Scalar block_coupling(const ConstraintMatrix<Scalar>& E, const BlockLowerBound<Scalar>& bound,
                      const Scalar& tolerance) {
  const ConstraintVector<Scalar> floor = pivot_floors(E, tolerance), own = E.diagonal();
  Scalar sum(0);
  for (const auto& [first, count] : bound.blocks)
    sum += weighted_inverse_diagonal(
        natural_factors(ConstraintMatrix<Scalar>(bound.energy.block(first, first, count, count)),
                        ConstraintVector<Scalar>(floor.segment(first, count))),
        ConstraintVector<Scalar>(own.segment(first, count)));
  return sum;
}

// `lower_bound`: (C5)'s B where the sweep formed one (the natural order is then first tested with
// it, and (C4)'s own sum computed only where that test fails).
template <class Scalar>
ConstraintVector<Scalar> solve_constraint_multipliers(const ConstraintMatrix<Scalar>& E,
                                                      const ConstraintVector<Scalar>& rhs,
                                                      ConstraintFactorisation factorisation, const Scalar& tolerance,
                                                      Scalar& dropped_pivots, Scalar* took_pivoted_path = nullptr,
                                                      const BlockLowerBound<Scalar>* lower_bound = nullptr) {
  const bool damped = factorisation == ConstraintFactorisation::damped;
  const Eigen::Index nc = rhs.size();
  dropped_pivots = Scalar(0);
  if (took_pivoted_path != nullptr) *took_pivoted_path = Scalar(damped ? 1 : 0);
  if (nc == 0) return ConstraintVector<Scalar>(0);
  const EquilibratedSystem<Scalar> sys = equilibrate(E, rhs);
  ConstraintVector<Scalar> x = pivoted_solve(sys, damped, tolerance, dropped_pivots);
  for (Eigen::Index j = 0; j < nc; ++j) x[j] *= sys.scale[j];
  if (!damped) {
    // (C4): the natural order's pivots keep every direction by a margin: (C2) would drop none.
    Scalar coupling;
    const ConstraintVector<Scalar> natural = natural_order_solve(E, rhs, tolerance, coupling);
    const Scalar one(1), margin = Scalar(kNaturalOrderMargin) * tolerance;
    Scalar bound = margin * coupling;
    if (lower_bound != nullptr) {  // (C5): (C4)'s sum only where the block bound does not decide
      const Scalar block_bound = margin * block_coupling(E, *lower_bound, tolerance);
      bound = select_path(one, block_bound, block_bound, bound);
    }
    // The natural path runs on E itself (no C1) where every E_jj lies within [tol³, tol⁻³]: (C1)'s
    // powers of two then scale each of its quantities by at most tol⁻⁶ (2^252 in double, 2^78 in
    // float, against exponent ranges of 2^±1022 and 2^±126), so none under- or overflows where the
    // scaled one would not, and the natural path's bits are (C1)'s scaled back. Elsewhere (a
    // subnormal E_jj, a zero or NaN one) the pivoted path on Ê decides.
    const Scalar floor = tolerance * tolerance * tolerance, ceiling = one / floor;
    Scalar outside(0);
    for (Eigen::Index j = 0; j < nc; ++j)
      outside += select_greater(E(j, j), floor, Scalar(0), one) + select_greater(ceiling, E(j, j), Scalar(0), one);
    bound = select_greater(outside, Scalar(0.5), one, bound);
    for (Eigen::Index j = 0; j < nc; ++j) x[j] = select_path(one, bound, natural[j], x[j]);
    dropped_pivots = select_path(one, bound, Scalar(0), dropped_pivots);
    if (took_pivoted_path != nullptr) *took_pivoted_path = select_greater(one, bound, Scalar(0), Scalar(1));
  }
  return x;
}

}  // namespace sweepgen::solver

// The two factorisations of E^A_cstr,0 (solver/constraint_multipliers.hpp, docs/stability.md) on
// matrices built to the purpose: Eν = r solved to rounding by pivoted LDLᵀ, the damped solve's
// bias bounded by its damping, the rank-deficiency count of each rule, invariance under any
// scaling of the directions (units), and the float case that once overflowed (a subnormal
// diagonal entry).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "oracle/condition_number.hpp"
#include "solver/constraint_multipliers.hpp"
#include "support/skip_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::ConstraintFactorisation;
using Matrix = solver::ConstraintMatrix<double>;
using Vector = solver::ConstraintVector<double>;
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kTol = 1000 * kEps;  // the default relative tolerance in double
constexpr ConstraintFactorisation kBoth[] = {ConstraintFactorisation::pivoted_ldlt, ConstraintFactorisation::damped};

struct Solved {
  Vector nu;
  double dropped = 0;
};

Solved solve(const Matrix& E, const Vector& r, ConstraintFactorisation f, double tol = kTol) {
  Solved s;
  s.nu = solver::solve_constraint_multipliers<double>(E, r, f, tol, s.dropped);
  return s;
}

// E = B Bᵀ with B (n x rank) random, then each direction scaled by 10^u, u in [-4, 4]: a positive
// semi-definite matrix of the given rank with diagonal entries eight orders of magnitude apart
// (moment and force directions in any units).
Matrix random_energy(std::mt19937_64& random, int n, int rank) {
  std::uniform_real_distribution<double> entry(-1, 1), exponent(-4, 4);
  Eigen::MatrixXd B(n, rank);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < rank; ++j) B(i, j) = entry(random);
  Eigen::VectorXd units(n);
  for (int i = 0; i < n; ++i) units[i] = std::pow(10.0, exponent(random));
  const Eigen::MatrixXd E = units.asDiagonal() * (B * B.transpose()) * units.asDiagonal();
  return E;
}

// Errors in the equilibrated coordinates d_j ν_j, d_j = sqrt(E_jj) (what a backward-stable solve
// of the equilibrated system bounds, and invariant under the units of each direction): multipliers
// of directions eight orders of magnitude apart are judged each against its own scale.
double multiplier_error(const Matrix& E, const Vector& nu, const Vector& truth) {
  const Eigen::VectorXd d = E.diagonal().cwiseSqrt();
  return d.cwiseProduct(nu - truth).cwiseAbs().maxCoeff() / d.cwiseProduct(truth).cwiseAbs().maxCoeff();
}
// ‖d^-1 (E ν − r)‖∞ / ‖d^-1 r‖∞: the constraint residual in the same coordinates.
double residual(const Matrix& E, const Vector& nu, const Vector& r) {
  const Eigen::VectorXd d = E.diagonal().cwiseSqrt().cwiseInverse();
  return d.cwiseProduct(E * nu - r).cwiseAbs().maxCoeff() / d.cwiseProduct(r).cwiseAbs().maxCoeff();
}

// The oracle's condition numbers: cond_2 = σmax/σmin of a square matrix (its SVD has no QR
// preconditioner, which only a non-square matrix would need), and a non-square one refused.
TEST(ConstraintFactorisation, ConditionNumbersOfSquareMatricesOnly) {
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(3, 3);
  E.diagonal() << 4, 1, 0.5;  // symmetric, eigenvalues 4, 1, 0.5
  EXPECT_DOUBLE_EQ(oracle::condition_number(E), 8);
  EXPECT_DOUBLE_EQ(oracle::scaled_condition_number(E), 1);  // diagonal: equilibrated to the identity
  Eigen::MatrixXd rotated = Eigen::MatrixXd::Zero(2, 2);
  rotated << 0, 3, -1, 0;  // singular values 3 and 1
  EXPECT_DOUBLE_EQ(oracle::condition_number(rotated), 3);
  EXPECT_THROW(oracle::condition_number(Eigen::MatrixXd::Ones(2, 3)), std::invalid_argument);
  EXPECT_THROW(oracle::condition_number(Eigen::MatrixXd::Ones(3, 2)), std::invalid_argument);
}

TEST(ConstraintFactorisation, FullRankPivotedIsExactAndDampedIsBiasedByItsDamping) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> entry(-1, 1);
  // random_energy's full-rank matrices rarely exceed cond_s 1e8 (measured: 1 of 500): at most 5%.
  test::SkipCount skips("full-rank factorisations", 0.05);
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 1 + trial % 6;
    const Matrix E = random_energy(random, n, n);
    const double cond = oracle::scaled_condition_number(E);
    if (skips.skip(cond > 1e8, "cond_s > 1e8")) continue;  // keep the damped bias (~tol cond) well below 1
    Vector nu_true(n);
    for (int i = 0; i < n; ++i) nu_true[i] = entry(random);
    const Vector r = E * nu_true;
    const Solved pivoted = solve(E, r, ConstraintFactorisation::pivoted_ldlt);
    const Solved damped = solve(E, r, ConstraintFactorisation::damped);
    EXPECT_EQ(pivoted.dropped, 0) << "cond " << cond;
    EXPECT_EQ(damped.dropped, 0) << "cond " << cond;
    // Backward-stable solve of the equilibrated system: eps cond, times a small constant
    // (measured <= 3).
    EXPECT_LE(multiplier_error(E, pivoted.nu, nu_true), 20 * kEps * cond) << "cond " << cond;
    // Damping by tol on a unit-order diagonal moves ν by at most ~tol cond_s relatively (the
    // equilibrated diagonal is in [1, 4), hence the factor 4), plus rounding.
    EXPECT_LE(multiplier_error(E, damped.nu, nu_true), 4 * kTol * cond + 20 * kEps * cond) << "cond " << cond;
  }
}

// diag(sqrt(E_jj)): setpoints of each direction's own scale.
Eigen::MatrixXd c_scale(const Matrix& E) { return E.diagonal().cwiseSqrt().asDiagonal(); }

TEST(ConstraintFactorisation, RankDeficientMatricesAreReportedAndStayFinite) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> entry(-1, 1);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 2 + trial % 5, rank = 1 + trial % (n - 1);
    const Matrix E = random_energy(random, n, rank);
    Vector nu_any(n), r_impossible(n);
    for (int i = 0; i < n; ++i) nu_any[i] = entry(random), r_impossible[i] = entry(random);
    const Vector r = E * nu_any;  // consistent: some ν solves it
    r_impossible = c_scale(E) * r_impossible;  // generic: not in the range of E
    // Pivoted: exactly the n - rank redundant directions are dropped, whatever the setpoints;
    // the consistent constraints are met.
    const Solved pivoted = solve(E, r, ConstraintFactorisation::pivoted_ldlt);
    EXPECT_TRUE(pivoted.nu.allFinite());
    EXPECT_EQ(pivoted.dropped, n - rank) << "n " << n << " rank " << rank;
    EXPECT_LE(residual(E, pivoted.nu, r), 1e-9) << "n " << n << " rank " << rank;
    EXPECT_EQ(solve(E, r_impossible, ConstraintFactorisation::pivoted_ldlt).dropped, n - rank);
    // Damped: consistent setpoints are met to sqrt(tol) and raise nothing; impossible ones
    // raise it, with bounded (finite) multipliers.
    const Solved met = solve(E, r, ConstraintFactorisation::damped);
    EXPECT_TRUE(met.nu.allFinite());
    EXPECT_EQ(met.dropped, 0) << "n " << n << " rank " << rank;
    EXPECT_LE(residual(E, met.nu, r), std::sqrt(kTol)) << "n " << n << " rank " << rank;
    const Solved missed = solve(E, r_impossible, ConstraintFactorisation::damped);
    EXPECT_TRUE(missed.nu.allFinite());
    EXPECT_GE(missed.dropped, 1) << "n " << n << " rank " << rank;
  }
}

// (C4): the natural-order path is an exact solve where it is taken, and it is taken only where the
// pivoted factorisation (C2) would keep every direction: the rank decision is the pivoted one's on
// every matrix, also on those built to put the smallest pivot ratio near the tolerance.
TEST(ConstraintFactorisation, NaturalOrderPathDecidesAsThePivotedFactorisation) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> entry(-1, 1), exponent(-3, 4);
  int natural = 0, well_conditioned = 0, well_conditioned_natural = 0;
  double worst_difference = 0;
  constexpr int kTrials = 3000;
  for (int trial = 0; trial < kTrials; ++trial) {
    // Up to Nc = 12, two 6-D sets (dual_panda_box, quadruped_stance).
    const int n = 1 + trial % 12, rank = trial % 3 == 0 ? n : 1 + trial % n;
    Matrix E = random_energy(random, n, rank);
    if (trial % 3 == 1) {
      // Rank-deficient, then lifted along a random direction by tol 10^u times its scale: the
      // smallest pivot ratio lands within a few orders of magnitude of the tolerance, both sides.
      Eigen::VectorXd v(n);
      for (int i = 0; i < n; ++i) v[i] = entry(random) * std::sqrt(E(i, i));
      E += kTol * std::pow(10.0, exponent(random)) * v * v.transpose();
    }
    Vector r(n);
    for (int i = 0; i < n; ++i) r[i] = entry(random) * std::sqrt(E(i, i));
    double pivoted_dropped = 0, path = 0;
    const Vector pivoted = solver::pivoted_solve(solver::equilibrate(E, r), false, kTol, pivoted_dropped);
    Solved both;
    both.nu = solver::solve_constraint_multipliers<double>(E, r, ConstraintFactorisation::pivoted_ldlt, kTol,
                                                           both.dropped, &path);
    ASSERT_EQ(both.dropped, pivoted_dropped) << "trial " << trial << " n " << n << " rank " << rank;
    const bool took_natural = path == 0;
    natural += took_natural;
    if (took_natural) {
      EXPECT_EQ(pivoted_dropped, 0) << "trial " << trial;
      // Both paths solve the same equilibrated system exactly but for rounding: the difference
      // in the equilibrated coordinates is a few ε cond_s each (cond_s ≤ 1/(M tol) here, so the
      // difference can be O(1) only for nearly singular systems); measured against the pivoted
      // solution's own error bound, 64 ε cond_s (Higham, LDLᵀ backward error times cond).
      Vector pivoted_nu = pivoted;
      for (int j = 0; j < n; ++j) pivoted_nu[j] *= solver::equilibration_scale(E(j, j));
      const double cond = oracle::scaled_condition_number(E);
      const double difference = multiplier_error(E, both.nu, pivoted_nu);
      EXPECT_LE(difference, 64 * kEps * cond) << "trial " << trial << " cond_s " << cond;
      worst_difference = std::max(worst_difference, difference / (kEps * cond));
    }
    if (rank == n && trial % 3 == 0 && oracle::scaled_condition_number(E) < 1e8) {
      ++well_conditioned;
      well_conditioned_natural += took_natural;
    }
  }
  std::printf("[          ] natural-order path on %d of %d systems (well-conditioned full rank: %d of %d); "
              "worst difference from the pivoted solve %.2f eps cond_s\n",
              natural, kTrials, well_conditioned_natural, well_conditioned, worst_difference);
  // (C4)'s rule M tol Σ_j Ê_jj (Ê^-1)_jj < 1 holds on every full-rank system with cond_s < 1e8:
  // each term is invariant under scaling a direction, so it is that of the Jacobi-scaled matrix E_s,
  // E_s,jj (E_s^-1)_jj <= cond_2(E_s) = cond_s, and M tol times the sum <= 4 · 2.2e-13 · 12 · 1e8 = 1.1e-3.
  EXPECT_EQ(well_conditioned_natural, well_conditioned);
  EXPECT_GE(well_conditioned, 100);
}

TEST(ConstraintFactorisation, NaturalOrderPathTakesCorrelatedWellConditionedSystems) {
  // Many directions that each share most of their motion with the others (two hands on one torso,
  // feet on one trunk): E = C ((1 − ρ) 1 + ρ 1 1^T) C, C random units. Its pivot ratios in the
  // natural order are (1 − ρ)(1 + kρ)/(1 + (k − 1)ρ), their product (1 − ρ)^(Nc−1) (1 + (Nc − 1)ρ):
  // below M tol = 8.9e-13 at ρ = 0.95 from Nc = 11 and at ρ = 0.99 from Nc = 8, though cond_s is
  // only (1 + (Nc − 1)ρ)/(1 − ρ) <= 1.2e3. (C4)'s rule: Σ_j E_s,jj (E_s^-1)_jj = tr E_s^-1 =
  // (Nc − 1)/(1 − ρ) + 1/(1 + (Nc − 1)ρ) <= 1.1e3, so M tol times it <= 1e-9: every one is solved on
  // the natural path.
  std::mt19937_64 random(13);
  std::uniform_real_distribution<double> exponent(-4, 4), entry(-1, 1);
  int systems = 0, natural = 0;
  for (int n = 2; n <= 12; ++n)
    for (double rho : {0.5, 0.9, 0.95, 0.99}) {
      Eigen::VectorXd units(n);
      for (int i = 0; i < n; ++i) units[i] = std::pow(10.0, exponent(random));
      const Matrix correlated = (1 - rho) * Matrix::Identity(n, n) + rho * Matrix::Ones(n, n);
      const Matrix E = units.asDiagonal() * correlated * units.asDiagonal();
      Vector r(n);
      for (int i = 0; i < n; ++i) r[i] = entry(random) * units[i];
      double dropped = 0, path = 1;
      const Vector nu = solver::solve_constraint_multipliers<double>(E, r, ConstraintFactorisation::pivoted_ldlt, kTol,
                                                                     dropped, &path);
      ++systems;
      natural += path == 0;
      EXPECT_EQ(path, 0) << "Nc " << n << " rho " << rho;
      EXPECT_EQ(dropped, 0);
      // The natural path's answer: residual of a backward-stable solve, <= 64 ε cond_s (cond_s <= 1.2e3).
      EXPECT_LE(residual(E, nu, r), 64 * kEps * 1.2e3) << "Nc " << n << " rho " << rho;
    }
  std::printf("[          ] natural-order path on %d of %d correlated systems\n", natural, systems);
}

// (C4) on E itself gives (C1)'s bits: within the range it checks, the natural path's factors,
// rule and multipliers on E equal those on Ê = S E S scaled back (powers of two scale without
// rounding), bit for bit, on matrices with diagonal entries eight orders of magnitude apart; and an
// E_jj outside [tol³, tol⁻³] (here 1e-45, a subnormal-scale direction) sends the solve to the
// pivoted path however well-conditioned the system.
TEST(ConstraintFactorisation, NaturalPathOnEItselfHasTheEquilibratedBits) {
  std::mt19937_64 random(19);
  std::uniform_real_distribution<double> entry(-1, 1);
  for (int trial = 0; trial < 500; ++trial) {
    const int n = 1 + trial % 12;
    const Matrix E = random_energy(random, n, n);
    Vector r(n);
    for (int i = 0; i < n; ++i) r[i] = entry(random) * std::sqrt(E(i, i));
    const auto sys = solver::equilibrate(E, r);
    double plain_rule = 0, scaled_rule = 0;
    const Vector plain = solver::natural_order_solve(E, r, kTol, plain_rule);
    const Vector scaled = solver::natural_order_solve(Matrix(sys.A), Vector(sys.y), kTol, scaled_rule);
    ASSERT_EQ(plain_rule, scaled_rule) << "trial " << trial;
    for (int j = 0; j < n; ++j) ASSERT_EQ(plain[j], scaled[j] * sys.scale[j]) << "trial " << trial << " direction " << j;
  }
  Matrix E = Matrix::Identity(3, 3);
  E(2, 2) = 1e-45;
  const Vector r = Vector::Ones(3);
  double dropped = 0, path = 0;
  const Vector nu = solver::solve_constraint_multipliers<double>(E, r, ConstraintFactorisation::pivoted_ldlt, kTol, dropped,
                                                                 &path);
  EXPECT_EQ(path, 1) << "an E_jj below tol³ took the natural path";
  EXPECT_EQ(dropped, 0);
  EXPECT_DOUBLE_EQ(nu[2], 1 / E(2, 2));  // the pivoted path on Ê
}

// (C5) on matrices shaped like a tree's: E = B + V Vᵀ with B block-diagonal (sets of 3 or 6
// directions, each block the Gram matrix of its own random joints: full rank, or short of it like a
// leg at its singularity) and V the joints the sets share (up to six: a floating base). With B as
// the lower bound, the solve decides as without it (the same path and statuses, (C2)'s decision),
// returns the same bits on the natural path (the same factors and substitutions), and its sum is at
// least (C4)'s; the bound decides on most systems with nonsingular blocks.
TEST(ConstraintFactorisation, BlockLowerBoundDecidesAsTheNaturalOrderRule) {
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> entry(-1, 1), exponent(-3, 3);
  int systems = 0, decided_by_blocks = 0, nonsingular_blocks = 0;
  constexpr int kTrials = 2000;
  for (int trial = 0; trial < kTrials; ++trial) {
    const int width = trial % 2 == 0 ? 3 : 6, sets = 2 + trial % 3;  // 6 .. 12 directions (the quadruped: 4 x 3)
    const int n = std::min(width * sets, 12), shared = 1 + trial % 6;
    if (width * sets > 12) continue;
    solver::BlockLowerBound<double> bound{Matrix::Zero(n, n), {}};
    bool singular = false;
    for (int first = 0; first < n; first += width) {
      // A block of rank `width` (own joints enough) or one short (a leg at its singularity).
      const int own = trial % 7 == 3 ? width - 1 : width + trial % 2;
      singular = singular || own < width;
      Eigen::MatrixXd J(width, own);
      for (int i = 0; i < width; ++i)
        for (int j = 0; j < own; ++j) J(i, j) = entry(random);
      bound.energy.block(first, first, width, width) = J * J.transpose();
      bound.blocks.emplace_back(first, width);
    }
    Eigen::MatrixXd V(n, shared);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < shared; ++j) V(i, j) = entry(random);
    Eigen::VectorXd units(n);
    for (int i = 0; i < n; ++i) units[i] = std::pow(10.0, exponent(random));
    bound.energy = units.asDiagonal() * bound.energy * units.asDiagonal();
    const Matrix E = bound.energy + units.asDiagonal() * (V * V.transpose()) * units.asDiagonal();
    Vector r(n);
    for (int i = 0; i < n; ++i) r[i] = entry(random) * units[i];
    ++systems;
    nonsingular_blocks += !singular;

    Solved plain, blocked;
    double plain_path = 0, blocked_path = 0;
    plain.nu = solver::solve_constraint_multipliers<double>(E, r, ConstraintFactorisation::pivoted_ldlt, kTol,
                                                            plain.dropped, &plain_path);
    blocked.nu = solver::solve_constraint_multipliers<double>(E, r, ConstraintFactorisation::pivoted_ldlt, kTol,
                                                              blocked.dropped, &blocked_path, &bound);
    ASSERT_EQ(blocked_path, plain_path) << "trial " << trial;
    ASSERT_EQ(blocked.dropped, plain.dropped) << "trial " << trial;
    for (int j = 0; j < n; ++j) ASSERT_EQ(blocked.nu[j], plain.nu[j]) << "trial " << trial << " direction " << j;

    double coupling = 0;
    solver::natural_order_solve(E, r, kTol, coupling);
    const double block_sum = solver::block_coupling(E, bound, kTol);
    // B ⪯ E: the block sum bounds (C4)'s, to the rounding of the two sums (a few ε relative), up to
    // ten times the rule's bound (beyond it, near-singular blocks and matrices are clamped
    // differently, and neither sum decides anything).
    if (solver::kNaturalOrderMargin * kTol * block_sum < 10) {
      EXPECT_GE(block_sum, coupling * (1 - 1e-12)) << "trial " << trial;
    }
    decided_by_blocks += solver::kNaturalOrderMargin * kTol * block_sum < 1;
  }
  std::printf("[          ] block bound decides %d of %d systems (%d with nonsingular blocks)\n", decided_by_blocks,
              systems, nonsingular_blocks);
  // Nonsingular random blocks of unit-order entries: cond_s of B's blocks is far below 1/(M tol)
  // (1.1e12) on all but a handful; a singular block decides nothing.
  EXPECT_GE(decided_by_blocks, 9 * nonsingular_blocks / 10);
  EXPECT_LE(decided_by_blocks, nonsingular_blocks);
}

TEST(ConstraintFactorisation, ScalingTheDirectionsScalesTheMultipliersOnly) {
  // Units: direction j in other units is direction j times c_j, so E -> C E C, r -> C r and
  // ν -> C^-1 ν, with any c_j (not only powers of two). Same decisions; full rank: the same ν to
  // rounding; rank deficient (ν not unique: which of two redundant directions goes is decided by
  // rounding among near-equal ratios): the same residual to the tolerance.
  std::mt19937_64 random(9);
  std::uniform_real_distribution<double> entry(-1, 1), exponent(-6, 6);
  // Full-rank matrices with cond_s > 1e6 are left out (the 1e-9 below is eps 1e6 with a margin):
  // measured 0 of 300; at most 5%.
  test::SkipCount skips("scaled factorisations", 0.05);
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 2 + trial % 5, rank = trial % 3 == 0 ? n - 1 : n;
    const Matrix E = random_energy(random, n, rank);
    if (skips.skip(rank == n && oracle::scaled_condition_number(E) > 1e6, "full rank, cond_s > 1e6")) continue;
    Vector r(n), c(n);
    for (int i = 0; i < n; ++i) r[i] = entry(random), c[i] = std::pow(10.0, exponent(random));
    if (rank < n) r = E * r;  // consistent
    const Matrix E_scaled = c.asDiagonal() * E * c.asDiagonal();
    const Vector r_scaled = c.asDiagonal() * r;
    for (ConstraintFactorisation f : kBoth) {
      const Solved a = solve(E, r, f), b = solve(E_scaled, r_scaled, f);
      EXPECT_EQ(a.dropped, b.dropped) << "trial " << trial;
      if (rank == n)
        EXPECT_LE(multiplier_error(E, c.asDiagonal() * b.nu, a.nu), 1e-9) << "trial " << trial;
      else
        EXPECT_LE(residual(E_scaled, b.nu, r_scaled), 1e-9) << "trial " << trial;
    }
  }
}

TEST(ConstraintFactorisation, SubnormalDiagonalInFloatGivesTheExactMultiplier) {
  // A direction with E_jj = 1e-42 (subnormal in float) decoupled from a unit one; ν = (1, 1)
  // exactly. Without equilibration the threshold tol E_jj underflowed to 0, the subnormal pivot
  // was kept and 1/d overflowed to Inf.
  using MatrixF = solver::ConstraintMatrix<float>;
  using VectorF = solver::ConstraintVector<float>;
  const float tiny = 1e-42f;
  ASSERT_LT(tiny, std::numeric_limits<float>::min());
  MatrixF E(2, 2);
  E << 1, 0, 0, tiny;
  VectorF r(2);
  r << 1, tiny;
  for (ConstraintFactorisation f : kBoth) {
    float dropped = 0;
    const VectorF nu = solver::solve_constraint_multipliers<float>(E, r, f, 1000 * std::numeric_limits<float>::epsilon(),
                                                                   dropped);
    EXPECT_EQ(dropped, 0);
    EXPECT_NEAR(nu[0], 1, f == ConstraintFactorisation::damped ? 1e-3 : 1e-6);
    EXPECT_NEAR(nu[1], 1, f == ConstraintFactorisation::damped ? 1e-3 : 1e-6);
  }
}

TEST(ConstraintFactorisation, EquilibrationScaleIsAnExactPowerOfTwo) {
  for (double x : {1.0, 2.0, 3.9, 4.0, 0.3, 1e-300, 5e-324, 1e300, 123456.0}) {
    const double s = solver::equilibration_scale(x);
    int exponent = 0;
    EXPECT_EQ(std::frexp(s, &exponent), 0.5) << x;  // a power of two
    // s x s, in the solver's order: s² alone overflows for the smallest subnormals (2^1074).
    EXPECT_GE(s * x * s, 1.0) << x;
    EXPECT_LT(s * x * s, 4.0) << x;
  }
  EXPECT_EQ(solver::equilibration_scale(0.0), 0.0);
  EXPECT_EQ(solver::equilibration_scale(-1.0), 0.0);
  EXPECT_EQ(solver::equilibration_scale(std::nan("")), 0.0);
  const float smallest = std::numeric_limits<float>::denorm_min();
  EXPECT_GE(solver::equilibration_scale(smallest) * smallest * solver::equilibration_scale(smallest), 1.0f);
}

// The exponent-field version (float, double) against the definition through ilogb and ldexp, on
// every binade from the smallest subnormal to the largest finite value, each at 1, a random
// mantissa and just below the next power of two, and on 0, negatives, ±Inf and NaN.
template <class T>
void expect_scale_as_defined() {
  const auto defined = [](T x) {
    const int k = x > T(0) ? std::ilogb(x) : 0;
    return x > T(0) ? std::ldexp(T(1), ((k & 1) - k) / 2) : T(0);
  };
  std::mt19937 random(5);
  std::size_t checked = 0;
  for (int e = std::numeric_limits<T>::min_exponent - std::numeric_limits<T>::digits;
       e < std::numeric_limits<T>::max_exponent; ++e) {
    const T binade = std::ldexp(T(1), e);
    const T mantissa = T(1) + std::uniform_real_distribution<T>(T(0), T(1))(random);
    for (T x : {binade, binade * mantissa, std::nextafter(binade * T(2), T(0))}) {
      if (!std::isfinite(x) || x == T(0)) continue;
      EXPECT_EQ(solver::equilibration_scale(x), defined(x)) << x;
      EXPECT_EQ(solver::equilibration_scale(-x), T(0)) << x;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3u * 250u);
  for (T x : {T(0), -T(0), std::numeric_limits<T>::infinity(), -std::numeric_limits<T>::infinity(),
              std::numeric_limits<T>::quiet_NaN()})
    EXPECT_EQ(solver::equilibration_scale(x), defined(x)) << x;
}

TEST(ConstraintFactorisation, EquilibrationScaleFromTheExponentFieldIsTheDefinition) {
  expect_scale_as_defined<double>();
  expect_scale_as_defined<float>();
}

// The generated code cannot include sweepgen's headers, so templates/lanes.mustache carries the
// same lines as solver/scalar_ops.hpp (FloatFormat's, and equilibration_scale's from `using F` to
// the return): they must not drift.
std::vector<std::string> equilibration_lines(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::vector<std::string> lines;
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    const std::size_t text = line.find_first_not_of(' ');
    if (text == std::string::npos) continue;
    line = line.substr(text);
    if (line.rfind("struct FloatFormat {", 0) == 0 || line.rfind("using F = FloatFormat<T>;", 0) == 0) inside = true;
    if (inside) lines.push_back(line);
    if (line == "};") inside = false;
    if (inside && line.rfind("return ((x > T(0))", 0) == 0) break;
  }
  return lines;
}

TEST(ConstraintFactorisation, GeneratedEquilibrationScaleIsTheSolversLineForLine) {
  const auto solver_lines = equilibration_lines(std::string(SWEEPGEN_SOURCE_DIR) + "/generator/solver/scalar_ops.hpp");
  const auto template_lines = equilibration_lines(std::string(SWEEPGEN_SOURCE_DIR) + "/templates/lanes.mustache");
  EXPECT_GE(solver_lines.size(), 16u);
  EXPECT_EQ(solver_lines, template_lines);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

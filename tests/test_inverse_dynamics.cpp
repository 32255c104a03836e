// The reference solver's accelerations and commanded torques against the dense oracle's
// inverse and forward dynamics in long double (generator/oracle/dense_dynamics.hpp):
//   (c) Nc = 0: RNEA(q, q̇, q̈) + d_i q̈_i = τff + Σ J_i^T F_ext,i, rotor inertia on some joints;
//   (d) forward dynamics M^-1 (τcmd + Σ J^T F_ext − b) reproduces q̈ for every policy, while
//       τff + τctrl does not (a trap of docs/derivation.md, section 7): it agrees with τcmd only
//       at the last joint; the saturating policies' τcmd realise their q̈, and exact saturation
//       keeps |τcmd| within the effort limits.
// Cases: the four bundled robots (default tips behind fixed joints, d_i = 0.1 on every other
// joint), 1000 random states each per Nc, and 1000 random chains (tests/support/random_chain.hpp).
#include <gtest/gtest.h>

#include <iostream>

#include "support/oracle_problem.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using test::LongDouble;
using test::Oracle;
using test::OracleVec;

const int kStatesPerRobot = test::state_count(1000);
const int kRandomChains = test::state_count(1000);

// Torque balance ‖RNEA + d q̈ − (τff + Σ J^T F)‖∞ / max(1, ‖τff + Σ J^T F‖∞): the solver's q̈
// comes from a backward-stable recursion, so its torque residual is rounding of the torques
// involved (≤ 1e3 N·m here) times a modest growth; 1e-11 is ~5e4 double ulps.
constexpr double kTorqueBalanceTolerance = 1e-11;
// Forward dynamics of a commanded torque vs the solver's q̈, ‖a−b‖∞ / max(1, ‖b‖∞). τcmd and q̈
// are both computed from the same ν, so E's conditioning cancels; what remains is rounding of
// the torques (including J^T α ν, which grows as E approaches singularity) amplified by M^-1.
// The tolerance therefore scales with the size of the torques relative to q̈'s normalisation:
// kForwardDynamicsTolerance · max(1, ‖τcmd‖∞ · ‖M^-1‖∞ / max(1, ‖q̈‖∞)). On 40000 states the
// worst error was 4.0e-11 where that growth factor gave 1.7e-11 at 1e-12, i.e. 2.4e-12 per unit
// of growth (the articulated recursion and the dense solve round differently along M's
// ill-conditioned directions, which the norm bound does not see); 1e-11 leaves a 4x margin.
constexpr double kForwardDynamicsTolerance = 1e-11;
// The trap: τff + τctrl and τcmd differ "materially" when the gap exceeds this fraction of ‖τcmd‖∞.
constexpr double kMaterialDifference = 1e-3;
// ... and they must do so in at least this share of the constrained states with N >= 2 (they
// can only agree by accident, e.g. a constraint wrench the inner joints do not feel).
constexpr double kTrapShare = 0.9;
// At the last joint they agree: S_N^T Σ_k X_tip^T α_k ν_k, summed as Σ_k (S_N^T F_k) ν_k in τctrl
// (S3, from the rows) and as S_N^T (Σ_k F_k ν_k) in τcmd (T1). Each is a sum of at most 6 Nc
// products, so each is within 6 Nc ε Σ_k ‖F_N,k‖₁ |ν_k| of the exact value: their difference,
// relative to max(1, Σ_k ‖F_N,k‖₁ |ν_k|) (the size of the terms, not of their sum, which can cancel
// near singular states), is within 12 Nc ε ≤ 72 ε = 1.6e-14 (Nc ≤ 6 here).
constexpr double kLastJointFactor = 12;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// Calls fn(case, solver, problem) for kStatesPerRobot states of every bundled robot and one
// state of each of kRandomChains random chains, all with Nc constraints; `floating_bases`: also
// one state of each of kRandomChains random trees on a floating base (F5).
template <class Fn>
void over_cases(std::size_t nc, unsigned seed, double torque_fraction, Fn&& fn, bool floating_bases = false) {
  test::RandomProblem random(seed);
  for (const auto& c : test::bundled_cases(true)) {
    solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
    for (int s = 0; s < kStatesPerRobot; ++s) fn(c, reference, test::draw_problem(random, c, nc, torque_fraction));
  }
  test::RandomChainGenerator generator(seed + 1);
  for (int k = 0; k < kRandomChains; ++k) {
    const test::OracleCase c = test::random_case(generator);
    solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
    fn(c, reference, test::draw_problem(random, c, nc, torque_fraction));
  }
  for (int k = 0; floating_bases && k < kRandomChains; ++k) {
    const test::OracleCase c = test::random_case(generator, false, true);
    solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
    fn(c, reference, test::draw_problem(random, c, nc, torque_fraction));
  }
}

// Forward dynamics of `tau` (double) with the problem's external forces, in long double, and
// the tolerance for comparing it with the solver's q̈.
struct ForwardDynamics {
  OracleVec qdd;
  double tolerance;
};
ForwardDynamics forward_dynamics(const test::OracleCase& c, const test::OracleProblem& p, const Eigen::VectorXd& tau,
                                 const Eigen::VectorXd& qdd_solver) {
  const Oracle o(c.chain, p.base_gravity());
  const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd);
  const auto ext = p.oracle_wrenches(c);
  const Oracle::Mat M = o.mass_matrix(q);
  const Oracle::Mat M_inverse = M.inverse();
  ForwardDynamics fd;
  // (a floating base's six as its spatial acceleration, as the solver's)
  fd.qdd = o.in_solver_coordinates(q, qd, M_inverse * (test::to_long(tau) + o.external_torque(q, ext) - o.bias(q, qd)));
  const LongDouble growth = tau.cwiseAbs().maxCoeff() * M_inverse.cwiseAbs().rowwise().sum().maxCoeff() /
                            std::max<LongDouble>(1, qdd_solver.cwiseAbs().maxCoeff());
  fd.tolerance = kForwardDynamicsTolerance * static_cast<double>(std::max<LongDouble>(1, growth));
  return fd;
}

// ---------------------------------------------------------------------------------------------
// (c) Without constraints the solver's q̈ balances the drivers through inverse dynamics.

TEST(InverseDynamics, RneaOfTheSolvedAccelerationsReproducesTheDrivers) {
  double worst = 0;
  int states = 0, states_with_rotor = 0, rotor_unnoticed = 0;
  over_cases(0, 41, 0.5, [&](const test::OracleCase& c, solver::ReferenceSolver<double>& reference,
                             const test::OracleProblem& p) {
    const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::original);
    const Oracle o(c.chain);
    const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd), qdd = test::to_long(sol.qdd);
    const OracleVec drivers = test::to_long(p.tau_ff) + o.external_torque(q, p.oracle_wrenches(c));
    const OracleVec tau = o.inverse_dynamics(q, qd, qdd);  // includes d_i q̈_i
    const double e = test::relative_error(tau, drivers);
    EXPECT_LE(e, kTorqueBalanceTolerance) << c.name;
    worst = std::max(worst, e);
    ++states;
    // The rotor term is not negligible: without d q̈ the balance fails by exactly d q̈.
    OracleVec rotor = OracleVec::Zero(c.chain.dof());
    for (std::size_t i = 1; i <= c.chain.dof(); ++i) rotor[i - 1] = c.chain.joints[i].rotor_inertia * qdd[i - 1];
    if (rotor.cwiseAbs().maxCoeff() > 1e-3 * std::max<LongDouble>(1, drivers.cwiseAbs().maxCoeff())) {
      ++states_with_rotor;
      if (test::relative_error(OracleVec(tau - rotor), drivers) < 1e-4) ++rotor_unnoticed;
    }
  });
  std::cout << "[inverse dynamics] " << states << " states, max relative torque residual " << worst << "\n";
  RecordProperty("max_torque_residual", std::to_string(worst));
  EXPECT_GT(states_with_rotor, states / 2);
  EXPECT_EQ(rotor_unnoticed, 0);
}

// ---------------------------------------------------------------------------------------------
// (d) Commanded torques.

// τcmd = τff + J^T α ν realises q̈ under Alg. 3 and Alg. 4 (all forces acting on the robot).
TEST(CommandedTorque, ForwardDynamicsOfTheCommandedTorqueReproducesTheAccelerations) {
  double worst = 0;
  int states = 0;
  for (const solver::Policy policy : {solver::Policy::original, solver::Policy::prioritize_external})
    for (std::size_t nc : {0u, 1u, 3u, 6u})
      over_cases(nc, 50 + static_cast<unsigned>(nc), 0.5,
                 [&](const test::OracleCase& c, solver::ReferenceSolver<double>& reference,
                     const test::OracleProblem& p) {
                   const solver::Solution<double>& sol = test::solve(reference, p, policy);
                   const ForwardDynamics fd = forward_dynamics(c, p, sol.tau_cmd, sol.qdd);
                   const double e = test::relative_error(sol.qdd, fd.qdd);
                   EXPECT_LE(e, fd.tolerance) << c.name << " " << solver::name(policy) << " Nc=" << nc;
                   worst = std::max(worst, e / fd.tolerance * kForwardDynamicsTolerance);
                   ++states;
                 }, true);
  std::cout << "[commanded torque] " << states << " states, max relative error of FD(tau_cmd) (normalised) "
            << worst << "\n";
  RecordProperty("max_fd_error", std::to_string(worst));
}

// The trap: τctrl is the constraint's share in the articulated recursion. τff + τctrl equals
// τcmd only at the last joint, and driving the robot with it does not produce q̈.
TEST(CommandedTorque, FeedForwardPlusControlTorqueIsNotTheTorqueThatRealisesTheMotion) {
  int constrained = 0, differ = 0, fd_differs = 0;
  double worst_last = 0;
  for (std::size_t nc : {1u, 3u, 6u})
    over_cases(nc, 60 + static_cast<unsigned>(nc), 0.5,
               [&](const test::OracleCase& c, solver::ReferenceSolver<double>& reference,
                   const test::OracleProblem& p) {
                 const std::size_t n = c.chain.dof();
                 const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::original);
                 const Eigen::VectorXd articulated = p.tau_ff + sol.tau_ctrl;
                 const double scale = std::max(1.0, sol.tau_cmd.cwiseAbs().maxCoeff());
                 double terms = 0;  // Σ_k ‖F_N,k‖₁ |ν_k|
                 for (std::size_t k = 0; k < nc; ++k) {
                   const auto& F = reference.articulated().body[n].constraint_force[k];
                   terms += (F.moment.cwiseAbs().sum() + F.force.cwiseAbs().sum()) * std::abs(sol.nu[k]);
                 }
                 const double last = std::abs(articulated[n - 1] - sol.tau_cmd[n - 1]) / std::max(1.0, terms);
                 EXPECT_LE(last, kLastJointFactor * static_cast<double>(nc) * kEps) << c.name << " Nc=" << nc;
                 worst_last = std::max(worst_last, last);
                 if (n < 2) return;
                 ++constrained;
                 if ((articulated - sol.tau_cmd).head(n - 1).cwiseAbs().maxCoeff() > kMaterialDifference * scale) ++differ;
                 const ForwardDynamics fd = forward_dynamics(c, p, articulated, sol.qdd);
                 if (test::relative_error(sol.qdd, fd.qdd) > kMaterialDifference) ++fd_differs;
               }, true);
  std::cout << "[trap] " << constrained << " constrained states with N >= 2: tau_ff + tau_ctrl differs from tau_cmd in "
            << differ << ", its forward dynamics misses qdd in " << fd_differs
            << "; max relative gap at the last joint " << worst_last << "\n";
  EXPECT_GE(differ, kTrapShare * constrained);
  EXPECT_GE(fd_differs, kTrapShare * constrained);
}

// Eq. 1 as printed: τctrl clamped; τcmd = RNEA(q, q̇, q̈; F_ext) + d q̈ realises its q̈.
TEST(CommandedTorque, SaturatePolicyCommandRealisesItsAccelerations) {
  double worst = 0;
  int saturated = 0, states = 0;
  for (std::size_t nc : {1u, 3u, 6u})
    over_cases(nc, 70 + static_cast<unsigned>(nc), 2.0,
               [&](const test::OracleCase& c, solver::ReferenceSolver<double>& reference,
                   const test::OracleProblem& p) {
                 const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::saturate);
                 const ForwardDynamics fd = forward_dynamics(c, p, sol.tau_cmd, sol.qdd);
                 const double e = test::relative_error(sol.qdd, fd.qdd);
                 EXPECT_LE(e, fd.tolerance) << c.name << " Nc=" << nc;
                 worst = std::max(worst, e / fd.tolerance * kForwardDynamicsTolerance);
                 ++states;
                 if (reference.status() & solver::status_saturated) ++saturated;
               }, true);
  std::cout << "[saturate] " << states << " states (" << saturated << " saturated), max relative error of FD(tau_cmd) "
            << "(normalised) " << worst << "\n";
  EXPECT_GT(saturated, states / 10);  // the clamp is exercised
}

// Exact saturation: τcmd within the effort limits, and forward dynamics with it is q̈.
TEST(CommandedTorque, ExactSaturationStaysWithinTheLimitsAndRealisesItsAccelerations) {
  double worst = 0;
  int saturated = 0, states = 0;
  for (std::size_t nc : {0u, 1u, 3u, 6u})
    over_cases(nc, 80 + static_cast<unsigned>(nc), 2.0,
               [&](const test::OracleCase& c, solver::ReferenceSolver<double>& reference,
                   const test::OracleProblem& p) {
                 const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::saturate_exact);
                 for (std::size_t i = 1; i <= c.chain.dof(); ++i)
                   EXPECT_LE(std::abs(sol.tau_cmd[i - 1]), c.chain.joints[i].effort_limit) << c.name << " joint " << i;
                 const ForwardDynamics fd = forward_dynamics(c, p, sol.tau_cmd, sol.qdd);
                 const double e = test::relative_error(sol.qdd, fd.qdd);
                 EXPECT_LE(e, fd.tolerance) << c.name << " Nc=" << nc;
                 worst = std::max(worst, e / fd.tolerance * kForwardDynamicsTolerance);
                 ++states;
                 if (reference.status() & solver::status_saturated) ++saturated;
               }, true);
  std::cout << "[saturate_exact] " << states << " states (" << saturated
            << " saturated), max relative error of FD(tau_cmd) (normalised) " << worst << "\n";
  EXPECT_GT(saturated, states / 10);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

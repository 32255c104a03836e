// Composition identities of the reference solver (docs/derivation.md, section 9):
// Alg. 1 ≡ Alg. 2 + Alg. 3, Alg. 4's exact relations to Alg. 3, linearity (per-driver
// contributions add up), and re-solving for new setpoints equals a fresh solve.
// Tolerances: these are identities between two double evaluations of the same sums in a
// different order. Rounding in ν is amplified by cond(E^A_cstr,0), so two correct double
// solvers differ by ~10 eps cond times the size of the terms: we allow 1e-10 relative where
// cond <= 1e6 (the bound the dense oracle is judged within, tests/test_dense_oracle.cpp) and 1e-10 * cond / 1e6 beyond.
// Where E^A_cstr,0 is rank deficient (Nc > dof, singular poses) ν is not unique and the
// dropped pivots depend on rounding: there both solves must report the rank deficiency and
// stay finite. 1000 random states per robot and Nc.
#include <gtest/gtest.h>


#include "oracle/condition_number.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"
#include "support/rounding_bound.hpp"
#include "support/skip_count.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::Policy;
using Solver = solver::ReferenceSolver<double>;

const int kStates = test::state_count(1000);  // a tenth in the sanitizer build and in CI
// Sums of the same terms (E_conf, the composed articulated forces) in another order, relative to
// max(1, |sum|): the terms (a track's energy with q̇ up to 2 rad/s, 1e2-1e3 on these arms) cancel
// to a sum of order 1, so a few ulps of the terms is 1e-13..1e-12 of it. Measured worst 2.9e-12
// (UR5, Nc = 1); no condition number enters (no solve): a flat 1e-10, 30x above it.
constexpr double kSumTolerance = 1e-10;
// Two solves of one problem that differ only in the order of their sums: rounding, amplified by
// cond_s(E^A_cstr,0) in ν and all that depends on it, and by the spread of the joints'
// articulated inertias in q̈ (not in cond_s: the wrist of the UR5 near q5 = 0). Measured worst
// error/(eps max(1, cond_s)): 120 (printed as [rounding]); factor 1000. Ceiling 1e-6: states
// with cond_s > 4.5e6 are counted as skipped (their share is asserted), never judged by a looser
// bound.
constexpr test::RoundingBound kRounding{1000, 1e-6};

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  if (a.size() == 0) return 0;
  return (a - b).cwiseAbs().maxCoeff() / std::max(1.0, b.cwiseAbs().maxCoeff());
}

struct Problem {
  Eigen::VectorXd q, qd, tau_a, tau_b;
  spatial::Force<double> push, contact;
  std::vector<spatial::Force<double>> alpha;
  solver::ConstraintVector<double> beta;
};

solver::DriverLayout layout_for(const model::Chain& chain, std::size_t nc, bool composed) {
  solver::DriverLayout layout;
  layout.torques = {"tau_a", "tau_b"};
  layout.external_forces = {{"push", chain.tip_link}, {"contact", chain.bodies[(chain.dof() + 1) / 2].link}};
  layout.constraints = nc;
  composed ? layout.compose_all() : layout.decompose_all();
  return layout;
}

Problem random_problem(test::RandomProblem& random, const model::Chain& chain, std::size_t nc) {
  Problem p{random.positions(chain), random.velocities(chain), random.torques(chain), random.torques(chain, 0.2),
            random.wrench(), random.wrench(), {}, solver::ConstraintVector<double>(nc)};
  for (std::size_t k = 0; k < nc; ++k) {
    p.alpha.push_back(random.unit_direction());
    p.beta[k] = random.uniform(-2, 2);
  }
  return p;
}

// Runs outward + decompose for `p`, each driver scaled by its factor (0 removes it).
void prepare(Solver& s, const Problem& p, double tau_a = 1, double tau_b = 1, double push = 1, double contact = 1,
             bool moving = true) {
  s.outward(p.q, moving ? p.qd : Eigen::VectorXd::Zero(p.qd.size()));
  auto& d = s.drivers();
  d.torques[0] = p.tau_a * tau_a;
  d.torques[1] = p.tau_b * tau_b;
  d.external_forces[0] = p.push * push;
  d.external_forces[1] = p.contact * contact;
  for (std::size_t k = 0; k < p.alpha.size(); ++k) d.constraint_directions[k] = p.alpha[k];
  s.decompose();
}

class Composition : public ::testing::TestWithParam<std::tuple<std::string, std::size_t>> {
 protected:
  void SetUp() override {
    for (const auto& robot : test::bundled_robots())
      if (robot.name == std::get<0>(GetParam())) chain_ = test::load_bundled(robot);
    nc_ = std::get<1>(GetParam());
  }
  // cond_s(E^A_cstr,0) (docs/stability.md): the amplification of rounding in the equilibrated,
  // pivoted solve of ν, whatever the units of each direction.
  double condition_of(const Solver& s) const {
    return oracle::scaled_condition_number(s.articulated().body[0].constraint_energy);
  }
  // States a comparison may skip: with Nc > N the random directions always overdetermine the
  // tip (every state rank-deficient). Six random unit directions, mixing moments and forces, make
  // E^A_cstr,0 ill-conditioned in many random configurations of a 6- or 7-joint arm (measured
  // cond_s > 4.5e6: UR5 46%, iiwa14 22%, Panda 11% of the states): at most 60%. Fewer directions
  // leave it well conditioned almost everywhere (planar, Nc = 3: 1.2%): at most 5%.
  double max_skipped_share() const { return nc_ > chain_.dof() ? 1.0 : nc_ == 6 ? 0.6 : 0.05; }
  // Whether to compare: counts the state as skipped when both solves dropped a pivot or the
  // condition puts it beyond kRounding's ceiling.
  bool compared(test::SkipCount& skips, const Solver& a, const Solver& b) const {
    const bool deficient = both_rank_deficient(a, b);
    const char* reason = deficient ? "both rank-deficient" : "cond beyond the ceiling";
    return !skips.skip(deficient || !kRounding.judged(condition_of(b)), reason);
  }
  // Both rank deficient (then both finite): nothing more to compare.
  static bool both_rank_deficient(const Solver& a, const Solver& b) {
    const bool da = a.status() & solver::status_constraint_rank_deficient;
    const bool db = b.status() & solver::status_constraint_rank_deficient;
    EXPECT_EQ(da, db) << "only one solve dropped a constraint pivot";
    EXPECT_TRUE(a.solution().qdd.allFinite() && b.solution().qdd.allFinite());
    return da && db;
  }
  model::Chain chain_;
  std::size_t nc_ = 0;
};

TEST_P(Composition, ComposedSweepEqualsDecompositionPlusOriginalSolverSweep) {
  test::RandomProblem random(11);
  Solver composed(chain_, layout_for(chain_, nc_, true)), decomposed(chain_, layout_for(chain_, nc_, false));
  test::SkipCount skips("composed vs decomposed", max_skipped_share());
  test::WorstRatio worst("composed vs decomposed");
  for (int n = 0; n < kStates; ++n) {
    const Problem p = random_problem(random, chain_, nc_);
    prepare(composed, p);
    prepare(decomposed, p);
    for (Policy policy : {Policy::original, Policy::saturate, Policy::saturate_exact}) {
      const auto a = composed.solve(policy, p.beta);
      const auto b = decomposed.solve(policy, p.beta);
      if (!compared(skips, composed, decomposed)) continue;
      const double cond = condition_of(decomposed), tol = kRounding(cond);
      worst.add(std::max({relative(a.qdd, b.qdd), relative(a.nu, b.nu), relative(a.tau_cmd, b.tau_cmd)}), cond);
      ASSERT_LE(relative(a.qdd, b.qdd), tol) << solver::name(policy) << " state " << n;
      ASSERT_LE(relative(a.nu, b.nu), tol);
      ASSERT_LE(relative(a.tau_cmd, b.tau_cmd), tol);
    }
    // E_conf of Alg. 1 is the sum of the decomposed tracks' energies at the base, and the
    // composed articulated force at every body the sum of the tracks' forces.
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(nc_);
    for (const auto& track : decomposed.articulated().track) sum += track[0].acceleration_energy;
    ASSERT_LE(relative(composed.articulated().track[0][0].acceleration_energy, sum), kSumTolerance);
    for (std::size_t i = 1; i <= chain_.dof(); ++i) {
      spatial::Force<double> total;
      for (const auto& track : decomposed.articulated().track) total += track[i].articulated_force;
      const auto& f = composed.articulated().track[0][i].articulated_force;
      Eigen::Matrix<double, 6, 1> x, y;
      x << f.moment, f.force;
      y << total.moment, total.force;
      ASSERT_LE(relative(x, y), kSumTolerance) << "body " << i;
    }
  }
}

// Alg. 4: q̈4 = q̈3|F_ext=0 + M^-1 Σ J^T F_ext, ν4 = ν3|F_ext=0, and the constraint residual is
// F_cstr^T J M^-1 Σ J^T F_ext. M^-1 Σ J^T F_ext is the Nc = 0 solve with only the external
// forces acting (no gravity, no velocity, no torques).
TEST_P(Composition, PrioritizedExternalForcesAddTheirFullEffect) {
  test::RandomProblem random(12);
  const solver::DriverLayout layout = layout_for(chain_, nc_, false);
  solver::DriverLayout free_layout = layout_for(chain_, 0, false);
  solver::SolverOptions weightless;
  weightless.gravity.setZero();
  Solver s(chain_, layout), without_external(chain_, layout), external_only(chain_, free_layout, weightless);
  test::SkipCount skips("prioritised external forces", max_skipped_share());
  test::WorstRatio worst("prioritised external forces");
  for (int n = 0; n < kStates; ++n) {
    const Problem p = random_problem(random, chain_, nc_);
    prepare(s, p);
    prepare(without_external, p, 1, 1, 0, 0);
    prepare(external_only, p, 0, 0, 1, 1, false);
    const auto a4 = s.solve(Policy::prioritize_external, p.beta);
    const auto a3 = without_external.solve(Policy::original, p.beta);
    const auto effect = external_only.solve(Policy::original, solver::ConstraintVector<double>(0));
    if (!compared(skips, s, without_external)) continue;
    const double cond = condition_of(s), tol = kRounding(cond);
    worst.add(std::max(relative(a4.qdd, a3.qdd + effect.qdd), relative(a4.nu, a3.nu)), cond);
    ASSERT_LE(relative(a4.qdd, a3.qdd + effect.qdd), tol) << "state " << n;
    ASSERT_LE(relative(a4.nu, a3.nu), tol);
    for (std::size_t k = 0; k < nc_; ++k) {
      const double residual = spatial::dot(p.alpha[k], a4.tip_acceleration) - p.beta[k];
      const double expected = spatial::dot(p.alpha[k], effect.tip_acceleration);
      // Relative to the size of the terms that cancel in the residual.
      const double scale = std::max({1.0, std::abs(p.beta[k]), a4.tip_acceleration.angular.cwiseAbs().maxCoeff(),
                                     a4.tip_acceleration.linear.cwiseAbs().maxCoeff()});
      ASSERT_NEAR(residual, expected, tol * scale);
    }
    // Without external forces Alg. 4 is Alg. 3.
    const auto b4 = without_external.solve(Policy::prioritize_external, p.beta);
    ASSERT_LE(relative(b4.qdd, a3.qdd), tol);
  }
}

// q̈ is affine in the drivers: the increments of each driver instance and of the setpoints
// over the bias-only solve add up to the full solve.
TEST_P(Composition, PerDriverContributionsAddUp) {
  test::RandomProblem random(13);
  const solver::DriverLayout layout = layout_for(chain_, nc_, false);
  Solver full(chain_, layout), part(chain_, layout);
  test::SkipCount skips("per-driver contributions", max_skipped_share());
  test::WorstRatio worst("per-driver contributions");
  for (int n = 0; n < kStates; ++n) {
    const Problem p = random_problem(random, chain_, nc_);
    const solver::ConstraintVector<double> zero = solver::ConstraintVector<double>::Zero(nc_);
    prepare(part, p, 0, 0, 0, 0);
    const Eigen::VectorXd bias = part.solve(Policy::original, zero).qdd;
    Eigen::VectorXd sum = bias + (part.solve(Policy::original, p.beta).qdd - bias);
    const double scales[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    for (const auto& f : scales) {
      prepare(part, p, f[0], f[1], f[2], f[3]);
      sum += part.solve(Policy::original, zero).qdd - bias;
    }
    prepare(full, p);
    const Eigen::VectorXd qdd = full.solve(Policy::original, p.beta).qdd;
    if (!compared(skips, full, part)) continue;
    // The sum carries the rounding of its six solves.
    const double cond = condition_of(full);
    worst.add(relative(qdd, sum) / 6, cond);
    ASSERT_LE(relative(qdd, sum), 6 * kRounding(cond)) << "state " << n;
  }
}

// The sweeps are separately callable: new setpoints or another policy after one decompose
// give exactly (bit for bit) what a fresh outward + decompose + solve gives.
TEST_P(Composition, ResolvingForNewSetpointsEqualsAFreshSolve) {
  test::RandomProblem random(14);
  const solver::DriverLayout layout = layout_for(chain_, nc_, false);
  Solver reused(chain_, layout);
  for (int n = 0; n < kStates / 10; ++n) {
    const Problem p = random_problem(random, chain_, nc_);
    prepare(reused, p);
    for (Policy policy : {Policy::original, Policy::prioritize_external, Policy::saturate, Policy::saturate_exact}) {
      Problem other = p;
      for (std::size_t k = 0; k < nc_; ++k) other.beta[k] = random.uniform(-2, 2);
      const auto again = reused.solve(policy, other.beta);
      Solver fresh(chain_, layout);
      prepare(fresh, other);
      const auto expected = fresh.solve(policy, other.beta);
      ASSERT_EQ(again.qdd, expected.qdd) << solver::name(policy);
      ASSERT_EQ(again.nu, expected.nu);
      ASSERT_EQ(again.tau_cmd, expected.tau_cmd);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(BundledRobots, Composition,
                         ::testing::Combine(::testing::Values("panda", "iiwa14", "ur5", "planar"),
                                            ::testing::Values(0u, 1u, 3u, 6u)),
                         [](const auto& info) {
                           return std::get<0>(info.param) + "_Nc" + std::to_string(std::get<1>(info.param));
                         });

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

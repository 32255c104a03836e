// Bad inputs at run time, reference solver (docs/generated-code.md, "Bad input at run time"): NaN or Inf in
// any input (q, q̇, τff, F_ext, α, E_cstr) raises status_not_finite, a clean problem does not,
// and the flag follows each sweep's own inputs (a clean re-decompose or re-solve clears it).
// A zero constraint direction is a rank-deficient constraint, not a non-finite one. The
// generated code's counterpart is check_bad_inputs in tests/support/generated_check.hpp.
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"

namespace {
namespace SWEEPGEN_TEST_FILE {

using namespace sweepgen;
using solver::status_not_finite;

struct Fixture {
  model::Chain chain = test::load_bundled(test::bundled_robots()[0]);
  solver::DriverLayout layout;
  Eigen::VectorXd q, qd, tau;
  spatial::Force<double> wrench;
  std::vector<spatial::Force<double>> alpha;
  solver::ConstraintVector<double> beta;

  Fixture() {
    layout.torques = {"tau_ff"};
    layout.external_forces = {{"push", "panda_link5"}};
    layout.constraints = 3;
    layout.decompose_all();
    test::RandomProblem random(3);
    q = random.positions(chain);
    qd = random.velocities(chain);
    tau = random.torques(chain, 1.0);
    wrench = random.wrench();
    for (std::size_t k = 0; k < layout.constraints; ++k) alpha.push_back(random.unit_direction());
    beta = solver::ConstraintVector<double>::Constant(3, 0.5);
  }

  // Status of a full solve of every policy; all must agree on the not_finite bit.
  unsigned status(solver::ReferenceSolver<double>& s) const {
    s.outward(q, qd);
    s.drivers().torques[0] = tau;
    s.drivers().external_forces[0] = wrench;
    for (std::size_t k = 0; k < alpha.size(); ++k) s.drivers().constraint_directions[k] = alpha[k];
    s.decompose();
    unsigned first = 0;
    for (auto policy : {solver::Policy::original, solver::Policy::prioritize_external, solver::Policy::saturate,
                        solver::Policy::saturate_exact}) {
      s.solve(policy, beta);
      if (policy == solver::Policy::original) first = s.status() & status_not_finite;
      EXPECT_EQ(s.status() & status_not_finite, first) << solver::name(policy);
    }
    return first;
  }
};

TEST(NonFiniteInputs, EveryInputValueRaisesTheFlag) {
  Fixture clean;
  solver::ReferenceSolver<double> solver(clean.chain, clean.layout);
  ASSERT_EQ(clean.status(solver), 0u);
  // Every scalar input, by name and index, as a setter on a copy of the fixture.
  std::vector<std::pair<std::string, std::function<void(Fixture&, double)>>> inputs;
  for (int i = 0; i < 7; ++i) {
    inputs.push_back({"q[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.q[i] = v; }});
    inputs.push_back({"qd[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.qd[i] = v; }});
    inputs.push_back({"tau_ff[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.tau[i] = v; }});
  }
  for (int i = 0; i < 3; ++i) {
    inputs.push_back({"push.moment[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.wrench.moment[i] = v; }});
    inputs.push_back({"push.force[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.wrench.force[i] = v; }});
    inputs.push_back({"alpha[" + std::to_string(i) + "].force[2]", [i](Fixture& f, double v) { f.alpha[i].force[2] = v; }});
    inputs.push_back({"beta[" + std::to_string(i) + "]", [i](Fixture& f, double v) { f.beta[i] = v; }});
  }
  for (const double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                           -std::numeric_limits<double>::infinity()}) {
    for (const auto& [name, set] : inputs) {
      Fixture f;
      set(f, bad);
      EXPECT_EQ(f.status(solver), status_not_finite) << name << " = " << bad;
    }
  }
}

TEST(NonFiniteInputs, TheFlagFollowsTheLatestInputsOfEachSweep) {
  Fixture f;
  solver::ReferenceSolver<double> solver(f.chain, f.layout);
  f.beta[1] = std::numeric_limits<double>::quiet_NaN();
  ASSERT_EQ(f.status(solver), status_not_finite);
  solver.solve(solver::Policy::original, solver::ConstraintVector<double>::Zero(3));  // re-solve, clean setpoints
  EXPECT_EQ(solver.status() & status_not_finite, 0u);
}

TEST(NonFiniteInputs, AZeroDirectionIsRankDeficientAndFinite) {
  Fixture f;
  f.alpha[1] = spatial::Force<double>::zero();
  solver::ReferenceSolver<double> solver(f.chain, f.layout);
  EXPECT_EQ(f.status(solver), 0u);
  EXPECT_NE(solver.status() & solver::status_constraint_rank_deficient, 0u);
  EXPECT_TRUE(solver.solution().qdd.allFinite());
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

// Generated derivatives (scene key derivatives; docs/derivation.md, (D1)–(D3)): bundled scenes with
// `derivatives: true` are generated, compiled and loaded (report/compiled_solver.hpp), and each
// derivatives_<policy>_flat entry point is compared, value by value and Jacobian entry by entry,
// with the reference solver's own derivatives (solver/solve_derivatives.hpp, itself checked
// against binary128 differences in tests/test_solve_derivatives.cpp). Kinds: a chain with six
// run-time directions under both differentiable policies, six fixed directions, a floating base;
// each with another choice of the Jacobians returned (the scene key's list): all, those of q̈ and
// ν, those of q̈ and τcmd.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "support/compiled_scene.hpp"
#include "support/derivative_case.hpp"
#include "support/rounding_bound.hpp"
#include "support/skip_count.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::Policy;

// |generated − reference| <= bound(κ) · max(1, ‖reference block‖max), κ of test::derivative_condition.
// The two run the same traced operations in the same order but for the trace's constant folding
// (a rounding dropped or moved where a factor is 1 or a term 0) and the compiler's contraction of
// a·b + c into an FMA: each such site perturbs one intermediate by at most one rounding, as each
// of the reference's own operations does, so the difference is at most the reference's own
// rounding bound, which tests/test_solve_derivatives.cpp asserts as 100 ε κ against binary128
// (the same factor here; the solve's generated-vs-reference test, tests/test_emitter.cpp, measured
// its difference at a third of its bound). A dropped or misplaced term is O(1) relative. Ceiling
// as there, the bound at double's domain of validity (κ = 1e8): beyond it a state is counted, not judged.
const test::RoundingBound kBound{100, 100 * std::numeric_limits<double>::epsilon() * test::kDoubleMaxKappa};

// Each costs a compile of its derivative functions, at -O0 (report::Optimisation::checked: the same
// numbers bit for bit as -O2, in seconds instead of a minute or two): a chain with
// run-time directions under both policies, fixed directions, a floating base, a set between two
// links (L4, L5 in D8) and coupled <mimic> joints (q, q̇ columns of the independent joints only).
// (Trees and sets on several links are covered by the reference's own test; the generated code is
// the same trace.)
struct Case {
  const char* scene;
  solver::DerivativeOutputs outputs;  // the Jacobians asked for
};
const Case kScenes[] = {{"panda/panda_nc6.yaml", {true, true, true}},
                        {"iiwa14/iiwa14_lean_nc6_fixed.yaml", {true, true, false}},
                        {"mobile_panda/mobile_panda_hand.yaml", {true, false, true}},
                        {"four_bar/four_bar_loop.yaml", {true, true, true}},
                        {"parallel_gripper/parallel_gripper_pinch.yaml", {true, true, true}}};

// What ctest lists beside the test's name (GetParam() = ...): the scene, not the struct's bytes.
void PrintTo(const Case& c, std::ostream* out) { *out << c.scene; }

std::string test_name(const Case& c) {
  std::string name = c.scene;
  name = name.substr(name.find('/') + 1);
  return name.substr(0, name.find('.'));
}

class GeneratedDerivatives : public ::testing::TestWithParam<Case> {};

TEST_P(GeneratedDerivatives, MatchTheReferenceSolversDerivatives) {
  const std::string relative = GetParam().scene;
  const solver::DerivativeOutputs asked = GetParam().outputs;
  test::SceneCase c = test::load_scene_case(relative);
  // Both differentiable policies on the first scene, the original one on the others (each policy is
  // a compile of its own).
  std::vector<Policy> policies{Policy::original};
  if (relative == kScenes[0].scene) policies.push_back(Policy::prioritize_external);
  c.scene = report::report_scene(c.scene, policies);
  c.scene.scalars = {"double"};  // the derivatives are compared in double
  c.scene.derivatives = true;
  c.scene.derivative_outputs = asked;
  test::TempDir dir;
  const report::CompiledSolver compiled = test::compile_scene(c.scene, c.chain, dir.path());
  ASSERT_EQ(compiled.derivatives_f64_of.size(), policies.size());

  const std::size_t n = c.chain.dof(), nc = c.scene.layout.constraints;
  const auto columns = solver::DerivativeColumns::of(n, nc, c.chain.couplings);
  const std::size_t m = columns.count();
  solver::DerivativeSolver<double> reference(c.chain, c.scene.layout, c.scene.solver_options());
  // 50 states in every build, the sanitizer's too: the compile above is what costs, and the share
  // of skipped states below is judged against the count (a tenth, 5 states, made it noise).
  const auto problems = report::random_problems(c.scene, c.chain, 50, 23);
  // Six random directions at the Panda's hand leave up to a quarter of the states beyond the
  // ceiling (tests/test_solve_derivatives.cpp, kRandomSixDirectionsSkipped); the others none.
  test::SkipCount skips(relative + " generated derivatives", 0.25);
  test::WorstRatio worst(relative + " generated derivatives against the reference's");
  for (const auto& [policy, derivatives] : compiled.derivatives_f64_of) {
    for (const report::Problem& p : problems) {
      // out = [qdd, nu, tau_cmd, d_qdd, d_nu, d_tau_cmd, status] (the header's derivative_flat_out),
      // the Jacobians not asked for left out. One value past the end tells a longer layout.
      constexpr double kPastTheEnd = -12345.5;
      std::vector<double> out(asked.flat_out_size(columns) + 1, kPastTheEnd);
      derivatives(p.flat.data(), out.data());
      ASSERT_EQ(out.back(), kPastTheEnd) << "the flat output is longer than the layout asked for";
      out.pop_back();
      const solver::SolveDerivatives<double> d = reference.solve(p, policy);
      const std::string where = relative + " " + solver::name(policy);
      ASSERT_EQ(static_cast<unsigned>(out.back()), d.status) << where;
      const double kappa = test::derivative_condition(c, p);
      if (skips.skip(d.status != solver::status_ok || !kBound.judged(kappa), "status raised or kappa beyond the ceiling"))
        continue;
      const Eigen::Map<const Eigen::VectorXd> flat(out.data(), static_cast<Eigen::Index>(out.size()));
      const auto rows = [](std::size_t r) { return static_cast<Eigen::Index>(r); };
      Eigen::Index at = 0;
      const auto next = [&](std::size_t size) {
        const Eigen::VectorXd v = flat.segment(at, rows(size));
        at += rows(size);
        return v;
      };
      const Eigen::VectorXd qdd = next(n), nu = next(nc), tau_cmd = next(n);
      const auto jacobian = [&](std::size_t r) {
        const Eigen::VectorXd v = next(r * m);
        return Eigen::MatrixXd(Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            v.data(), rows(r), rows(m)));
      };
      // The Jacobians asked for, in the layout's order; the reference computes all three.
      const Eigen::MatrixXd d_qdd = asked.qdd ? jacobian(n) : Eigen::MatrixXd(),
                            d_nu = asked.nu ? jacobian(nc) : Eigen::MatrixXd(),
                            d_tau_cmd = asked.tau_cmd ? jacobian(n) : Eigen::MatrixXd();
      ASSERT_EQ(at + 1, flat.size()) << where << ": the layout ends with the status";
      const std::pair<Eigen::MatrixXd, Eigen::MatrixXd> pairs[] = {
          {qdd, d.qdd}, {nu, d.nu}, {tau_cmd, d.tau_cmd}, {d_qdd, test::stacked(d.d_qdd)}, {d_nu, test::stacked(d.d_nu)},
          {d_tau_cmd, test::stacked(d.d_tau_cmd)}};
      const bool returned[] = {true, true, true, asked.qdd, asked.nu, asked.tau_cmd};
      const char* names[] = {"qdd", "nu", "tau_cmd", "d_qdd", "d_nu", "d_tau_cmd"};
      for (int k = 0; k < 6; ++k) {
        const auto& [generated, theirs] = pairs[k];
        if (theirs.size() == 0 || !returned[k]) continue;
        const double scale = std::max(1.0, theirs.cwiseAbs().maxCoeff());
        Eigen::Index r = 0, j = 0;
        const double error = (generated - theirs).cwiseAbs().maxCoeff(&r, &j) / scale;
        worst.add(error, kappa);
        EXPECT_LE(error, kBound(kappa)) << where << " " << names[k] << " (" << r << ", " << j << "): " << generated(r, j)
                                        << " vs " << theirs(r, j) << ", kappa " << kappa;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, GeneratedDerivatives, ::testing::ValuesIn(kScenes),
                         [](const auto& info) { return test_name(info.param); });

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// The quad (IEEE binary128) scalar of the stability suite's referee (solver/quad_scalar.hpp):
// its arithmetic and functions are right, the reference solver in quad agrees with long double
// and double where those are accurate, and it is wider: where long double loses digits, quad
// does not (docs/stability.md).
#include <gtest/gtest.h>

#include <cmath>

#include "report/extreme_states.hpp"
#include "report/stability_cases.hpp"
#include "report/stability_errors.hpp"
#include "solver/quad_scalar.hpp"
#include "solver/reference_solver.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::Quad;

TEST(QuadScalar, ArithmeticAndFunctions) {
  EXPECT_EQ(std::numeric_limits<Quad>::digits, 113);
  EXPECT_EQ(std::numeric_limits<Quad>::epsilon(), Quad(std::ldexp(1.0, -112)));
  EXPECT_NE(Quad(1) + Quad(std::ldexp(1.0, -100)), Quad(1));  // 2^-100 is below long double's resolution
  EXPECT_EQ(static_cast<long double>(Quad(1) + Quad(std::ldexp(1.0, -100))), 1.0L);
  const Quad two(2);
  EXPECT_LE(abs(sqrt(two) * sqrt(two) - two), Quad(4) * std::numeric_limits<Quad>::epsilon());
  // sin(π/6) = 1/2 and cos(π/3) = 1/2, with π to 36 digits (3.14159265358979323846264338327950288).
  const Quad pi = Quad(3.141592653589793) + Quad(1.2246467991473532e-16);  // π to ~1e-32
  EXPECT_LE(abs(sin(pi / Quad(6)) - Quad(0.5)), Quad(1e-31));
  EXPECT_LE(abs(cos(pi / Quad(3)) - Quad(0.5)), Quad(1e-31));
  EXPECT_TRUE(isfinite(Quad(1)));
  EXPECT_FALSE(isfinite(std::numeric_limits<Quad>::infinity()));
  EXPECT_TRUE(isnan(std::numeric_limits<Quad>::quiet_NaN()));
}

// The solver in quad, long double and double on a state of the arm.
struct Answers {
  report::Problem problem;
  std::vector<Quad> quad, quad_permuted;
  Eigen::VectorXd in_double;
  std::vector<long double> in_long_double;
};

template <class Scalar>
std::vector<Scalar> solve(const report::StabilityCase& c, const report::Problem& p, bool reverse_directions = false) {
  solver::SolverOptions options = c.scene.solver_options();
  options.pivot_tolerance = 1e-40;  // keep every direction in every scalar: compare one problem
  // Without the refinement (R1): the referee must judge unrefined solves too (a scene option),
  // and this is where a scalar's own rounding shows most.
  options.refinement = false;
  solver::ReferenceSolver<Scalar> s(c.chain, c.scene.layout, options);
  s.outward(p.q.cast<Scalar>(), p.qd.cast<Scalar>());
  auto& d = s.drivers();
  for (std::size_t t = 0; t < p.torques.size(); ++t) d.torques[t] = p.torques[t].cast<Scalar>();
  for (std::size_t e = 0; e < p.wrenches.size(); ++e)
    d.external_forces[e] = {p.wrenches[e].moment.cast<Scalar>(), p.wrenches[e].force.cast<Scalar>()};
  const std::size_t nc = p.alpha.size();
  solver::ConstraintVector<Scalar> beta(static_cast<Eigen::Index>(nc));
  for (std::size_t k = 0; k < nc; ++k) {
    const std::size_t from = reverse_directions ? nc - 1 - k : k;
    d.constraint_directions[k] = {p.alpha[from].moment.cast<Scalar>(), p.alpha[from].force.cast<Scalar>()};
    beta[static_cast<Eigen::Index>(k)] = Scalar(p.beta[static_cast<Eigen::Index>(from)]);
  }
  s.decompose();
  const auto& r = s.solve(solver::Policy::original, beta);
  return std::vector<Scalar>(r.qdd.data(), r.qdd.data() + r.qdd.size());
}

template <class Scalar>
double error(const std::vector<Scalar>& a, const std::vector<Quad>& b) {
  return report::vector_relative_error(std::vector<Quad>(a.begin(), a.end()), b);
}

TEST(QuadScalar, AgreesWhereEasyAndIsWiderWhereNot) {
  test::TempDir dir;
  const report::StabilityCase c = report::family_stability_case("arm", dir.path());
  const auto states = report::extreme_states(c.scene, c.chain, 1, c.singular_q, 3);
  for (const auto& state : states) {
    if (state.kind != "nominal" && !(state.kind == "near_singular" && state.delta == 1e-6)) continue;
    // δ = 1e-6 from the stretched, wrist-aligned singularity: cond_s(E) ~ 1e8.
    const auto quad = solve<Quad>(c, state.problem);
    const auto permuted = solve<Quad>(c, state.problem, true);  // another rounding path, the same exact answer
    const double e_double = error(solve<double>(c, state.problem), quad);
    const double e_long = error(solve<long double>(c, state.problem), quad);
    const double e_quad = error(permuted, quad);
    std::printf("[quad] arm %s: qdd error vs quad: double %.2e, long double %.2e, quad (directions reversed) %.2e\n",
                state.kind.c_str(), e_double, e_long, e_quad);
    // Where double is accurate (q̈ to ~1e-10 here), all three agree to their own precision.
    EXPECT_LE(e_double, 1e-9);
    EXPECT_LE(e_long, 1e-12);
    // The errors are rounding, measured by a referee far finer than both: they scale with the
    // scalar's eps (eps_double / eps_long_double = 2048; allowed 100..1e5), and long double
    // itself is off by far more than its eps (1.1e-19): it could not referee double here.
    EXPECT_GE(e_double, 100 * e_long);
    EXPECT_LE(e_double, 1e5 * e_long);
    EXPECT_GE(e_long, 1e3 * std::numeric_limits<long double>::epsilon());
    EXPECT_LE(e_quad, 1e-10 * e_long);  // quad's own rounding: 1e10 below long double's
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// The reference solver runs in float, double and long double from the same templates; each
// agrees with long double to its own precision. Tolerances: relative error of q̈ below
// 50 eps(Scalar) cond(E^A_cstr,0), floored at 1e-3 for float (eps 1.2e-7 times the spread of
// the articulated inertias, ~1e3 on the Panda) and 1e-12 for double, on 1000 states with Nc = 3.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "oracle/condition_number.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

template <class Scalar>
Eigen::VectorXd solve_in(const model::Chain& chain, const solver::DriverLayout& layout, const Eigen::VectorXd& q,
                         const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                         const std::vector<spatial::Force<double>>& alpha, const Eigen::VectorXd& beta,
                         solver::ConstraintMatrix<double>* energy = nullptr) {
  solver::ReferenceSolver<Scalar> s(chain, layout);
  s.outward(q.cast<Scalar>(), qd.cast<Scalar>());
  s.drivers().torques[0] = tau.cast<Scalar>();
  for (std::size_t k = 0; k < alpha.size(); ++k)
    s.drivers().constraint_directions[k] = {alpha[k].moment.cast<Scalar>(), alpha[k].force.cast<Scalar>()};
  s.decompose();
  const auto& sol = s.solve(solver::Policy::original, solver::ConstraintVector<Scalar>(beta.cast<Scalar>()));
  if (energy) *energy = s.articulated().body[0].constraint_energy.template cast<double>();
  return sol.qdd.template cast<double>();
}

TEST(ScalarTypes, FloatDoubleAndLongDoubleAgreeToTheirPrecision) {
  const model::Chain chain = test::load_bundled(test::bundled_robots().front());
  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  layout.constraints = 3;
  layout.decompose_all();
  test::RandomProblem random(3);
  double worst_float = 0, worst_double = 0;
  for (int n = 0; n < 1000; ++n) {
    const Eigen::VectorXd q = random.positions(chain), qd = random.velocities(chain), tau = random.torques(chain);
    std::vector<spatial::Force<double>> alpha;
    for (int k = 0; k < 3; ++k) alpha.push_back(random.unit_direction());
    const Eigen::VectorXd beta = Eigen::VectorXd::Random(3);
    solver::ConstraintMatrix<double> E;
    const Eigen::VectorXd exact = solve_in<long double>(chain, layout, q, qd, tau, alpha, beta, &E);
    const double cond = oracle::condition_number(Eigen::MatrixXd(E));
    const double scale = std::max(1.0, exact.cwiseAbs().maxCoeff());
    const double e_float = (solve_in<float>(chain, layout, q, qd, tau, alpha, beta) - exact).cwiseAbs().maxCoeff() / scale;
    const double e_double = (solve_in<double>(chain, layout, q, qd, tau, alpha, beta) - exact).cwiseAbs().maxCoeff() / scale;
    ASSERT_LE(e_float, std::max(1e-3, 50 * 1.2e-7 * cond)) << "state " << n << " cond " << cond;
    ASSERT_LE(e_double, std::max(1e-12, 50 * 2.2e-16 * cond)) << "state " << n << " cond " << cond;
    worst_float = std::max(worst_float, e_float);
    worst_double = std::max(worst_double, e_double);
  }
  std::cout << "ReferenceSolver vs long double, Panda Nc=3: max relative q̈ error float " << worst_float << ", double "
            << worst_double << "\n";
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

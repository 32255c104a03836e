// The generated-scene checks that need no generated type, compiled once for double and float
// (generated_check.hpp).
#include "support/generated_check.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "report/relative_error.hpp"
#include "solver/reference_solver.hpp"
#include "support/flat_problem.hpp"

namespace sweepgen::test {
namespace {

inline double condition_number(const solver::ConstraintMatrix<long double>& E) {
  if (E.rows() == 0) return 1;
  const Eigen::MatrixXd Ed = E.cast<double>();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(Ed).singularValues();
  return sv(sv.size() - 1) > 0 ? sv(0) / sv(sv.size() - 1) : std::numeric_limits<double>::infinity();
}

}  // namespace

// Compares every flat solve of the variant with ReferenceSolver<long double> on `states` random
// problems. The relative error of q̈, τcmd and ν must stay below
//     max(floor, eps_multiple * eps * cond(E^A_cstr,0)):
// a fixed floor where the constraint is well conditioned, growing with the condition number
// beyond, since rounding in ν is amplified by it in any solver of that precision. Where the
// reference drops a constraint pivot the generated solve must report
// constraint_rank_deficient too (the dropped direction makes ν non-unique) and stay finite.
template <class Scalar>
ErrorSummary check_against_reference(const FlatVariant<Scalar>& variant, const std::string& scene_path, int states,
                                     long double floor, long double eps_multiple, unsigned seed) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  solver::SolverOptions options = s.solver_options();
  // The generated code's pivot tolerance, so both make the same rank decisions.
  options.pivot_tolerance = options.pivot_tolerance_for(std::numeric_limits<Scalar>::epsilon());
  solver::ReferenceSolver<long double> reference(chain, s.layout, options);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const solver::FlatLayout layout = s.flat_layout(chain.dof());
  EXPECT_EQ(variant.out_size, layout.out_size());

  RandomProblem random(seed);
  ErrorSummary summary;
  std::vector<Scalar> in(variant.in_size), out(variant.out_size);
  for (int state = 0; state < states; ++state) {
    const FlatProblem p = random_flat_problem(random, s, chain);
    EXPECT_EQ(p.in.size(), variant.in_size);
    for (std::size_t i = 0; i < p.in.size(); ++i) in[i] = static_cast<Scalar>(p.in[i]);

    const solver::SolveInputs<long double> problem = p.cast<long double>();
    reference.prepare(problem);
    const double cond = condition_number(reference.articulated().body[0].constraint_energy);
    const long double eps = std::numeric_limits<Scalar>::epsilon();
    const long double allowed = std::max(floor, eps_multiple * eps * static_cast<long double>(cond));
    ++summary.states;
    if (cond > 1e6) ++summary.ill_conditioned;

    for (const auto& entry : variant.solves) {
      const auto policy = *solver::policy_from_name(entry.policy);
      entry.solve(in.data(), out.data());
      const auto& r = reference.solve(policy, problem.beta);
      const unsigned status = static_cast<unsigned>(out[layout.status()]);
      for (Scalar v : out) EXPECT_TRUE(std::isfinite(v)) << entry.policy << " state " << state;
      const bool reference_dropped = reference.status() & solver::status_constraint_rank_deficient;
      const bool generated_dropped = status & solver::status_constraint_rank_deficient;
      if (reference_dropped != generated_dropped) {
        // Rounding may flip a pivot that sits at the tolerance; a kept pivot has
        // d_k / E_kk >= 1 / cond, so that can only happen where cond * tolerance is near 1.
        ++summary.borderline;
        EXPECT_GE(cond * options.pivot_tolerance, 0.1)
            << entry.policy << " state " << state << ": rank decisions differ on a well-conditioned constraint";
        continue;
      }
      if (reference_dropped) {
        ++summary.rank_deficient;
        continue;
      }
      const auto slice = [&](std::size_t offset, std::size_t count) {
        return std::vector<long double>(out.begin() + offset, out.begin() + offset + count);
      };
      const auto vec = [](const auto& v) { return std::vector<long double>(v.data(), v.data() + v.size()); };
      const long double e_qdd = report::relative_error<long double>(slice(layout.qdd(), n), vec(r.qdd));
      const long double e_tau = report::relative_error<long double>(slice(layout.tau_cmd(), n), vec(r.tau_cmd));
      const long double e_nu = report::relative_error<long double>(slice(layout.nu(), nc), vec(r.nu));
      if (cond <= 1e6) {
        summary.qdd = std::max(summary.qdd, e_qdd);
        summary.tau_cmd = std::max(summary.tau_cmd, e_tau);
        summary.nu = std::max(summary.nu, e_nu);
      }
      summary.worst_ratio = std::max(summary.worst_ratio, std::max({e_qdd, e_tau, e_nu}) / allowed);
      EXPECT_LE(e_qdd, allowed) << entry.policy << " state " << state << " cond " << cond;
      EXPECT_LE(e_tau, allowed) << entry.policy << " state " << state << " cond " << cond;
      EXPECT_LE(e_nu, allowed) << entry.policy << " state " << state << " cond " << cond;
      if (::testing::Test::HasFailure()) return summary;
    }
  }
  std::cout << scene_path.substr(scene_path.find_last_of('/') + 1) << " " << (sizeof(Scalar) == 8 ? "double" : "float")
            << ": max relative error (cond <= 1e6) qdd " << static_cast<double>(summary.qdd) << ", tau_cmd "
            << static_cast<double>(summary.tau_cmd) << ", nu " << static_cast<double>(summary.nu) << "; states "
            << summary.states << ", cond > 1e6: " << summary.ill_conditioned
            << ", rank-deficient solves: " << summary.rank_deficient << " (+" << summary.borderline << " at the tolerance)"
            << ", worst error/tolerance " << static_cast<double>(summary.worst_ratio) << "\n";
  return summary;
}

// Bad inputs at run time (README, "Generated code"): on a random problem of the scene,
//  - NaN and +Inf written into any one flat input value make every flat solve raise
//    status_not_finite (when the scene checks inputs; `checks_inputs` is the generated
//    header's constant), and the clean problem does not;
//  - a zero constraint direction alpha_k raises status_constraint_rank_deficient with finite
//    results (the direction is not enforced);
//  - a non-unit direction is a valid input: alpha_k and beta_k scaled by the same factor give
//    the same q̈ (the constraint alpha_k^T Ẍ = beta_k is unchanged), to rounding.
template <class Scalar>
void check_bad_inputs(const FlatVariant<Scalar>& variant, const std::string& scene_path, bool checks_inputs,
                      unsigned not_finite_bit) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const solver::FlatLayout layout = s.flat_layout(chain.dof());
  const std::size_t status_at = layout.status();
  RandomProblem random(5);
  const FlatProblem p = random_flat_problem(random, s, chain);
  const std::vector<Scalar> clean(p.in.begin(), p.in.end());
  std::vector<Scalar> in = clean, out(variant.out_size);
  const auto status_of = [&](const auto& entry) {
    entry.solve(in.data(), out.data());
    return static_cast<unsigned>(out[status_at]);
  };
  for (const auto& entry : variant.solves) EXPECT_EQ(status_of(entry) & not_finite_bit, 0u) << entry.policy;
  if (checks_inputs) {
    for (const Scalar bad : {std::numeric_limits<Scalar>::quiet_NaN(), std::numeric_limits<Scalar>::infinity()}) {
      for (std::size_t i = 0; i < in.size(); ++i) {
        in = clean;
        in[i] = bad;
        for (const auto& entry : variant.solves)
          EXPECT_NE(status_of(entry) & not_finite_bit, 0u) << entry.policy << ": " << bad << " at flat input " << i;
      }
    }
  }
  if (nc == 0 || !s.fixed_directions.empty()) return;  // alpha is not a run-time input
  const std::size_t alpha_at = layout.alpha(0);
  for (std::size_t k = 0; k < nc; ++k) {
    in = clean;
    for (std::size_t i = 0; i < 6; ++i) in[alpha_at + 6 * k + i] = 0;
    for (const auto& entry : variant.solves) {
      EXPECT_NE(status_of(entry) & solver::status_constraint_rank_deficient, 0u) << entry.policy << " alpha_" << k << " = 0";
      for (Scalar v : out) EXPECT_TRUE(std::isfinite(v)) << entry.policy << " alpha_" << k << " = 0";
    }
  }
  std::vector<Scalar> unit_qdd(n);
  for (const auto& entry : variant.solves) {
    in = clean;
    if (status_of(entry) != 0) continue;  // saturation or a dropped pivot: compare only plain solves
    std::copy(out.begin(), out.begin() + n, unit_qdd.begin());
    const Scalar scale = Scalar(64);
    for (std::size_t k = 0; k < nc; ++k) {
      for (std::size_t i = 0; i < 6; ++i) in[alpha_at + 6 * k + i] *= scale;
      in[layout.beta() + k] *= scale;
    }
    EXPECT_EQ(status_of(entry), 0u) << entry.policy;
    const long double e = report::relative_error<long double>(std::vector<long double>(out.begin(), out.begin() + n),
                                         std::vector<long double>(unit_qdd.begin(), unit_qdd.end()));
    EXPECT_LE(e, 1e4L * std::numeric_limits<Scalar>::epsilon()) << entry.policy << ": alpha and beta scaled by 64";
  }
}

ResolveProblems resolve_problems(const std::string& scene_path, int states) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  ResolveProblems p;
  p.layout = s.flat_layout(chain.dof());
  RandomProblem random(99);
  for (int state = 0; state < states; ++state) {
    p.in.push_back(random_flat_problem(random, s, chain).in);
    std::vector<double> beta1(p.layout.constraints + 1);
    for (auto& b : beta1) b = random.uniform(-1, 1);
    p.first_beta.push_back(std::move(beta1));
  }
  return p;
}

template ErrorSummary check_against_reference<double>(const FlatVariant<double>&, const std::string&, int, long double,
                                                      long double, unsigned);
template ErrorSummary check_against_reference<float>(const FlatVariant<float>&, const std::string&, int, long double,
                                                     long double, unsigned);
template void check_bad_inputs<double>(const FlatVariant<double>&, const std::string&, bool, unsigned);
template void check_bad_inputs<float>(const FlatVariant<float>&, const std::string&, bool, unsigned);

}  // namespace sweepgen::test

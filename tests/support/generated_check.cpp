// The generated-scene checks that need no generated type, compiled once for double and float
// (generated_check.hpp).
#include "support/generated_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "oracle/condition_number.hpp"
#include "report/measure.hpp"
#include "oracle/relative_error.hpp"
#include "report/stability_errors.hpp"
#include "solver/reference_solver.hpp"
#include "support/flat_problem.hpp"
#include "support/run_command.hpp"
#include "support/skip_count.hpp"

namespace sweepgen::test {
namespace {

// κ = max(1, cond_s(E^A_cstr,0), 1 / min_i ρ_i) of the state prepared in `reference`
// (report/stability_errors.hpp, docs/stability.md): the amplification of rounding any solver of
// a given precision suffers on it.
double kappa(const solver::ReferenceSolver<long double>& reference) {
  return report::kappa(oracle::scaled_condition_number(reference.articulated().body[0].constraint_energy),
                       static_cast<double>(solver::min_relative_joint_inertia(reference.model(), reference.articulated())));
}

}  // namespace

// Per state and flat solve (generated_check.hpp): the generated solve against
//  (1) ReferenceSolver<Scalar>, the operations it was traced from (the rows formed as the generator
//      chose, I2 or I6): they differ by constant folding
//      and the compiler's order only, so by a few roundings amplified like any rounding:
//      ≤ kSameOperations eps κ;
//  (2) ReferenceSolver<long double>, the answer: ≤ domain.accuracy eps κ (a sanity bound: the
//      stability suite judges the same operations against binary128 with scale-aware errors).
// Both inside the scalar's domain, κ ≤ domain.max_kappa; states beyond it are counted (their
// share asserted), not judged by a tolerance that would keep growing. Where the reference drops a
// constraint pivot the generated solve must report constraint_rank_deficient too (the dropped
// direction makes ν non-unique) and stay finite.
template <class Scalar>
ErrorSummary check_against_reference(const FlatVariant<Scalar>& variant, const std::string& scene_path, int states,
                                     const Domain& domain, unsigned seed) {
  // (1) in double: measured worst 1.1 eps κ over the bundled scenes (printed as "same
  // operations"); 40 as in tests/test_emitter.cpp (kEmittedErrorFactor, where FMA contraction
  // adds to the folding: 13.5 measured there). In float the generated code's constants (the
  // robot's transforms and inertias, folded in double and rounded once) are more accurate than
  // the float reference's, computed in float from the rounded model: the two differ by the float
  // reference's own error: measured worst 166 eps κ (planar_nc2, its prismatic joint), factor
  // 1000 (ceiling inside float's domain κ ≤ 1e3: 0.12; measured differences ≤ 5.5e-5).
  const long double kSameOperations = sizeof(Scalar) == sizeof(double) ? 40 : 1000;
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  solver::SolverOptions options = s.solver_options();
  // The generated code's tolerances, so that the answer makes the same rank decisions.
  options.pivot_tolerance = options.pivot_tolerance_for(std::numeric_limits<Scalar>::epsilon());
  options.joint_inertia_tolerance = options.joint_inertia_tolerance_for(std::numeric_limits<Scalar>::epsilon());
  solver::ReferenceSolver<long double> reference(chain, s.layout, options);
  solver::SolverOptions traced_options = s.solver_options();  // as the generator formed the rows
  traced_options.constraint_rows =
      variant.outward_rows ? solver::ConstraintRows::outward_rows : solver::ConstraintRows::inward_columns;
  solver::ReferenceSolver<Scalar> traced(chain, s.layout, traced_options);
  const std::size_t n = chain.dof(), nc = s.layout.constraints;
  const solver::FlatLayout layout = s.flat_layout(chain);
  EXPECT_EQ(variant.out_size, layout.out_size());
  const long double eps = std::numeric_limits<Scalar>::epsilon();
  const std::string name = scene_path.substr(scene_path.find_last_of('/') + 1) +
                           (sizeof(Scalar) == 8 ? " double" : " float");
  SkipCount outside(name + ": states with kappa > " + std::to_string(static_cast<int>(domain.max_kappa)),
                    domain.max_outside_share);

  RandomProblem random(seed);
  ErrorSummary summary;
  std::vector<Scalar> in(variant.in_size), out(variant.out_size);
  for (int state = 0; state < states; ++state) {
    const FlatProblem p = random_flat_problem(random, s, chain);
    EXPECT_EQ(p.in.size(), variant.in_size);
    for (std::size_t i = 0; i < p.in.size(); ++i) in[i] = static_cast<Scalar>(p.in[i]);

    const solver::SolveInputs<long double> problem = p.cast<long double>();
    reference.prepare(problem);
    traced.prepare(p.cast<Scalar>());
    const double k = kappa(reference);
    ++summary.states;
    // Outside the domain the solves still run and must stay finite and make the reference's rank
    // decisions; only their errors are not judged.
    const bool inside = !outside.skip(!(k <= domain.max_kappa), "outside the domain");
    const long double same_allowed = kSameOperations * eps * k, accuracy_allowed = domain.accuracy * eps * k;

    for (const auto& entry : variant.solves) {
      const auto policy = *solver::policy_from_name(entry.policy);
      entry.solve(in.data(), out.data());
      const auto& r = reference.solve(policy, problem.beta);
      const auto& t = traced.solve(policy, p.beta.template cast<Scalar>());
      const unsigned status = static_cast<unsigned>(out[layout.status()]);
      for (Scalar v : out) EXPECT_TRUE(std::isfinite(v)) << entry.policy << " state " << state;
      const bool reference_dropped = reference.status() & solver::status_constraint_rank_deficient;
      const bool generated_dropped = status & solver::status_constraint_rank_deficient;
      if (reference_dropped != generated_dropped) {
        // Rounding may flip a pivot that sits at the tolerance; a kept pivot has
        // d_k / E_kk >= 1 / cond, so that can only happen where cond * tolerance is near 1.
        ++summary.borderline;
        EXPECT_GE(k * options.pivot_tolerance, 0.1)
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
      const auto error = [&](const auto& answer) {  // of the results the scene returns (scene key outputs)
        long double e = 0;
        if (layout.outputs.qdd) e = std::max(e, oracle::relative_error<long double>(slice(layout.qdd(), n), vec(answer.qdd)));
        if (layout.outputs.tau_cmd)
          e = std::max(e, oracle::relative_error<long double>(slice(layout.tau_cmd(), n), vec(answer.tau_cmd)));
        const auto couplings = static_cast<Eigen::Index>(layout.couplings.size());
        if (layout.outputs.nu)
          e = std::max(e, oracle::relative_error<long double>(slice(layout.nu(), nc), vec(answer.nu.head(answer.nu.size() - couplings))));
        if (layout.outputs.coupling_torque && couplings > 0)  // the couplings' ν (M2)
          e = std::max(e, oracle::relative_error<long double>(slice(layout.coupling_torque(), layout.couplings.size()),
                                                              vec(answer.nu.tail(couplings))));
        return e;
      };
      if (!inside) continue;
      const long double e_same = error(t), e_accuracy = error(r);
      // κ leaves out cond(M(q)): q̈ near a wrist singularity of the UR5 is large and its rounding
      // with it. Where an error exceeds eps κ times its factor, the state's κ is widened by
      // cond(M) (report::inertia_condition_number, binary128, n + 1 solves: only for those
      // states). The same-operations difference too: the refinement (R1) feeds the first pass's
      // Ẍ_tip, whose rounding grows with q̈, through E^-1 into ν.
      double k_accuracy = k;
      if (e_accuracy > accuracy_allowed || e_same > same_allowed)
        k_accuracy = std::max(k, report::inertia_condition_number(chain, problem.q.cast<report::Precise>(), options));
      const double k_same = e_same > same_allowed ? k_accuracy : k;
      summary.same_operations = std::max(summary.same_operations, e_same / (eps * k_same));
      summary.accuracy = std::max(summary.accuracy, e_accuracy / (eps * k_accuracy));
      summary.largest_difference = std::max(summary.largest_difference, e_same);
      summary.largest_error = std::max(summary.largest_error, e_accuracy);
      EXPECT_LE(e_same, kSameOperations * eps * k_same)
          << entry.policy << " state " << state << " kappa " << k << ", with cond(M) " << k_same;
      EXPECT_LE(e_accuracy, domain.accuracy * eps * k_accuracy)
          << entry.policy << " state " << state << " kappa " << k << ", with cond(M) " << k_accuracy;
      if (::testing::Test::HasFailure()) return summary;
    }
  }
  std::cout << name << ": " << summary.states << " states, " << outside.skipped() << " with kappa > "
            << domain.max_kappa << "; inside: max difference from ReferenceSolver<" << (sizeof(Scalar) == 8 ? "double" : "float")
            << "> " << static_cast<double>(summary.largest_difference) << " (same operations: max "
            << static_cast<double>(summary.same_operations) << " eps kappa, allowed " << static_cast<double>(kSameOperations)
            << "), max error against long double " << static_cast<double>(summary.largest_error) << ", "
            << static_cast<double>(summary.accuracy) << " eps kappa (allowed "
            << static_cast<double>(domain.accuracy) << "); rank-deficient solves: " << summary.rank_deficient << " (+"
            << summary.borderline << " at the tolerance)\n";
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
  const std::size_t n = chain.dof();
  const solver::FlatLayout layout = s.flat_layout(chain);
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
  if (layout.input_directions.empty()) return;  // alpha is not a run-time input
  // A run-time direction set to 0 drops its pivot.
  for (std::size_t j = 0; j < layout.input_directions.size(); ++j) {
    const std::size_t k = layout.input_directions[j];
    in = clean;
    for (std::size_t i = 0; i < 6; ++i) in[layout.alpha(j) + i] = 0;
    for (const auto& entry : variant.solves) {
      EXPECT_NE(status_of(entry) & solver::status_constraint_rank_deficient, 0u) << entry.policy << " alpha_" << k << " = 0";
      for (Scalar v : out) EXPECT_TRUE(std::isfinite(v)) << entry.policy << " alpha_" << k << " = 0";
    }
  }
  if (!layout.outputs.qdd) return;  // the scene does not return q̈ (scene key outputs)
  std::vector<Scalar> unit_qdd(n);
  for (const auto& entry : variant.solves) {
    in = clean;
    if (status_of(entry) != 0) continue;  // saturation or a dropped pivot: compare only plain solves
    std::copy(out.begin(), out.begin() + n, unit_qdd.begin());
    const Scalar scale = Scalar(64);
    for (std::size_t j = 0; j < layout.input_directions.size(); ++j) {
      for (std::size_t i = 0; i < 6; ++i) in[layout.alpha(j) + i] *= scale;
      in[layout.beta() + layout.input_directions[j]] *= scale;
    }
    EXPECT_EQ(status_of(entry), 0u) << entry.policy;
    const long double e = oracle::relative_error<long double>(std::vector<long double>(out.begin(), out.begin() + n),
                                         std::vector<long double>(unit_qdd.begin(), unit_qdd.end()));
    EXPECT_LE(e, 1e4L * std::numeric_limits<Scalar>::epsilon()) << entry.policy << ": alpha and beta scaled by 64";
  }
}

// The states, `states` of them in a scene's random problems (an odd count: the last group of
// lanes is partial), every third one made to part from its group's others (part_from_group,
// support/flat_problem.hpp); the statuses counted show the cases occur.
template <class Scalar>
void check_batch_equals_flat(const FlatVariant<Scalar>& variant, const std::string& scene_path, int states) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  const solver::FlatLayout layout = s.flat_layout(chain);
  const std::size_t rows = static_cast<std::size_t>(states | 1), in_size = variant.in_size, out_size = variant.out_size;
  RandomProblem random(11);
  std::vector<std::vector<Scalar>> problems;
  for (std::size_t state = 0; state < rows; ++state) {
    const FlatProblem p = random_flat_problem(random, s, chain);
    std::vector<Scalar> in(p.in.begin(), p.in.end());
    part_from_group(in, layout, state);
    problems.push_back(std::move(in));
  }
  std::vector<Scalar> batch_in(in_size * rows), batch_out(out_size * rows), out(out_size);
  for (std::size_t state = 0; state < rows; ++state)
    for (std::size_t k = 0; k < in_size; ++k) batch_in[k * rows + state] = problems[state][k];
  const auto same = [](Scalar a, Scalar b) { return std::isnan(a) ? std::isnan(b) : std::memcmp(&a, &b, sizeof a) == 0; };
  for (const auto& entry : variant.solves) {
    entry.batch(static_cast<int>(rows), batch_in.data(), batch_out.data());
    unsigned seen = 0;
    for (std::size_t state = 0; state < rows; ++state) {
      entry.solve(problems[state].data(), out.data());
      seen |= static_cast<unsigned>(out[layout.status()]);
      for (std::size_t k = 0; k < out_size; ++k)
        ASSERT_TRUE(same(batch_out[k * rows + state], out[k])) << entry.policy << ", state " << state << ", flat output " << k
                                                             << ": batch " << batch_out[k * rows + state] << ", flat " << out[k];
    }
    std::cout << "[batch] " << scene_path << " " << entry.policy << ": " << rows << " states equal to their flat calls; status bits seen "
              << seen << "\n";
    if (layout.input_directions.size() > 1) {
      EXPECT_NE(seen & solver::status_constraint_rank_deficient, 0u) << entry.policy;
    }
    if (layout.constraints > 0 && layout.torques > 0 && std::string(entry.policy).rfind("saturate", 0) == 0) {
      EXPECT_NE(seen & solver::status_saturated, 0u) << entry.policy;  // saturation clamps the constraint torque
    }
  }
}

// `states` random problems of the scene (the seed of check_against_reference: its first states),
// each policy's line {"flat": in, "policy": p} answered by one run of `sweepgen solve --scene`:
//  - its flat output equals ReferenceSolver<double> with the scene's options bit for bit (the
//    CLI reads gravity, locked joints, rotor inertia, fixed directions and policies from the
//    scene: nothing is retyped), its named results are the flat ones;
//  - the generated solve makes the same rank decisions (but at the pivot tolerance, as in
//    check_against_reference) and its q̈, τcmd and ν differ from the CLI's by at most 200 eps κ
//    inside double's domain (κ ≤ 1e8, widened by cond(M) where needed): both are within
//    100 eps κ of the answer (check_against_reference's accuracy bound), so of each other within
//    twice that; ceiling 200 · 2.2e-16 · 1e8 = 4.4e-6.
void check_solve_scene(const FlatVariant<double>& variant, const std::string& scene_path, int states) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  const solver::FlatLayout layout = s.flat_layout(chain);
  solver::SolverOptions options = s.solver_options();
  options.pivot_tolerance = options.pivot_tolerance_for(std::numeric_limits<double>::epsilon());
  options.joint_inertia_tolerance = options.joint_inertia_tolerance_for(std::numeric_limits<double>::epsilon());
  solver::ReferenceSolver<double> reference(chain, s.layout, s.solver_options());
  solver::ReferenceSolver<long double> answer(chain, s.layout, options);
  RandomProblem random(2024);
  std::vector<FlatProblem> problems;
  std::string lines;
  for (int state = 0; state < states; ++state) {
    problems.push_back(random_flat_problem(random, s, chain));
    for (const auto& entry : variant.solves)
      lines += nlohmann::json{{"flat", problems.back().in}, {"policy", entry.policy}}.dump() + "\n";
  }
  const CommandResult run = run_command(shell_command({SWEEPGEN_EXECUTABLE, "solve", "--scene", scene_path}), &lines);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::istringstream answers(run.out);
  constexpr double eps = std::numeric_limits<double>::epsilon(), kMaxKappa = 1e8, kFactor = 200;
  int compared = 0, beyond = 0, borderline = 0;
  std::vector<double> out(variant.out_size), expected(layout.out_size());
  for (int state = 0; state < states; ++state) {
    const FlatProblem& p = problems[static_cast<std::size_t>(state)];
    answer.prepare(p.cast<long double>());
    const double k = kappa(answer);
    for (const auto& entry : variant.solves) {
      std::string text;
      ASSERT_TRUE(std::getline(answers, text)) << "no answer to state " << state << " " << entry.policy;
      const nlohmann::json cli = nlohmann::json::parse(text);
      ASSERT_TRUE(cli.contains("flat")) << text;
      const std::vector<double> cli_out = cli["flat"].get<std::vector<double>>();
      const auto policy = *solver::policy_from_name(entry.policy);
      const auto& solution = reference.run(p, policy);
      solver::flat_output(solution, reference.status(), layout, expected.data());
      ASSERT_EQ(cli_out, expected) << "state " << state << " " << entry.policy << ": the CLI is not the scene's reference";
      if (layout.outputs.qdd) {
        ASSERT_EQ(cli["qdd"].get<std::vector<double>>(), std::vector<double>(expected.begin(), expected.begin() + layout.dof));
      }
      entry.solve(p.in.data(), out.data());
      const bool cli_dropped = static_cast<unsigned>(cli_out[layout.status()]) & solver::status_constraint_rank_deficient;
      const bool generated_dropped = static_cast<unsigned>(out[layout.status()]) & solver::status_constraint_rank_deficient;
      if (cli_dropped != generated_dropped) {
        ++borderline;
        EXPECT_GE(k * options.pivot_tolerance, 0.1) << "state " << state << " " << entry.policy
                                                    << ": rank decisions differ on a well-conditioned constraint";
        continue;
      }
      EXPECT_EQ(out[layout.status()], cli_out[layout.status()]) << "state " << state << " " << entry.policy;
      if (cli_dropped) continue;  // ν is not unique where a pivot drops
      if (!(k <= kMaxKappa)) {
        ++beyond;
        continue;
      }
      const auto error = [&](std::size_t offset, std::size_t count) {
        const auto part = [&](const std::vector<double>& v) {
          return std::vector<long double>(v.begin() + static_cast<std::ptrdiff_t>(offset),
                                          v.begin() + static_cast<std::ptrdiff_t>(offset + count));
        };
        return static_cast<double>(oracle::relative_error<long double>(part(out), part(cli_out)));
      };
      double e = 0;
      if (layout.outputs.qdd) e = std::max(e, error(layout.qdd(), layout.dof));
      if (layout.outputs.tau_cmd) e = std::max(e, error(layout.tau_cmd(), layout.dof));
      if (layout.outputs.nu) e = std::max(e, error(layout.nu(), layout.constraints));
      if (layout.outputs.coupling_torque) e = std::max(e, error(layout.coupling_torque(), layout.couplings.size()));
      const double k_widened = e > kFactor * eps * k
                                   ? std::max(k, report::inertia_condition_number(chain, p.q.cast<report::Precise>(), options))
                                   : k;
      EXPECT_LE(e, kFactor * eps * k_widened) << "state " << state << " " << entry.policy << " kappa " << k;
      ++compared;
    }
  }
  std::cout << "[solve --scene] " << scene_path << ": " << compared << " solves compared with the generated solver, "
            << beyond << " beyond kappa 1e8, " << borderline << " at the pivot tolerance\n";
  EXPECT_GE(compared, static_cast<int>(variant.solves.size()) * states / 2);
}

ResolveProblems resolve_problems(const std::string& scene_path, int states) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  ResolveProblems p;
  p.layout = s.flat_layout(chain);
  RandomProblem random(99);
  for (int state = 0; state < states; ++state) {
    p.in.push_back(random_flat_problem(random, s, chain).in);
    std::vector<double> beta1(p.layout.constraints + 1);
    for (auto& b : beta1) b = random.uniform(-1, 1);
    p.first_beta.push_back(std::move(beta1));
  }
  return p;
}

template ErrorSummary check_against_reference<double>(const FlatVariant<double>&, const std::string&, int,
                                                      const Domain&, unsigned);
template ErrorSummary check_against_reference<float>(const FlatVariant<float>&, const std::string&, int, const Domain&,
                                                     unsigned);
template void check_bad_inputs<double>(const FlatVariant<double>&, const std::string&, bool, unsigned);
template void check_bad_inputs<float>(const FlatVariant<float>&, const std::string&, bool, unsigned);
template void check_batch_equals_flat<double>(const FlatVariant<double>&, const std::string&, int);
template void check_batch_equals_flat<float>(const FlatVariant<float>&, const std::string&, int);

}  // namespace sweepgen::test

#include "report/stability_measure.hpp"

#include <limits>
#include <map>

#include "report/extreme_states.hpp"

namespace sweepgen::report {

const std::vector<solver::ConstraintFactorisation>& stability_policies() {
  static const std::vector<solver::ConstraintFactorisation> policies = {solver::ConstraintFactorisation::pivoted_ldlt,
                                                                       solver::ConstraintFactorisation::damped};
  return policies;
}

std::string policy_name(solver::ConstraintFactorisation f) {
  return f == solver::ConstraintFactorisation::damped ? "damped" : "pivoted_ldlt";
}

double epsilon_of(const std::string& scalar) {
  return scalar == "float" ? std::numeric_limits<float>::epsilon() : std::numeric_limits<double>::epsilon();
}

std::vector<StabilityRow> measure_stability_case(const StabilityCase& c, const StabilityRunOptions& options) {
  const auto states = extreme_states(c.scene, c.chain, options.states_per_kind, c.singular_q, options.seed);
  std::vector<Problem> problems;
  for (const auto& s : states) problems.push_back(s.problem);

  // The referees first: the damped rows are judged against the pivoted ones too.
  std::map<std::string, scene::Scene> scenes;                             // by policy
  std::map<std::pair<std::string, std::string>, std::vector<Truth>> referee;  // by policy, scalar
  for (const auto policy : stability_policies()) {
    scene::Scene s = report_scene(c.scene);
    s.constraint_factorisation = policy;
    for (const std::string scalar : {"double", "float"})
      referee[{policy_name(policy), scalar}] =
          precise_reference(s, c.chain, problems, with_tolerance_factor(s, 1, epsilon_of(scalar)));
    scenes.emplace(policy_name(policy), std::move(s));
  }

  TimingOptions untimed;
  untimed.repetitions = 0;
  std::vector<StabilityRow> rows;
  for (const auto policy : stability_policies()) {
    const std::string name = policy_name(policy);
    const scene::Scene& s = scenes.at(name);
    const CompiledSolver compiled =
        compile_scene_solver(s, c.chain, options.build_dir / name, options.cxx, options.progress(name), Isa::baseline,
                             Optimisation::checked);  // untimed: only its numbers count
    const std::vector<VariantResult> results = {
        measure_reference_double(s, c.chain, problems, untimed),
        measure_generated<double>(compiled.solve_f64_of.at(solver::Policy::original), "double", s.flat_layout(c.chain), problems, untimed),
        measure_generated<float>(compiled.solve_f32, "float", s.flat_layout(c.chain), problems, untimed)};
    for (const VariantResult& result : results) {
      const double largest =
          result.scalar == "float" ? std::numeric_limits<float>::max() : std::numeric_limits<double>::max();
      const std::vector<Truth>& truth = referee.at({name, result.scalar});
      const std::vector<Truth>& pivoted = referee.at({policy_name(stability_policies().front()), result.scalar});
      for (std::size_t k = 0; k < states.size(); ++k) {
        StabilityRow row{c.name, name, result.variant, result.scalar, k, states[k].kind,
                         judge(result.outcomes[k], truth[k], problems[k], c.chain, largest)};
        if (policy == solver::ConstraintFactorisation::damped)
          row.bias_vs_pivoted = judge(result.outcomes[k], pivoted[k], problems[k], c.chain, largest).error();
        rows.push_back(std::move(row));
      }
    }
  }
  return rows;
}

}  // namespace sweepgen::report

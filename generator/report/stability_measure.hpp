// `sweepgen report --stability`: one case's extreme states through the generated solver (and
// ReferenceSolver<double>) under both ill-conditioning policies, each judged against the
// binary128 referee run with the same factorisation and that scalar's tolerances
// (docs/stability.md, "Stability report").
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "report/compiled_solver.hpp"
#include "report/stability_cases.hpp"
#include "report/stability_errors.hpp"

namespace sweepgen::report {

// One state of one variant.
struct StabilityRow {
  std::string case_name, policy, variant, scalar;  // policy: pivoted_ldlt or damped
  std::size_t state = 0;                           // index in the case's extreme states
  std::string kind;                                // extreme_states.hpp
  StateJudgement judgement;                        // against the referee of this policy and scalar
  // damped only (NaN otherwise): the error against the pivoted referee of this scalar, the
  // policy's price where pivoting drops a direction and damping keeps it.
  double bias_vs_pivoted = NAN;
};

// The policies, in report order, and their scene-file names.
const std::vector<solver::ConstraintFactorisation>& stability_policies();
std::string policy_name(solver::ConstraintFactorisation f);

// Machine epsilon of a scalar by name ("double", "float").
double epsilon_of(const std::string& scalar);

struct StabilityRunOptions {
  std::size_t states_per_kind = 10;
  unsigned long long seed = 1;
  std::string cxx = "c++";
  std::filesystem::path build_dir;  // the case's generated code goes to build_dir/<policy>/
  // What a compile step says, with the policy it is for.
  std::function<CompileProgress(const std::string& policy)> progress;
};

// The rows of one case: per policy, reference double, generated double and generated float on
// every extreme state.
std::vector<StabilityRow> measure_stability_case(const StabilityCase& c, const StabilityRunOptions& options);

}  // namespace sweepgen::report

// `sweepgen report`: random states of a scene, the high-precision referee, timing, and the
// error statistics of each measured variant (README, "sweepgen report").
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "model/chain.hpp"
#include "scene/scene.hpp"
#include "solver/state.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::report {

// The referee: ReferenceSolver in a scalar wider than double. long double is the 80-bit x87
// format on x86-64 (64-bit mantissa) and IEEE quad on aarch64; where it is only double
// (MSVC, some PowerPC ABIs) there is no wider built-in scalar that Eigen takes as is, and the
// report refuses to build rather than compare double with itself.
using Precise = long double;
static_assert(std::numeric_limits<Precise>::digits > std::numeric_limits<double>::digits,
              "sweepgen report needs a long double wider than double as its high-precision reference");

// States whose cond(E^A_cstr,0) exceeds this are counted apart: there rounding is amplified
// by the condition number in any solver of a given precision.
constexpr double kIllConditioned = 1e6;

// One random state with its drivers and setpoints, in double.
struct Problem {
  Eigen::VectorXd q, qd;
  std::vector<Eigen::VectorXd> torques;              // one per torque instance
  Eigen::VectorXd tau_ff;                            // their sum (what τcmd starts from)
  std::vector<spatial::Force<double>> wrenches;      // one per external-force instance, link frame
  std::vector<spatial::Force<double>> alpha;         // Nc directions, tip frame (fixed ones too)
  solver::ConstraintVector<double> beta;             // Nc setpoints
  std::vector<double> flat;                          // the generated code's flat input
};

// Seeded random states: q within the joint limits ([-pi, pi] where unlimited), q̇ in [-2, 2],
// the first torque instance up to 1.5x and others up to 0.2x the effort limit (10 where
// unlimited), wrenches with moments in [-2, 2] N m and forces in [-20, 20] N, random unit
// directions (unless the scene fixes them), beta in [-3, 3] (the conventions of
// tests/support/generated_check.hpp).
std::vector<Problem> random_problems(const scene::Scene& s, const model::Chain& chain, std::size_t count,
                                     unsigned long long seed);

// Number of values in the generated flat input of the scene.
std::size_t flat_in_size(const scene::Scene& s, const model::Chain& chain);

// The high-precision answer for one state.
struct Truth {
  std::vector<Precise> qdd, tau_cmd;
  double cond = 1;  // cond_2(E^A_cstr,0), 1 when Nc = 0
};
std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems);

// One variant's answer for one state, widened.
struct Outcome {
  std::vector<Precise> qdd, tau_cmd;
  std::array<Precise, 6> tip_acceleration{};  // [angular; linear], tip frame, minus gravity
  bool rank_deficient = false;                // the variant reported constraint_rank_deficient
};

// One row of the report.
struct VariantResult {
  std::string variant;  // "reference", "generated", "kdl"
  std::string scalar;   // "double", "float"
  std::string note;     // why there are no numbers (empty when measured)
  std::vector<double> ns_per_solve;  // one entry per timed repetition
  std::vector<Outcome> outcomes;     // one per state
};

struct TimingOptions {
  int repetitions = 20;  // timed passes over the whole state set (after one warm-up pass)
};

// Times `run_all` (one pass over `states` states): one warm-up pass, then `repetitions` timed
// passes; returns nanoseconds per solve of each pass.
template <class RunAll>
std::vector<double> time_passes(std::size_t states, const TimingOptions& timing, RunAll&& run_all) {
  run_all();
  std::vector<double> ns;
  for (int r = 0; r < timing.repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    run_all();
    const auto stop = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(stop - start).count() / static_cast<double>(states));
  }
  return ns;
}

// ReferenceSolver<double>: outward + decompose + solve(original) per state.
VariantResult measure_reference_double(const scene::Scene& s, const model::Chain& chain,
                                       const std::vector<Problem>& problems, const TimingOptions& timing);

// A generated flat solve (`in` -> `out`, layout of templates/solver.hpp.mustache) in Scalar.
template <class Scalar>
using FlatSolve = void (*)(const Scalar* in, Scalar* out);

// Instantiated for float and double.
template <class Scalar>
VariantResult measure_generated(FlatSolve<Scalar> solve, const char* scalar_name, std::size_t dof,
                                std::size_t constraints, const std::vector<Problem>& problems,
                                const TimingOptions& timing);

// The error statistics of one variant (README, "sweepgen report").
struct Summary {
  double ns_median = 0, ns_p90 = 0;
  Precise max_rel_err_qdd = 0, median_rel_err_qdd = 0, max_rel_err_tau = 0, max_constraint_residual = 0;
  std::size_t states = 0;                  // all states
  std::size_t ill_conditioned_states = 0;  // cond(E^A_cstr,0) > kIllConditioned
  Precise ill_conditioned_max_rel_err_qdd = 0;
  std::size_t rank_deficient_well_conditioned = 0;  // the variant dropped a pivot where cond <= 1e6
  Precise max_rel_err_qdd_full_rank = 0;            // max q̈ error over the other well-conditioned states
};
Summary summarize(const VariantResult& result, const std::vector<Problem>& problems, const std::vector<Truth>& truth);

// ‖a − b‖∞ / max(1, ‖b‖∞).
Precise relative_error(const std::vector<Precise>& a, const std::vector<Precise>& b);
// The q-th quantile (0..1) of `values`, linear between order statistics; NaN when empty.
template <class T>
T quantile(std::vector<T> values, double q) {
  if (values.empty()) return std::numeric_limits<T>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const double at = q * static_cast<double>(values.size() - 1);
  const std::size_t below = static_cast<std::size_t>(at);
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const T fraction = static_cast<T>(at - static_cast<double>(below));
  return values[below] + fraction * (values[above] - values[below]);
}

}  // namespace sweepgen::report

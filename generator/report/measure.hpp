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
#include "solver/solve_inputs.hpp"
#include "solver/quad_scalar.hpp"
#include "solver/state.hpp"
#include "spatial/spatial.hpp"

namespace sweepgen::report {

// The referee: ReferenceSolver in IEEE binary128 (113-bit mantissa, solver/quad_scalar.hpp).
// Wider than long double (64 bits on x86-64), which cannot judge double where double loses more
// than ~3 digits (docs/stability.md).
using Precise = solver::Quad;
static_assert(std::numeric_limits<Precise>::digits >= 2 * std::numeric_limits<double>::digits,
              "the high-precision reference must be at least twice as wide as double");

// One random state with its drivers and setpoints, in double.
struct Problem : solver::SolveInputs<double> {
  Eigen::VectorXd tau_ff;     // the sum of the torques (what τcmd starts from)
  std::vector<double> flat;   // the generated code's flat input (solver/flat_layout.hpp)
};

// Seeded random states: q within the joint limits ([-pi, pi] where unlimited), q̇ in [-2, 2],
// the first torque instance up to 1.5x and others up to 0.2x the effort limit (10 where
// unlimited), wrenches with moments in [-2, 2] N m and forces in [-20, 20] N, random unit
// directions (unless the scene fixes them), beta in [-3, 3] (the conventions of
// tests/support/generated_check.hpp).
std::vector<Problem> random_problems(const scene::Scene& s, const model::Chain& chain, std::size_t count,
                                     unsigned long long seed);

// Fills p.flat, the generated code's flat input.
void pack_flat(const scene::Scene& s, const model::Chain& chain, Problem& p);

// The high-precision answer for one state.
struct Truth {
  std::vector<Precise> qdd, tau_cmd, nu;
  // q̈ of the same state without the constraint (α = 0): the constraint's share q̈ − q̈_free can
  // cancel most of it, and rounding is relative to the larger of the two (docs/stability.md).
  std::vector<Precise> qdd_free;
  // Per joint, Σ_k |S_iᵀ f_k,i| with f_k the rigid inward propagation of direction k's force
  // F_cstr,k ν_k from its set's body: the terms τcmd − τff = J_cᵀ ν sums (T1). Opposed directions with large
  // multipliers cancel there, and rounding is relative to the terms (docs/stability.md).
  std::vector<Precise> tau_constraint_terms;
  double cond = 1;  // cond_2(E^A_cstr,0), 1 when Nc = 0
  // cond_2 of E^A_cstr,0 with its diagonal scaled to 1 (each direction by 1/sqrt(E_kk)): the
  // condition number the relative pivot test sees, invariant under the units of each direction.
  double cond_scaled = 1;
  // min_i D_i / (d_i + trace of M^A_i's block of the joint's kind): how close a joint's
  // articulated inertia comes to 0 relative to its own scale (docs/stability.md).
  double min_relative_D = 1;
  // cond_2 of the joint-space inertia M(q); infinite when the joint-inertia policy locks a joint.
  double cond_M = 1;
  unsigned status = 0;  // the reference's status bits in Precise, with `options`' tolerances
};
// The scene's solver options with both tolerances (pivot, joint inertia) at `factor` times their
// defaults for a scalar of machine epsilon `eps`: the referee of that scalar's solver (factor 1:
// "what should this scalar's solver have returned", rank decisions included), or the band
// around its decisions (0.5, 2).
solver::SolverOptions with_tolerance_factor(const scene::Scene& s, double factor, double eps);
// `options`: the solver options the referee runs with (default: the scene's); `policy`: the
// solver policy it answers for (τcmd, q̈ and ν differ by policy; the condition numbers do not).
// Without `with_cond_M`, Truth::cond_M stays NaN (it costs n + 1 more binary128 solves a state).
std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems);
std::vector<Truth> precise_reference(const scene::Scene& s, const model::Chain& chain,
                                     const std::vector<Problem>& problems, const solver::SolverOptions& options,
                                     solver::Policy policy = solver::Policy::original, bool with_cond_M = true);

// cond_2 of the joint-space inertia M(q), in Precise, without new dynamics code: with q̇ = 0, no
// gravity, no constraint and no external force the solver's q̈ is linear in τ, so column j of
// M^-1 is q̈(τ = e_j) − q̈(τ = 0). `options`: the referee's (its joint-inertia tolerance decides
// which joints are locked). Infinite when a joint is locked (M^-1 singular there).
double inertia_condition_number(const model::Chain& chain, const solver::JointVector<Precise>& q,
                                solver::SolverOptions options);

// One variant's answer for one state, widened.
struct Outcome {
  std::vector<Precise> qdd, tau_cmd, nu;
  std::array<Precise, 6> tip_acceleration{};  // [angular; linear], tip frame, minus gravity
  // Per constraint direction k, Ẍ of its set's link, in that link's frame (as tip_acceleration).
  std::vector<std::array<Precise, 6>> link_acceleration;
  bool rank_deficient = false;                // the variant reported constraint_rank_deficient
  unsigned status = 0;                        // every status bit the variant reported
};

// What a solve wrote to `out` (generated layout, solver/flat_layout.hpp), widened; the results the
// layout does not list stay empty (judge() leaves them out). Instantiated for float and double.
template <class Scalar>
Outcome outcome_of(const Scalar* out, const solver::FlatLayout& layout);

// One variant's measurements on a state set.
struct VariantResult {
  std::string variant;  // "reference", "generated", "kdl", "dense_kkt"
  std::string scalar;   // "double", "float", "binary128"
  std::string note;     // why there are no numbers (empty when measured)
  std::vector<double> ns_per_call;  // one entry per timed call (every state, every timed pass)
  std::vector<Outcome> outcomes;    // one per state
};

struct TimingOptions {
  int repetitions = 20;  // timed passes over the whole state set (after one untimed pass)
};

// The cost of one steady_clock::now() pair with nothing between them (the median of many), in ns:
// what time_calls subtracts from each call.
double clock_overhead_ns();

// Calls `call(state)` for every state once untimed (the pass that fills the outcomes), then
// `repetitions` timed passes, timing each call alone; returns one time per timed call in ns, the
// clock's own cost subtracted (never below 0). Per-call times give the median and the tail (p99,
// max) a real-time loop sees; a pass-average would hide the tail.
template <class Call>
std::vector<double> time_calls(std::size_t states, const TimingOptions& timing, Call&& call) {
  for (std::size_t state = 0; state < states; ++state) call(state);
  const double overhead = timing.repetitions > 0 ? clock_overhead_ns() : 0;
  std::vector<double> ns;
  ns.reserve(states * static_cast<std::size_t>(std::max(timing.repetitions, 0)));
  for (int r = 0; r < timing.repetitions; ++r)
    for (std::size_t state = 0; state < states; ++state) {
      const auto start = std::chrono::steady_clock::now();
      call(state);
      const auto stop = std::chrono::steady_clock::now();
      ns.push_back(std::max(0.0, std::chrono::duration<double, std::nano>(stop - start).count() - overhead));
    }
  return ns;
}

// ReferenceSolver<double>: outward + decompose + solve(original) per state.
VariantResult measure_reference_double(const scene::Scene& s, const model::Chain& chain,
                                       const std::vector<Problem>& problems, const TimingOptions& timing);
// ReferenceSolver<Precise>, the referee itself: its time per call (its error is 0 by definition).
VariantResult measure_reference_precise(const scene::Scene& s, const model::Chain& chain,
                                        const std::vector<Problem>& problems, const TimingOptions& timing);
// ReferenceSolver<float> (inputs rounded to float): the operations of the generated float code
// (the generated code is the traced reference; tests/generated/ check them against each other).
VariantResult measure_reference_float(const scene::Scene& s, const model::Chain& chain,
                                      const std::vector<Problem>& problems, const TimingOptions& timing);

// A generated flat solve (`in` -> `out`, layout of templates/solver.hpp.mustache) in Scalar.
template <class Scalar>
using FlatSolve = void (*)(const Scalar* in, Scalar* out);

// Instantiated for float and double.
template <class Scalar>
VariantResult measure_generated(FlatSolve<Scalar> solve, const char* scalar_name, const solver::FlatLayout& layout,
                                const std::vector<Problem>& problems, const TimingOptions& timing);

// How far a variant's link accelerations miss the constraint it was asked to meet:
// max_k |α_kᵀ Ẍ_link(k) − β_k| / max(1, ‖β‖∞, max_k ‖Ẍ_link(k)‖∞) (0 when Nc = 0; infinite when
// an Ẍ_link is not finite; NaN when the outcome carries no Ẍ_link). Needs no referee: it checks the answer against the problem itself.
Precise constraint_residual(const Outcome& outcome, const Problem& problem);
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

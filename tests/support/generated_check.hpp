// Checks one generated solver variant (f64 or f32 namespace of a scene) against the
// reference solver in its own scalar and in long double, through the generated flat and structured APIs. The checks
// that need no generated type take a FlatVariant (sizes and the flat solves as function
// pointers) and are compiled once, in generated_check.cpp, for double and float: a scene's test
// translation unit compiles only its own few lines.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <type_traits>
#include <vector>

#include "solver/flat_layout.hpp"

// Defines struct `Name` describing the generated variant in namespace `ns` (e.g. panda::f64).
#define SWEEPGEN_GENERATED_API(Name, ns)                                          \
  struct Name {                                                                   \
    using Scalar = ns::Scalar;                                                    \
    using State = ns::State;                                                      \
    using Solution = ns::Solution;                                                \
    static constexpr const auto& solves = ns::solves;                             \
    static constexpr const auto& flat_solves = ns::flat_solves;                   \
    static constexpr const auto& batch_solves = ns::batch_solves;                 \
    static constexpr int flat_in_size = ns::flat_in_size;                         \
    static constexpr int flat_out_size = ns::flat_out_size;                       \
    [[maybe_unused]] static constexpr bool outward_rows = ns::outward_constraint_rows; \
    static void outward(const Scalar* q, const Scalar* qd, State& s) { ns::outward(q, qd, s); } \
    static void decompose(const Scalar* drivers_in, State& s) { ns::decompose(ns::drivers_from_flat(drivers_in), s); } \
  }

namespace sweepgen::test {

// A generated variant's flat entry points.
template <class Scalar>
struct FlatVariant {
  struct Entry {
    const char* policy;
    void (*solve)(const Scalar* in, Scalar* out);
    void (*batch)(int n, const Scalar* in, Scalar* out);  // the same policy, n states at once
  };
  std::size_t in_size = 0, out_size = 0;
  std::vector<Entry> solves;
  bool outward_rows = false;  // the generator formed the constraint rows outward (I6)
};

template <class Api>
FlatVariant<typename Api::Scalar> flat_variant() {
  FlatVariant<typename Api::Scalar> v;
  v.in_size = static_cast<std::size_t>(Api::flat_in_size);
  v.out_size = static_cast<std::size_t>(Api::flat_out_size);
  for (std::size_t k = 0; k < std::size(Api::flat_solves); ++k)
    v.solves.push_back({Api::flat_solves[k].policy, Api::flat_solves[k].solve, Api::batch_solves[k].solve});
  v.outward_rows = Api::outward_rows;
  return v;
}

struct ErrorSummary {
  long double same_operations = 0;     // max error/(eps κ) against ReferenceSolver<Scalar>
  long double accuracy = 0;            // max error/(eps κ) against ReferenceSolver<long double>
  long double largest_difference = 0;  // max relative difference from ReferenceSolver<Scalar>
  long double largest_error = 0;       // max relative error against ReferenceSolver<long double>
  int states = 0, rank_deficient = 0, borderline = 0;
};

// Where a scalar's results are judged (docs/stability.md, "Float: domain of validity"): states
// with κ ≤ max_kappa, at most max_outside_share of them beyond; inside, the error against the
// long double answer is at most accuracy · eps · κ.
struct Domain {
  double max_kappa;
  long double accuracy;
  double max_outside_share;
};

// Compares every flat solve of the variant with ReferenceSolver<Scalar> (the traced operations)
// and ReferenceSolver<long double> (the answer) on `states` random problems
// (generated_check.cpp says how).
template <class Scalar>
ErrorSummary check_against_reference(const FlatVariant<Scalar>& variant, const std::string& scene_path, int states,
                                     const Domain& domain, unsigned seed = 2024);

// Bad inputs at run time (generated_check.cpp says which).
template <class Scalar>
void check_bad_inputs(const FlatVariant<Scalar>& variant, const std::string& scene_path, bool checks_inputs,
                      unsigned not_finite_bit);

// The batch entry points against the flat ones (generated_check.cpp says on which states): the
// same status and, bit for bit, the same values for every state (NaN where the flat call gives NaN).
template <class Scalar>
void check_batch_equals_flat(const FlatVariant<Scalar>& variant, const std::string& scene_path, int states);

// `sweepgen solve --scene` against the generated double solver, state by state (generated_check.cpp
// says how): the CLI solves the scene's own problem.
void check_solve_scene(const FlatVariant<double>& variant, const std::string& scene_path, int states);

// Problems for check_resolve_equals_full_solve: flat inputs, a first setpoint vector (one value
// more than there are constraints: a solve reads only its own), and where the parts of `in` are.
struct ResolveProblems {
  solver::FlatLayout layout;
  std::vector<std::vector<double>> in, first_beta;
};
ResolveProblems resolve_problems(const std::string& scene_path, int states);

// The joint-space array `member` reads from a generated Solution, against its place in the flat
// `out`: where the scene returns it (scene key outputs), and a member of Solution exactly there.
template <class Solution, class Member, class Scalar>
void expect_joint_array(const Solution& s, Member member, bool listed, const std::vector<Scalar>& out,
                        std::size_t offset, std::size_t dof, const char* what) {
  ASSERT_EQ((std::is_invocable_v<Member, const Solution&>), listed) << what << ": a Solution member exactly where listed";
  if constexpr (std::is_invocable_v<Member, const Solution&>) {
    for (std::size_t i = 0; i < dof; ++i) ASSERT_EQ(member(s)[i], out[offset + i]) << what << " joint " << i;
  }
}

// outward + decompose once, then every policy's solve for one setpoint and again for a second:
// the second equals (bit for bit) a full flat solve with the second setpoint.
template <class Api>
void check_resolve_equals_full_solve(const std::string& scene_path, int states) {
  using Scalar = typename Api::Scalar;
  const ResolveProblems p = resolve_problems(scene_path, states);
  const solver::FlatLayout& layout = p.layout;
  std::vector<Scalar> out(Api::flat_out_size);
  for (std::size_t state = 0; state < p.in.size(); ++state) {
    const std::vector<Scalar> in(p.in[state].begin(), p.in[state].end());
    ASSERT_EQ(in.size(), static_cast<std::size_t>(Api::flat_in_size));
    typename Api::State st;
    Api::outward(in.data() + layout.q(), in.data() + layout.qd(), st);
    Api::decompose(in.data() + layout.torque(0), st);
    const std::vector<Scalar> beta1(p.first_beta[state].begin(), p.first_beta[state].end());
    const std::vector<Scalar> beta2(in.begin() + static_cast<std::ptrdiff_t>(layout.beta()), in.end());
    for (std::size_t k = 0; k < std::size(Api::flat_solves); ++k) {
      typename Api::Solution first, second;
      Api::solves[k].solve(st, beta1.data(), first);
      Api::solves[k].solve(st, beta2.data(), second);
      Api::flat_solves[k].solve(in.data(), out.data());
      const auto qdd = [](const auto& s) -> decltype((s.qdd)) { return s.qdd; };
      const auto tau_cmd = [](const auto& s) -> decltype((s.tau_cmd)) { return s.tau_cmd; };
      const auto tau_ctrl = [](const auto& s) -> decltype((s.tau_ctrl)) { return s.tau_ctrl; };
      const std::size_t n = layout.dof;
      expect_joint_array(second, qdd, layout.outputs.qdd, out, layout.qdd(), n, Api::solves[k].policy);
      expect_joint_array(second, tau_cmd, layout.outputs.tau_cmd, out, layout.tau_cmd(), n, "tau_cmd");
      expect_joint_array(second, tau_ctrl, layout.outputs.tau_ctrl, out, layout.tau_ctrl(), n, "tau_ctrl");
      ASSERT_EQ(static_cast<Scalar>(second.status), out[layout.status()]);
    }
  }
}

extern template ErrorSummary check_against_reference<double>(const FlatVariant<double>&, const std::string&, int,
                                                             const Domain&, unsigned);
extern template ErrorSummary check_against_reference<float>(const FlatVariant<float>&, const std::string&, int,
                                                            const Domain&, unsigned);
extern template void check_bad_inputs<double>(const FlatVariant<double>&, const std::string&, bool, unsigned);
extern template void check_bad_inputs<float>(const FlatVariant<float>&, const std::string&, bool, unsigned);
extern template void check_batch_equals_flat<double>(const FlatVariant<double>&, const std::string&, int);
extern template void check_batch_equals_flat<float>(const FlatVariant<float>&, const std::string&, int);

}  // namespace sweepgen::test

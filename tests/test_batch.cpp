// The batch entry points (solve_<policy>_batch, templates/lanes.mustache's solve_in_lanes) against
// the flat ones on a scene generated and compiled here (so a change to the templates shows in this
// suite, which tests/faults/run.sh rebuilds): the Panda with two run-time directions at the hand,
// check_inputs on, the original and the saturating policy, double and float. Its states part inside
// groups of lanes in every way a batch must handle (test::part_from_group: q = 0 and the same
// direction twice, both rank-deficient, so (C4)'s pivoted path; a NaN in one input; the torques
// 1000 times their range, saturation); 64 states drawn alone follow, so that every lane width has
// whole groups that do not part, and 267 states leave a partial group at the end. Every output of
// every state, status word included, must be the flat call's bit for bit (NaN where it is NaN): the
// lanes run each state's operations in the same order, with the same rounding, and a group whose
// states part is solved state by state by the flat call itself. Compiled for each lane width this
// CPU runs: the x86-64 baseline (two doubles a vector), x86-64-v3 (four) and x86-64-v4 (eight,
// AVX-512), the last two with -ffp-contract=off (a fused multiply-add contracted in one of the two
// calls and not the other would round differently: that is the compiler's choice, not the lanes').
// The generated scenes' own tests (tests/generated/scene_test.cpp.in) do the same on every bundled scene.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "emit/scene_request.hpp"
#include "scene/scene.hpp"
#include "support/bundled_robots.hpp"
#include "support/flat_problem.hpp"
#include "support/run_command.hpp"
#include "support/skip_count.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

// Reads states in rows (value k of state s on line k, the states' values in hexadecimal), solves
// them with every policy's batch entry point and state by state with the flat one, and prints the
// number of outputs whose bits differ (NaN against NaN counts as equal) and the status bits seen.
constexpr const char* kDriver = R"(#include "batch_check.hpp"
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>
template <class Scalar, class Solves, class Batches>
long differing(const Solves& solves, const Batches& batches, int in_size, int out_size, int n, const std::vector<double>& rows,
               unsigned& seen) {
  std::vector<Scalar> in(rows.begin(), rows.end()), out(static_cast<std::size_t>(out_size) * n), one_in(in_size), one_out(out_size);
  long count = 0;
  for (std::size_t p = 0; p < std::size(solves); ++p) {
    batches[p].solve(n, in.data(), out.data());
    for (int s = 0; s < n; ++s) {
      for (int k = 0; k < in_size; ++k) one_in[k] = in[k * n + s];
      solves[p].solve(one_in.data(), one_out.data());
      seen |= static_cast<unsigned>(one_out[out_size - 1]);
      for (int k = 0; k < out_size; ++k) {
        const Scalar a = out[k * n + s], b = one_out[k];
        count += std::isnan(a) ? !std::isnan(b) : std::memcmp(&a, &b, sizeof a) != 0;
      }
    }
  }
  return count;
}
int main() {
  using namespace batch_check;
  int n = 0;
  if (std::scanf("%d", &n) != 1) return 2;
  std::vector<double> rows(static_cast<std::size_t>(f64::flat_in_size) * n);
  for (double& v : rows) if (std::scanf("%la", &v) != 1) return 2;
  unsigned seen = 0;
  const long f64 = differing<double>(f64::flat_solves, f64::batch_solves, f64::flat_in_size, f64::flat_out_size, n, rows, seen);
  const long f32 = differing<float>(f32::flat_solves, f32::batch_solves, f32::flat_in_size, f32::flat_out_size, n, rows, seen);
  std::printf("%ld %ld %u\n", f64, f32, seen);
}
)";

TEST(Batch, EveryStateAsItsFlatCall) {
  const model::Chain chain = test::load_bundled(test::bundled_robots().front());  // the Panda, to its hand
  scene::Scene s;
  s.solver = "batch_check";
  s.chain.urdf = chain.source;
  s.scalars = {"double", "float"};
  s.policies = {solver::Policy::original, solver::Policy::saturate};
  s.layout.torques = {"tau_ff"};
  s.layout.constraints = 2;  // two run-time directions at the tip
  s.layout.compose_all();
  const solver::FlatLayout layout = s.flat_layout(chain.dof());
  ASSERT_EQ(layout.input_directions.size(), 2u);

  test::TempDir dir;
  const emit::EmittedSolver emitted = emit::emit_solver(chain, emit::emit_request(s, "test"));
  for (const auto& file : emitted.files) std::ofstream(dir.path() / file.name) << file.text;
  std::ofstream(dir.path() / "driver.cpp") << kDriver;

  constexpr int kParting = 203, kStates = kParting + 64;
  test::RandomProblem random(23);
  std::vector<std::vector<double>> states;
  for (int state = 0; state < kStates; ++state) {
    std::vector<double> in = test::random_flat_problem(random, s, chain).in;
    if (state < kParting) test::part_from_group(in, layout, static_cast<std::size_t>(state));
    states.push_back(std::move(in));
  }
  std::ostringstream input;
  input << kStates << "\n" << std::hexfloat;
  for (std::size_t k = 0; k < layout.in_size(); ++k)
    for (const auto& in : states) input << in[k] << "\n";

  struct Isa {
    const char* name;
    std::vector<std::string> flags;
    bool runs;  // this CPU executes it
  };
  __builtin_cpu_init();
  const std::vector<Isa> isas = {
      {"x86-64 baseline, 2 doubles a vector", {}, true},
      {"x86-64-v3, 4", {"-march=x86-64-v3", "-ffp-contract=off"},
       __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")},
      {"x86-64-v4, 8", {"-march=x86-64-v4", "-ffp-contract=off"},
       __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512cd")}};
  // The baseline runs everywhere; a CPU without AVX2 skips the other two.
  test::SkipCount unsupported("batch lane widths this CPU does not run", 2.0 / 3.0);
  for (const Isa& isa : isas) {
    if (unsupported.skip(!isa.runs, isa.name)) continue;
    const std::string binary = (dir.path() / ("driver" + std::to_string(&isa - isas.data()))).string();
    std::vector<std::string> command{"c++", "-std=c++17", "-O2"};
    command.insert(command.end(), isa.flags.begin(), isa.flags.end());
    command.insert(command.end(), {"-I", dir.path().string(), (dir.path() / "driver.cpp").string(),
                                   (dir.path() / "batch_check.cpp").string(), "-o", binary});
    const test::CommandResult build = test::run_command(test::shell_command(command));
    ASSERT_EQ(build.exit_code, 0) << isa.name << "\n" << build.err;
    const test::CommandResult run = test::run_command(test::shell_command({binary}), input.str());
    ASSERT_EQ(run.exit_code, 0) << isa.name << "\n" << run.err;
    long differing_f64 = -1, differing_f32 = -1;
    unsigned seen = 0;
    std::istringstream(run.out) >> differing_f64 >> differing_f32 >> seen;
    std::cout << "[batch] " << isa.name << ": " << kStates << " states, two policies: " << differing_f64 << " double and "
              << differing_f32 << " float outputs differ from the flat calls; status bits seen " << seen << "\n";
    EXPECT_EQ(differing_f64, 0) << isa.name;
    EXPECT_EQ(differing_f32, 0) << isa.name;
    // The states part as intended: some rank-deficient (pivoted), some saturated, some not finite.
    EXPECT_NE(seen & solver::status_constraint_rank_deficient, 0u) << isa.name;
    EXPECT_NE(seen & solver::status_saturated, 0u) << isa.name;
    EXPECT_NE(seen & solver::status_not_finite, 0u) << isa.name;
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

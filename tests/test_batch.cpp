// The batch entry points (solve_<policy>_batch, templates/lanes.mustache's solve_in_lanes) against
// the flat ones on a scene generated and compiled here (so a change to the templates shows in this
// suite, which tests/faults/run.sh rebuilds): the Panda with two run-time directions at the hand,
// check_inputs on, the original and the saturating policy, double and float. Its states part inside
// groups of lanes in every way a batch must handle (test::part_from_group: q = 0 and the same
// direction twice, both rank-deficient, so (C4)'s pivoted path; a NaN in one input; the torques
// 1000 times their range, saturation); 64 states drawn alone follow, so that every lane width has
// whole groups that do not part, and 267 states leave a partial group at the end.
// Three builds of the scene (docs/generated-code.md, "Batches and GPUs"):
//  - sweepgen_add_solver's without ARCH (cmake/SweepgenAddSolver.cmake, sweepgen_solver_library):
//    the source at the x86-64 baseline with SWEEPGEN_BATCH_X86_64_V3 and _V4, and once more per
//    ISA with SWEEPGEN_BATCH_ISA, -march=<ISA> -ffp-contract=off. The entry points the program
//    calls must use the widest lanes this CPU runs (batch_lanes(): 8 doubles with AVX-512, 4 with
//    AVX2, else 1), and each ISA object's own entry points, called directly where the CPU runs
//    them, must use their width (4, 8). Every output of every state, status word included, must
//    be the flat call's bit for bit (NaN where it is NaN): the lanes run each state's operations in
//    the same order with the same rounding, nothing is contracted into a fused multiply-add (the
//    baseline has none, the ISA objects are compiled without), and a group whose states part is
//    solved state by state by the flat call itself.
//  - the source compiled alone (no CMake), at the baseline: two doubles a vector, bit for bit too;
//    with SWEEPGEN_BATCH_STATE_BY_STATE (the report's builds), state by state: one a vector.
//  - ARCH x86-64-v3 (-march=x86-64-v3, contraction left on, as the README documents it): the two
//    calls round differently where the compiler fuses differently; every status must agree and,
//    on the states that are not rank-deficient, each of q̈, τcmd and ν of the batch must lie within
//    kArchRelation eps κ of the flat call's (‖a − b‖∞ / max(1, ‖b‖∞), κ as the generated-scene
//    tests take it).
// A CPU without AVX2 (AVX-512) skips what needs it, counted and printed.
// The generated scenes' own tests (tests/generated/scene_test.cpp.in) compare each bundled
// scene's batch entry points with its flat calls the same way: in the lanes this CPU picks for the
// scenes of SWEEPGEN_BATCH_ISA_SCENES, state by state for the others (cmake/BundledScenes.cmake).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "emit/scene_request.hpp"
#include "oracle/condition_number.hpp"
#include "oracle/relative_error.hpp"
#include "report/stability_errors.hpp"
#include "scene/scene.hpp"
#include "solver/joint_inertia.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/flat_problem.hpp"
#include "support/run_command.hpp"
#include "support/skip_count.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

// Both calls of the ARCH x86-64-v3 build are the traced operations rounded in another order: each
// lies within kSameOperations = 40 eps κ of ReferenceSolver<double> (tests/support/generated_check.cpp,
// (1); measured 13.5 where FMA contraction adds to the folding, tests/test_emitter.cpp), so the two
// within twice that of each other.
constexpr double kArchRelation = 2 * 40;

// Reads states in rows (value k of state s on line k, the states' values in hexadecimal) and, for
// each entry-point set named on the command line, solves them with every policy's batch entry
// point and state by state with the flat one, and prints "<set> <double outputs whose bits differ>
// <float ones> <status bits seen> <batch_lanes() double> <float>" (NaN against NaN counts as
// equal). Sets: batch (batch_solves: what a program calls), x86_64_v3 and x86_64_v4 (the ISA
// objects' own, with -DISA_OBJECTS), values (prints the original policy's double outputs, batch
// then flat, a line per state).
constexpr const char* kDriver = R"(#include "batch_check.hpp"
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>
#if defined(ISA_OBJECTS)
#define ISA_ENTRY_POINTS(isa, tag, Scalar)                                   \
  namespace batch_check::tag::isa {                                          \
  void solve_original_batch(int n, const Scalar* in, Scalar* out) noexcept;  \
  void solve_saturate_batch(int n, const Scalar* in, Scalar* out) noexcept;  \
  int batch_lanes() noexcept;                                                \
  }
ISA_ENTRY_POINTS(x86_64_v3, f64, double)
ISA_ENTRY_POINTS(x86_64_v3, f32, float)
ISA_ENTRY_POINTS(x86_64_v4, f64, double)
ISA_ENTRY_POINTS(x86_64_v4, f32, float)
#define ISA_SOLVES(isa, tag) {{"original", &tag::isa::solve_original_batch}, {"saturate", &tag::isa::solve_saturate_batch}}
#endif
template <class Scalar, class Solves, class Batch>
long differing(const Solves& solves, const Batch* batches, int in_size, int out_size, int n, const std::vector<double>& rows,
               unsigned& seen) {
  std::vector<Scalar> in(rows.begin(), rows.end()), out(static_cast<std::size_t>(out_size) * n), one_in(in_size), one_out(out_size);
  long count = 0;
  for (std::size_t p = 0; p < std::size(solves); ++p) {
    if (std::strcmp(solves[p].policy, batches[p].policy) != 0) return -1;
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
int main(int argc, char** argv) {
  using namespace batch_check;
  int n = 0;
  if (std::scanf("%d", &n) != 1) return 2;
  std::vector<double> rows(static_cast<std::size_t>(f64::flat_in_size) * n);
  for (double& v : rows) if (std::scanf("%la", &v) != 1) return 2;
  for (int a = 1; a < argc; ++a) {
    const std::string set = argv[a];
    const f64::BatchSolve* batch64 = f64::batch_solves;
    const f32::BatchSolve* batch32 = f32::batch_solves;
    int lanes64 = f64::batch_lanes(), lanes32 = f32::batch_lanes();
#if defined(ISA_OBJECTS)
    static const f64::BatchSolve v3_64[] = ISA_SOLVES(x86_64_v3, f64), v4_64[] = ISA_SOLVES(x86_64_v4, f64);
    static const f32::BatchSolve v3_32[] = ISA_SOLVES(x86_64_v3, f32), v4_32[] = ISA_SOLVES(x86_64_v4, f32);
    if (set == "x86_64_v3") batch64 = v3_64, batch32 = v3_32, lanes64 = f64::x86_64_v3::batch_lanes(), lanes32 = f32::x86_64_v3::batch_lanes();
    if (set == "x86_64_v4") batch64 = v4_64, batch32 = v4_32, lanes64 = f64::x86_64_v4::batch_lanes(), lanes32 = f32::x86_64_v4::batch_lanes();
#endif
    if (set == "values") {
      std::vector<double> out(static_cast<std::size_t>(f64::flat_out_size) * n), one_in(f64::flat_in_size), one_out(f64::flat_out_size);
      f64::batch_solves[0].solve(n, rows.data(), out.data());
      for (int s = 0; s < n; ++s) {
        for (int k = 0; k < f64::flat_in_size; ++k) one_in[k] = rows[k * n + s];
        f64::flat_solves[0].solve(one_in.data(), one_out.data());
        for (int k = 0; k < f64::flat_out_size; ++k) std::printf("%a ", out[k * n + s]);
        for (int k = 0; k < f64::flat_out_size; ++k) std::printf("%a ", one_out[k]);
        std::printf("\n");
      }
      continue;
    }
    unsigned seen = 0;
    const long d64 = differing<double>(f64::flat_solves, batch64, f64::flat_in_size, f64::flat_out_size, n, rows, seen);
    const long d32 = differing<float>(f32::flat_solves, batch32, f32::flat_in_size, f32::flat_out_size, n, rows, seen);
    std::printf("%s %ld %ld %u %d %d\n", set.c_str(), d64, d32, seen, lanes64, lanes32);
  }
}
)";

// The source at the x86-64 baseline includes this file to be compiled for an ISA, as
// sweepgen_solver_library's wrappers do.
std::string isa_wrapper(const std::string& isa) { return "#define SWEEPGEN_BATCH_ISA " + isa + "\n#include \"batch_check.cpp\"\n"; }

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
  const solver::FlatLayout layout = s.flat_layout(chain);
  ASSERT_EQ(layout.input_directions.size(), 2u);

  test::TempDir dir;
  const emit::EmittedSolver emitted = emit::emit_solver(chain, emit::emit_request(s, "test"));
  for (const auto& file : emitted.files) std::ofstream(dir.path() / file.name) << file.text;
  std::ofstream(dir.path() / "driver.cpp") << kDriver;
  std::ofstream(dir.path() / "batch_check_x86_64_v3.cpp") << isa_wrapper("x86_64_v3");
  std::ofstream(dir.path() / "batch_check_x86_64_v4.cpp") << isa_wrapper("x86_64_v4");

  constexpr int kParting = 203, kStates = kParting + 64;
  test::RandomProblem random(23);
  std::vector<test::FlatProblem> drawn;
  std::vector<std::vector<double>> states;
  for (int state = 0; state < kStates; ++state) {
    drawn.push_back(test::random_flat_problem(random, s, chain));
    std::vector<double> in = drawn.back().in;
    if (state < kParting) test::part_from_group(in, layout, static_cast<std::size_t>(state));
    states.push_back(std::move(in));
  }
  std::ostringstream input;
  input << kStates << "\n" << std::hexfloat;
  for (std::size_t k = 0; k < layout.in_size(); ++k)
    for (const auto& in : states) input << in[k] << "\n";

  __builtin_cpu_init();
  const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                  __builtin_cpu_supports("bmi2");
  const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                  __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
                  __builtin_cpu_supports("avx512cd");
  const auto run = [&](const std::string& name, const std::vector<std::vector<std::string>>& compiles,
                       const std::vector<std::string>& sets) {
    const std::string binary = (dir.path() / ("driver_" + std::to_string(std::hash<std::string>{}(name)))).string();
    std::vector<std::string> objects;
    for (const auto& compile : compiles) {
      std::vector<std::string> command{"c++", "-std=c++17", "-O2", "-c", "-I", dir.path().string()};
      command.insert(command.end(), compile.begin() + 1, compile.end());
      objects.push_back(binary + "_" + std::to_string(objects.size()) + ".o");
      command.insert(command.end(), {(dir.path() / compile.front()).string(), "-o", objects.back()});
      const test::CommandResult build = test::run_command(test::shell_command(command));
      EXPECT_EQ(build.exit_code, 0) << name << ": " << compile.front() << "\n" << build.err;
      if (build.exit_code != 0) return std::string();
    }
    std::vector<std::string> link{"c++"};
    link.insert(link.end(), objects.begin(), objects.end());
    link.insert(link.end(), {"-o", binary});
    const test::CommandResult linked = test::run_command(test::shell_command(link));
    EXPECT_EQ(linked.exit_code, 0) << name << "\n" << linked.err;
    std::vector<std::string> command{binary};
    command.insert(command.end(), sets.begin(), sets.end());
    const test::CommandResult ran = test::run_command(test::shell_command(command), input.str());
    EXPECT_EQ(ran.exit_code, 0) << name << "\n" << ran.err;
    return ran.out;
  };
  // One line of the driver: every output bit for bit the flat call's, the states part as intended
  // (some rank-deficient, some saturated, some not finite), and the lanes expected.
  const auto expect_line = [&](const std::string& name, std::istream& lines, bool bit_for_bit, int lanes) {
    std::string set;
    long differing_f64 = -1, differing_f32 = -1;
    unsigned seen = 0;
    int lanes_f64 = 0, lanes_f32 = 0;
    lines >> set >> differing_f64 >> differing_f32 >> seen >> lanes_f64 >> lanes_f32;
    std::cout << "[batch] " << name << " (" << set << ", " << lanes_f64 << " doubles and " << lanes_f32 << " floats a vector): "
              << kStates << " states, two policies: " << differing_f64 << " double and " << differing_f32
              << " float outputs differ from the flat calls; status bits seen " << seen << "\n";
    if (bit_for_bit) {
      EXPECT_EQ(differing_f64, 0) << name;
      EXPECT_EQ(differing_f32, 0) << name;
    }
    EXPECT_EQ(lanes_f64, lanes) << name;
    EXPECT_EQ(lanes_f32, lanes == 1 ? 1 : 2 * lanes) << name;
    EXPECT_NE(seen & solver::status_constraint_rank_deficient, 0u) << name;
    EXPECT_NE(seen & solver::status_saturated, 0u) << name;
    EXPECT_NE(seen & solver::status_not_finite, 0u) << name;
  };
  // Of the six builds below, three need AVX2 or AVX-512.
  test::SkipCount unsupported("batch lane widths and builds this CPU does not run", 3.0 / 6.0);

  // sweepgen_add_solver without ARCH: what a program calls, and each ISA object the CPU runs.
  {
    const std::string name = "sweepgen_add_solver, no ARCH";
    std::vector<std::string> sets{"batch"};
    unsupported.skip(false, "the program's entry points");
    if (!unsupported.skip(!v3, "x86-64-v3 object, 4 doubles a vector")) sets.push_back("x86_64_v3");
    if (!unsupported.skip(!v4, "x86-64-v4 object, 8 doubles a vector")) sets.push_back("x86_64_v4");
    std::istringstream lines(run(name,
                                 {{"batch_check.cpp", "-DSWEEPGEN_BATCH_X86_64_V3", "-DSWEEPGEN_BATCH_X86_64_V4"},
                                  {"batch_check_x86_64_v3.cpp", "-march=x86-64-v3", "-ffp-contract=off"},
                                  {"batch_check_x86_64_v4.cpp", "-march=x86-64-v4", "-ffp-contract=off"},
                                  {"driver.cpp", "-DISA_OBJECTS"}},
                                 sets));
    expect_line(name + ", the program's entry points", lines, true, v4 ? 8 : v3 ? 4 : 1);
    if (v3) expect_line(name + ", the x86-64-v3 object's", lines, true, 4);
    if (v4) expect_line(name + ", the x86-64-v4 object's", lines, true, 8);
  }
  // The source compiled alone, at the baseline: its own two-double lanes.
  {
    const std::string name = "the source alone, x86-64 baseline";
    unsupported.skip(false, name.c_str());
    std::istringstream lines(run(name, {{"batch_check.cpp"}, {"driver.cpp"}}, {"batch"}));
    expect_line(name, lines, true, 2);
  }
  // ... and with SWEEPGEN_BATCH_STATE_BY_STATE: no lanes, the batch entry points the flat call's loop.
  {
    const std::string name = "the source alone, SWEEPGEN_BATCH_STATE_BY_STATE";
    unsupported.skip(false, name.c_str());
    std::istringstream lines(run(name, {{"batch_check.cpp", "-DSWEEPGEN_BATCH_STATE_BY_STATE"}, {"driver.cpp"}}, {"batch"}));
    expect_line(name, lines, true, 1);
  }
  // ARCH x86-64-v3: contracted, within kArchRelation eps κ.
  if (!unsupported.skip(!v3, "ARCH x86-64-v3 build")) {
    const std::string name = "ARCH x86-64-v3";
    std::istringstream lines(run(name, {{"batch_check.cpp", "-march=x86-64-v3"}, {"driver.cpp", "-march=x86-64-v3"}},
                                 {"batch", "values"}));
    expect_line(name, lines, false, 4);
    solver::SolverOptions options = s.solver_options();
    options.pivot_tolerance = options.pivot_tolerance_for(std::numeric_limits<double>::epsilon());
    options.joint_inertia_tolerance = options.joint_inertia_tolerance_for(std::numeric_limits<double>::epsilon());
    solver::ReferenceSolver<long double> reference(chain, s.layout, options);
    test::SkipCount judged("ARCH x86-64-v3: states judged against eps κ (not parted by hand, not rank-deficient)", 0.6);
    double worst = 0, worst_kappa = 0;
    int differing_states = 0;
    const std::size_t n = layout.out_size();
    for (int state = 0; state < kStates; ++state) {
      std::vector<double> batch(n), flat(n);
      const auto read = [&lines](double& v) {  // hexadecimal: strtod (an istream does not read it)
        std::string token;
        lines >> token;
        v = std::strtod(token.c_str(), nullptr);
      };
      for (double& v : batch) read(v);
      for (double& v : flat) read(v);
      ASSERT_TRUE(lines) << "state " << state;
      EXPECT_EQ(batch[layout.status()], flat[layout.status()]) << "state " << state;
      differing_states += batch != flat;
      const bool parted = state < kParting && state % 3 == 0;
      const bool deficient = static_cast<unsigned>(flat[layout.status()]) & solver::status_constraint_rank_deficient;
      if (judged.skip(parted || deficient, parted ? "parted from its group by hand" : "rank-deficient")) continue;
      reference.prepare(drawn[static_cast<std::size_t>(state)].cast<long double>());
      const double k = report::kappa(oracle::scaled_condition_number(reference.articulated().body[0].constraint_energy),
                                     static_cast<double>(solver::min_relative_joint_inertia(reference.model(), reference.articulated())));
      const auto part = [&](const std::vector<double>& v, std::size_t offset, std::size_t count) {
        return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(offset), v.begin() + static_cast<std::ptrdiff_t>(offset + count));
      };
      const double error = std::max({oracle::relative_error(part(batch, layout.qdd(), layout.dof), part(flat, layout.qdd(), layout.dof)),
                                     oracle::relative_error(part(batch, layout.tau_cmd(), layout.dof), part(flat, layout.tau_cmd(), layout.dof)),
                                     oracle::relative_error(part(batch, layout.nu(), layout.constraints), part(flat, layout.nu(), layout.constraints))}) /
                           (std::numeric_limits<double>::epsilon() * k);
      if (error > worst) worst = error, worst_kappa = k;
      EXPECT_LE(error, kArchRelation) << "state " << state << ", kappa " << k;
    }
    std::cout << "[batch] " << name << ": " << differing_states << " of " << kStates << " states differ from their flat calls; worst "
              << worst << " eps kappa (kappa " << worst_kappa << "), ceiling " << kArchRelation << "\n";
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// `sweepgen report --scene S --judge FILE` (report/flat_judgement.hpp): a solver's flat results
// from elsewhere (a GPU's, bench/gpu/run.sh) judged against the binary128 referee. Here the
// results are ReferenceSolver<double>'s, written as the GPU benchmark writes its sample; then one
// fault at a time: a perturbed q̈, a wrong status word, a malformed line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "solver/flat_layout.hpp"
#include "solver/reference_solver.hpp"
#include "support/run_command.hpp"
#include "support/temp_dir.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using test::run_command;
using test::shell_command;

std::string scene_path(const std::string& relative) { return std::string(SWEEPGEN_SOURCE_DIR) + "/robots/" + relative; }

// A line per state: the flat input, then `result` applied to ReferenceSolver<double>'s flat output.
template <class Result>
void write_results(const std::string& scene_file, const std::string& file, std::size_t states, Result&& result) {
  const scene::Scene s = scene::load_scene(scene_file);
  const model::Chain chain = scene::load_scene_chain(s);
  const solver::FlatLayout layout = s.flat_layout(chain);
  solver::ReferenceSolver<double> reference(chain, s.layout, s.solver_options());
  std::FILE* out = std::fopen(file.c_str(), "w");
  ASSERT_NE(out, nullptr);
  std::fprintf(out, "# %zu states of %s\n", states, scene_file.c_str());
  std::size_t k = 0;
  for (const report::Problem& p : report::random_problems(s, chain, states, 5)) {
    reference.prepare(p);
    const auto& solution = reference.solve(solver::Policy::original, p.beta);
    std::vector<double> values(layout.out_size());
    solver::flat_output(solution, reference.status(), layout, values.data());
    result(layout, k++, values);
    for (double v : p.flat) std::fprintf(out, "%a ", v);
    for (double v : values) std::fprintf(out, "%a ", v);
    std::fprintf(out, "\n");
  }
  std::fclose(out);
}

test::CommandResult judge(const std::string& scene_file, const std::string& file) {
  return run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", scene_file, "--judge", file}));
}

// The count in the summary line's "<count> <label>".
long summary_count(const std::string& out, const std::string& label) {
  test::Match m;
  if (!test::Pattern("(\\d+) " + label).search(out, m)) return -1;
  return std::stol(m[1]);
}

const auto unchanged = [](const solver::FlatLayout&, std::size_t, std::vector<double>&) {};

// Every result (planar_nc2: τcmd, τctrl, the tip's acceleration too) and a lean scene's q̈ and ν
// with six run-time directions (panda_lean_nc6).
TEST(FlatJudgement, ASolversOwnResultsPass) {
  test::TempDir dir;
  for (const std::string scene : {"planar/planar_nc2.yaml", "panda/panda_lean_nc6.yaml", "quadruped/quadruped_stance.yaml"}) {
    const std::string file = (dir.path() / "results.txt").string();
    write_results(scene_path(scene), file, 40, unchanged);
    const test::CommandResult r = judge(scene_path(scene), file);
    EXPECT_EQ(r.exit_code, 0) << scene << "\n" << r.out << r.err;
    EXPECT_NE(r.out.find("passed"), std::string::npos) << r.out;
    EXPECT_EQ(summary_count(r.out, "states against"), 40) << r.out;
    EXPECT_GE(summary_count(r.out, "judged"), 20) << scene << ": most random states are full rank\n" << r.out;
  }
}

// q̈_1 off by one part in a million of itself (the bound is 100 eps κ, 2.2e-14 κ, on the error of
// all of q̈ relative to its largest entry and to q̈ without the constraint): most judged states
// fail (18 of 20 here; where q̈_1 is small against the rest, 1e-6 of it may be within the bound).
TEST(FlatJudgement, APerturbedResultFails) {
  test::TempDir dir;
  const std::string scene = scene_path("panda/panda_lean_nc6.yaml"), file = (dir.path() / "results.txt").string();
  write_results(scene, file, 20, [](const solver::FlatLayout& layout, std::size_t, std::vector<double>& out) {
    out[layout.qdd()] *= 1 + 1e-6;
  });
  const test::CommandResult r = judge(scene, file);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILED"), std::string::npos) << r.out;
  EXPECT_GT(summary_count(r.out, "over the bound"), 0) << r.out;
  EXPECT_GT(2 * summary_count(r.out, "over the bound"), summary_count(r.out, "judged")) << r.out;
  EXPECT_TRUE(test::Pattern("state \\d+: error .* eps kappa").search(r.out)) << r.out;
}

TEST(FlatJudgement, AnotherStatusFails) {
  test::TempDir dir;
  const std::string scene = scene_path("planar/planar_nc2.yaml"), file = (dir.path() / "results.txt").string();
  write_results(scene, file, 10, [](const solver::FlatLayout& layout, std::size_t state, std::vector<double>& out) {
    if (state == 3) out[layout.status()] = static_cast<double>(solver::status_constraint_rank_deficient);
  });
  const test::CommandResult r = judge(scene, file);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("state 3: status 1, the referee's 0"), std::string::npos) << r.out;
  EXPECT_EQ(summary_count(r.out, "with another status"), 1) << r.out;
}

TEST(FlatJudgement, AMalformedLineNamesTheFileAndLine) {
  test::TempDir dir;
  const std::string scene = scene_path("planar/planar_nc2.yaml"), file = (dir.path() / "results.txt").string();
  write_results(scene, file, 3, unchanged);
  std::ofstream(file, std::ios::app) << "1 2 3\n";
  test::CommandResult r = judge(scene, file);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("line 5"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("3 numbers"), std::string::npos) << r.err;
  std::ofstream(file) << "0x1p+0 seven\n";
  r = judge(scene, file);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.err.find("not a number: 'seven'"), std::string::npos) << r.err;
  r = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--judge", file}));
  EXPECT_EQ(r.exit_code, 2) << "--judge needs one --scene\n" << r.err;
}

// solve_inputs_from_flat is flat_input's inverse: a fixed base with run-time directions, and a
// floating base (its rotation in q) with fixed ones.
TEST(FlatJudgement, FlatInputsReadBackExactly) {
  for (const std::string scene : {"panda/panda_sets.yaml", "quadruped/quadruped_stance.yaml", "planar/planar_nc2.yaml"}) {
    const scene::Scene s = scene::load_scene(scene_path(scene));
    const model::Chain chain = scene::load_scene_chain(s);
    const solver::FlatLayout layout = s.flat_layout(chain);
    for (const report::Problem& p : report::random_problems(s, chain, 5, 9)) {
      const solver::SolveInputs<double> back = solver::solve_inputs_from_flat(p.flat.data(), layout, s.layout);
      EXPECT_EQ(solver::flat_input(back, layout), p.flat) << scene;
      ASSERT_EQ(back.alpha.size(), p.alpha.size()) << scene;
      for (std::size_t k = 0; k < p.alpha.size(); ++k) {
        EXPECT_EQ(back.alpha[k].moment, p.alpha[k].moment) << scene << " direction " << k;
        EXPECT_EQ(back.alpha[k].force, p.alpha[k].force) << scene << " direction " << k;
      }
    }
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

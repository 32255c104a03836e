// `sweepgen solve`: the reference solver on JSON lines.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>

namespace sweepgen::cli {

struct SolveOptions {
  std::string scene;  // a scene file: its chain, gravity, drivers, policies and outputs (scene_problem.hpp)
  std::string urdf;
  std::string root;
  std::string tip;
  std::vector<std::string> branch_tips;  // further tips: the tree of all root-to-tip paths
  bool floating_base = false;
  std::string mimic;            // --mimic: independent | coupled (docs/derivation.md, M1)
  bool literal_angles = false;  // --no-snap-quarter-turns
  std::string input = "-";
  std::vector<std::string> rotor_inertia;  // JOINT=VALUE
};

void add_solve_command(CLI::App& app, SolveOptions& options);

// Reads one JSON object per line, answers one per line in input order. Returns the exit
// code: 0 if every line was answered, 1 if any line had an error (reported on stderr and as
// {"line": N, "error": "..."} in the output).
int run_solve(const SolveOptions& options);

}  // namespace sweepgen::cli

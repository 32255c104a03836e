// `sweepgen report`: for each scene, generate its solver, compile it with the system compiler in
// every variant the scene can use, load it into this process and measure it on named families
// of states next to the reference solver, KDL and a dense KKT solve: error against a binary128
// referee and time per call (report/study.hpp). README, "sweepgen report".
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sweepgen::report {

struct ReportOptions {
  std::vector<std::string> scenes;  // scene files (none: every bundled scene and kStiffCases), or
  std::string urdf;   // a URDF for the default scene (with root / tip)
  std::string root;
  std::string tip;
  std::vector<std::string> family_cases;  // synthetic robots of `sweepgen family` studied like scenes
  std::size_t states = 40;  // per state family
  // A report in seconds: one compile per scene, without --scene only the Panda, and (the command
  // line's defaults, report_command.cpp) fewer states and passes unless --states or --repetitions is given.
  bool quick = false;
  std::string out;  // empty: "report", or "stability" with --stability
  // --stability (report/stability_command.hpp) and its options
  bool stability = false;
  std::vector<std::string> cases;
  std::size_t states_per_kind = 10;
  bool full = false;
  unsigned long long seed = 1;
  int repetitions = 10;
  std::string cxx = "c++";
  std::string judge;  // --judge FILE: a solver's flat results judged (report/flat_judgement.hpp)
};

// The family cases a full default report adds: the stiff mass ratios (docs/stability.md).
inline const std::vector<std::string> kStiffCases = {"mass_ratio_alternating", "mass_ratio_light_tool",
                                                     "mass_ratio_heavy_tool"};

void add_report_command(CLI::App& app, ReportOptions& options);

// Exit 0 on success (with --stability: run_stability_report; with --judge: 4 where the results
// miss the referee's bound). Throws InputError for a bad scene or URDF (exit 1) and io::IoError when
// a file cannot be written or the compiler, dlopen() or gnuplot fails (exit 3).
int run_report(const ReportOptions& options);

}  // namespace sweepgen::report

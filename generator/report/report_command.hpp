// `sweepgen report`: generate a scene's solver, compile it with the system compiler, load it
// into this process and measure it (run time and error against a long double reference)
// next to the reference solver and KDL. README, "sweepgen report".
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace sweepgen::report {

struct ReportOptions {
  std::string scene;  // scene file, or
  std::string urdf;   // a URDF for the default scene (with root / tip)
  std::string root;
  std::string tip;
  std::size_t states = 1000;
  std::string out;  // empty: "report", or "stability" with --stability
  // --stability (report/stability_command.hpp) and its options
  bool stability = false;
  std::vector<std::string> cases;
  std::size_t states_per_kind = 10;
  bool full = false;
  unsigned long long seed = 1;
  int repetitions = 20;
  std::string cxx = "c++";
};

void add_report_command(CLI::App& app, ReportOptions& options);

// Exit 0 on success (with --stability: run_stability_report). Throws InputError for a bad scene or URDF (exit 1) and io::IoError when
// a file cannot be written or the compiler, dlopen() or gnuplot fails (exit 3).
int run_report(const ReportOptions& options);

}  // namespace sweepgen::report

// `sweepgen report --stability`: error against condition number, per case, ill-conditioning
// policy and variant (docs/stability.md, "Stability report").
#pragma once

#include <string>
#include <vector>

namespace sweepgen::report {

struct StabilityOptions {
  std::vector<std::string> cases;  // empty: every family case not heavy (all with `full`) and the bundled scenes
  std::size_t states_per_kind = 10;
  bool full = false;
  unsigned long long seed = 1;
  std::string out;  // DIR: stability.csv, stability.png, build/
  std::string cxx = "c++";
};

// Every case name --cases takes: the family's, then the bundled scenes' (their solver names).
std::vector<std::string> stability_case_names();

// Exit 0 on success. Throws InputError for an unknown case (exit 1) and io::IoError when a file
// cannot be written or the compiler, dlopen() or gnuplot fails (exit 3).
int run_stability_report(const StabilityOptions& options);

}  // namespace sweepgen::report

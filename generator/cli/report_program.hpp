// `sweepgen report` runs sweepgen-report, the program beside this one (as git runs git-<command>):
// the report compiles the oracles and the measurement code (generator/oracle, generator/report),
// which `generate`, `info`, `solve` and `family` do not need, so that building those does not
// compile them (bench/README.md, "Build and CI time").
#pragma once

#include <string>
#include <vector>

namespace sweepgen::cli {

// The name sweepgen-report is built and installed under.
inline constexpr const char* kReportProgram = "sweepgen-report";

// Replaces this process by sweepgen-report in this program's directory, with `args` (the words
// after `report`). Returns only when that program cannot be run: 3, having said on standard error
// which file is missing and how to get it.
int run_report_program(const std::vector<std::string>& args);

}  // namespace sweepgen::cli

// The external programs `sweepgen report` needs, checked before any work: the C++ compiler it
// builds the generated solvers with (--cxx) and gnuplot, which draws the figures at the end. A
// missing one is an io::IoError (exit 3) at the start, not after minutes of measuring.
#pragma once

#include <string>

namespace sweepgen::report {

// Runs `cxx --version` and asks gnuplot for its terminals (logs in `work_dir`); throws io::IoError
// naming the program that cannot be run.
void check_external_tools(const std::string& cxx, const std::string& work_dir);

}  // namespace sweepgen::report

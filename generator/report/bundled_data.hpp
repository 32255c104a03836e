// Where `sweepgen report` finds the bundled robots/ (its default scenes and the stability suite's
// arms): in the installed package, beside the program (<prefix>/share/sweepgen/robots, found from
// the program's own path, so a moved installation still finds it), else in the source tree the
// program was built from.
#pragma once

#include <filesystem>

namespace sweepgen::report {

// The directory that holds robots/. Throws InputError naming both places when neither has it.
std::filesystem::path bundled_data_dir();

}  // namespace sweepgen::report

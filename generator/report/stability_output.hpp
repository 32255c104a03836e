// `sweepgen report --stability`: DIR/stability.csv, the summary table and DIR/stability.png
// (docs/stability.md, "Stability report").
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "report/stability_measure.hpp"

namespace sweepgen::report {

// The CSV columns, in order.
const std::vector<std::string>& stability_csv_columns();

// DIR/stability.csv text: the header, then one line per state and variant.
std::string stability_csv_text(const std::vector<StabilityRow>& rows);

// One line per case × policy × variant: states, rank-deficient, non-finite, beyond the scalar's
// range; over the full-rank states max error, max error/(eps κ) and max κ; max damped bias (over
// the states whose exact result fits the scalar).
void print_stability_table(const std::vector<StabilityRow>& rows, std::ostream& out);

// Writes the gnuplot script and data under `work_dir` and runs gnuplot to make `png_path`: error
// against κ (log-log) over the full-rank states, one series per variant × policy, with eps κ of
// double and float. Throws io::IoError when gnuplot cannot be run or fails.
void plot_stability(const std::vector<StabilityRow>& rows, const std::string& work_dir, const std::string& png_path);

}  // namespace sweepgen::report

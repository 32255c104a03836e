// `sweepgen report`: the table, DIR/report.csv and DIR/report.png (gnuplot).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "report/measure.hpp"

namespace sweepgen::report {

struct ReportRow {
  const VariantResult* result;
  Summary summary;
};

// The CSV columns, in order.
const std::vector<std::string>& csv_columns();

// DIR/report.csv text: the header, then one line per row. A row without measurements (a note)
// has its reason in the variant field ("kdl (KDL not found at build time)") and empty numbers.
std::string csv_text(const std::vector<ReportRow>& rows);

// The human-readable table.
void print_table(const std::vector<ReportRow>& rows, std::ostream& out);

// Writes the gnuplot script and data under `work_dir` and runs gnuplot to make `png_path`:
// max_rel_err_qdd (log y) against ns_median (log x), one labelled point per measured row.
// Throws io::IoError when gnuplot cannot be run or fails.
void plot(const std::vector<ReportRow>& rows, const std::string& title, const std::string& work_dir,
          const std::string& png_path);

}  // namespace sweepgen::report

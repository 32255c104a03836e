// Number and field formatting shared by the report's tables, CSV files and gnuplot scripts.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace sweepgen::report {

// `value` through the printf `pattern`; "nan", "inf", "-inf" for those.
std::string format(const char* pattern, double value);
// "1.234e-05"
std::string scientific(double value);
// "12.3 s"
std::string seconds(double value);

// A CSV field, double-quoted when it holds a comma, quote or newline ("" an embedded quote).
std::string csv_field(const std::string& text);
// The fields joined by commas, with a newline.
std::string csv_line(const std::vector<std::string>& fields);

// A string in single quotes for gnuplot ('' is a literal quote there).
std::string gnuplot_string(const std::string& text);

// Prints the rows with each column padded to its widest cell. A row shorter than the first (the
// header) neither sets widths nor is padded in its last cell (a note running across columns).
void print_aligned(const std::vector<std::vector<std::string>>& table, std::ostream& out);

}  // namespace sweepgen::report

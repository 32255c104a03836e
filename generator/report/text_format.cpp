#include "report/text_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sweepgen::report {

std::string format(const char* pattern, double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}
std::string scientific(double value) { return format("%.3e", value); }
std::string seconds(double value) { return format("%.1f s", value); }

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string csv_line(const std::vector<std::string>& fields) {
  std::string line;
  for (std::size_t i = 0; i < fields.size(); ++i) line += (i ? "," : "") + csv_field(fields[i]);
  return line + "\n";
}

std::string gnuplot_string(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

void print_aligned(const std::vector<std::vector<std::string>>& table, std::ostream& out) {
  if (table.empty()) return;
  std::vector<std::size_t> width(table.front().size(), 0);
  for (const auto& r : table)
    if (r.size() == width.size())
      for (std::size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
  for (const auto& r : table) {
    std::string line;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const bool last = i + 1 == r.size();
      std::string cell = r[i];
      if (!last) cell.resize(std::max(cell.size(), width[i]), ' ');
      line += cell + (last ? "" : "  ");
    }
    out << line << "\n";
  }
}

}  // namespace sweepgen::report

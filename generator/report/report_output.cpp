#include "report/report_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "io/output_files.hpp"
#include "report/gnuplot.hpp"
#include "report/text_format.hpp"

namespace sweepgen::report {
namespace {

std::string ns(double value) { return format("%.1f", value); }
std::string err(Precise value) { return format("%.3e", static_cast<double>(value)); }

std::string label(const ReportRow& row) {
  return row.result->note.empty() ? row.result->variant : row.result->variant + " (" + row.result->note + ")";
}

// The fields of a row, in csv_columns() order.
std::vector<std::string> fields(const ReportRow& row) {
  const Summary& s = row.summary;
  if (!row.result->note.empty()) {
    std::vector<std::string> f(csv_columns().size());
    f[0] = label(row);
    f[1] = row.result->scalar;
    return f;
  }
  return {row.result->variant,
          row.result->scalar,
          ns(s.ns_median),
          ns(s.ns_p90),
          err(s.max_rel_err_qdd),
          err(s.median_rel_err_qdd),
          err(s.max_rel_err_tau),
          err(s.max_constraint_residual),
          std::to_string(s.states),
          std::to_string(s.ill_conditioned_states),
          err(s.ill_conditioned_max_rel_err_qdd)};
}

}  // namespace

const std::vector<std::string>& csv_columns() {
  static const std::vector<std::string> columns = {
      "variant",         "scalar",           "ns_median", "ns_p90", "max_rel_err_qdd",        "median_rel_err_qdd",
      "max_rel_err_tau", "max_constraint_residual", "states", "ill_conditioned_states", "ill_conditioned_max_rel_err_qdd"};
  return columns;
}

std::string csv_text(const std::vector<ReportRow>& rows) {
  std::string text = csv_line(csv_columns());
  for (const auto& row : rows) text += csv_line(fields(row));
  return text;
}

void print_table(const std::vector<ReportRow>& rows, std::ostream& out) {
  const std::vector<std::string> header = {"variant", "scalar", "ns_median", "ns_p90", "max_err_qdd", "median_err_qdd",
                                           "max_err_tau", "max_residual", "states", "ill_cond", "ill_cond_max_err_qdd"};
  std::vector<std::vector<std::string>> table = {header};
  for (const auto& row : rows) {
    std::vector<std::string> f = fields(row);
    if (!row.result->note.empty()) f = {row.result->variant, row.result->scalar, row.result->note};
    table.push_back(f);
  }
  print_aligned(table, out);
}

void plot(const std::vector<ReportRow>& rows, const std::string& title, const std::string& work_dir,
          const std::string& png_path) {
  const std::string terminal = png_terminal(work_dir, 1000, 650);

  struct Point {
    std::string label;
    double x, y;
  };
  std::vector<Point> points;
  for (const auto& row : rows) {
    if (!row.result->note.empty()) continue;
    const double x = row.summary.ns_median;
    const double y = std::max(static_cast<double>(row.summary.max_rel_err_qdd), 1e-20);  // log scale: no zeros
    if (!(x > 0) || !std::isfinite(y)) continue;
    points.push_back({row.result->variant + " " + row.result->scalar, x, y});
  }
  if (points.empty()) throw io::IoError(png_path + ": nothing to plot (no variant has a finite time and error)");
  double x_min = 1e300, x_max = 0, y_min = 1e300, y_max = 0;
  for (const Point& p : points) {
    x_min = std::min(x_min, p.x);
    x_max = std::max(x_max, p.x);
    y_min = std::min(y_min, p.y);
    y_max = std::max(y_max, p.y);
  }
  x_min /= 2;
  x_max *= 6;
  y_min /= 30;
  y_max *= 30;

  // Labels: right of the point, above it, else below, else left of it, whichever overlaps no
  // other label or point first (in approximate pixels of the 1000x650 plot area).
  constexpr double kWidth = 880, kHeight = 540, kChar = 7.5, kLine = 15, kGap = 12;
  struct Box {
    double left, bottom, right, top;
    bool overlaps(const Box& o) const { return left < o.right && o.left < right && bottom < o.top && o.bottom < top; }
  };
  const auto pixel = [&](const Point& p) {
    return std::pair<double, double>{kWidth * std::log(p.x / x_min) / std::log(x_max / x_min),
                                     kHeight * std::log(p.y / y_min) / std::log(y_max / y_min)};
  };
  std::vector<Box> taken;
  for (const Point& p : points) {
    const auto [u, v] = pixel(p);
    taken.push_back({u - 8, v - 8, u + 8, v + 8});
  }
  std::ostringstream data, labels;
  data << std::setprecision(6);
  labels << std::setprecision(6);
  for (const Point& p : points) {
    const auto [u, v] = pixel(p);
    const double w = kChar * static_cast<double>(p.label.size());
    struct Candidate {
      Box box;
      const char* placement;
    };
    const Candidate candidates[] = {
        {{u + kGap, v + 2, u + kGap + w, v + 2 + kLine}, "left offset char 1.2,0.8"},
        {{u + kGap, v - 2 - kLine, u + kGap + w, v - 2}, "left offset char 1.2,-0.8"},
        {{u - kGap - w, v + 2, u - kGap, v + 2 + kLine}, "right offset char -1.2,0.8"},
        {{u - kGap - w, v - 2 - kLine, u - kGap, v - 2}, "right offset char -1.2,-0.8"},
    };
    const Candidate* chosen = &candidates[0];
    for (const Candidate& c : candidates) {
      bool free = c.box.left >= 0 && c.box.right <= kWidth && c.box.bottom >= 0 && c.box.top <= kHeight;
      for (const Box& t : taken) free = free && !c.box.overlaps(t);
      if (free) {
        chosen = &c;
        break;
      }
    }
    taken.push_back(chosen->box);
    data << p.x << " " << p.y << "\n";
    labels << "set label " << gnuplot_string(p.label) << " at " << p.x << "," << p.y << " " << chosen->placement
           << " noenhanced\n";
  }
  const std::string data_path = work_dir + "/report_plot.dat";
  const std::string script_path = work_dir + "/report_plot.gp";
  std::ostringstream script;
  script << std::setprecision(6);
  script << "# Written by `sweepgen report`: run `gnuplot " << script_path << "` to redraw.\n"
         << terminal
         << "set output " << gnuplot_string(png_path) << "\n"
         << "set title " << gnuplot_string(title) << " noenhanced\n"
         << "set logscale xy\n"
         << "set format y '10^{%L}'\n"
         << "set xlabel 'run time per solve, median [ns] (log)'\n"
         << "set ylabel 'max relative error of qdd vs quad (binary128), cond <= 1e6 (log)'\n"
         << "set grid xtics ytics mxtics\n"
         << "set key off\n"
         << "set xrange [" << x_min << ":" << x_max << "]\n"
         << "set yrange [" << y_min << ":" << y_max << "]\n"
         << labels.str()
         << "plot " << gnuplot_string(data_path) << " using 1:2 with points pointtype 7 pointsize 2 linecolor rgb '#1f5fa8'\n";
  io::write_files_atomically({{data_path, data.str()}, {script_path, script.str()}});
  run_gnuplot(script_path, png_path, work_dir);
}

}  // namespace sweepgen::report

#include "report/stability_output.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "io/output_files.hpp"
#include "report/gnuplot.hpp"
#include "report/text_format.hpp"

namespace sweepgen::report {
namespace {

std::string yes_no(bool b) { return b ? "1" : "0"; }
std::string err(double e) { return format("%.3e", e); }

std::string series(const StabilityRow& r) { return r.variant + " " + r.scalar + ", " + r.policy; }

// A log axis cannot show 0: exact results are drawn at this floor (said on the axis).
constexpr double kZeroFloor = 1e-20;

}  // namespace

const std::vector<std::string>& stability_csv_columns() {
  static const std::vector<std::string> columns = {
      "case",          "policy",        "variant",         "scalar",     "state",
      "kind",          "cond_s_E",      "min_rho_D",       "cond_M",     "kappa",
      "rel_err_qdd",   "rel_err_tau_cmd", "rel_err_nu",    "constraint_residual", "status",
      "referee_status", "finite",       "representable",   "bias_vs_pivoted"};
  return columns;
}

std::string stability_csv_text(const std::vector<StabilityRow>& rows) {
  std::string text = csv_line(stability_csv_columns());
  for (const StabilityRow& r : rows) {
    const StateJudgement& j = r.judgement;
    text += csv_line({r.case_name, r.policy, r.variant, r.scalar, std::to_string(r.state), r.kind, err(j.cond_E),
                      err(j.rho_D), err(j.cond_M), err(j.kappa()), err(j.qdd), err(j.tau), err(j.nu),
                      err(j.constraint_residual), std::to_string(j.status),
                      std::to_string(j.exact_status), yes_no(j.finite), yes_no(j.representable),
                      std::isnan(r.bias_vs_pivoted) ? "" : err(r.bias_vs_pivoted)});
  }
  return text;
}

void print_stability_table(const std::vector<StabilityRow>& rows, std::ostream& out) {
  std::vector<std::vector<std::string>> table = {{"case", "policy", "variant", "states", "rank_def", "non_finite",
                                                  "beyond_range", "max_err_full_rank", "max_err/(eps*kappa)",
                                                  "max_kappa_full_rank", "max_cond_M", "max_residual_full_rank",
                                                  "max_bias_vs_pivoted"}};
  // Rows arrive grouped by case, policy and variant (measure_stability_case's order).
  for (std::size_t first = 0; first < rows.size();) {
    std::size_t last = first;
    while (last < rows.size() && rows[last].case_name == rows[first].case_name &&
           rows[last].policy == rows[first].policy && series(rows[last]) == series(rows[first]))
      ++last;
    std::size_t deficient = 0, non_finite = 0, beyond = 0, full_rank = 0;
    double max_err = 0, max_ratio = 0, max_kappa = 1, max_cond_M = 1, max_residual = 0, max_bias = 0;
    const double eps = epsilon_of(rows[first].scalar);
    for (std::size_t k = first; k < last; ++k) {
      const StateJudgement& j = rows[k].judgement;
      non_finite += !j.finite;
      beyond += !j.representable;
      deficient += j.representable && !j.full_rank();
      max_cond_M = std::max(max_cond_M, j.cond_M);
      if (j.full_rank()) {
        ++full_rank;
        max_kappa = std::max(max_kappa, j.kappa());
        max_err = std::max(max_err, j.error());
        max_ratio = std::max(max_ratio, j.error() / (eps * j.kappa()));
        max_residual = std::max(max_residual, j.constraint_residual);
      }
      if (j.representable) max_bias = std::max(max_bias, rows[k].bias_vs_pivoted);
    }
    // "-" where there is no full-rank state (a maximum over none is no figure).
    const StabilityRow& r = rows[first];
    table.push_back({r.case_name, r.policy, r.variant + " " + r.scalar, std::to_string(last - first),
                     std::to_string(deficient), std::to_string(non_finite), std::to_string(beyond),
                     full_rank ? err(max_err) : "-", full_rank ? format("%.2f", max_ratio) : "-",
                     full_rank ? err(max_kappa) : "-", err(max_cond_M), full_rank ? err(max_residual) : "-",
                     std::isnan(r.bias_vs_pivoted) ? "-" : err(max_bias)});
    first = last;
  }
  print_aligned(table, out);
}

void plot_stability(const std::vector<StabilityRow>& rows, const std::string& work_dir, const std::string& png_path) {
  const std::string terminal = png_terminal(work_dir, 1100, 750);
  // One data block per series (gnuplot's `index`), in first-appearance order.
  std::vector<std::string> names;
  std::vector<std::ostringstream> blocks;
  double kappa_max = 10, error_min = 1e-7, error_max = 1e-15;
  // A state can be full rank for its policy and still have kappa = inf: the damped policy meets a
  // redundant direction that asks for a compatible motion without raising a status, while
  // cond_s(E) is infinite. No log axis holds it: counted in the title instead.
  std::size_t infinite_kappa = 0;
  for (const StabilityRow& r : rows) {
    const StateJudgement& j = r.judgement;
    if (!j.full_rank() || !std::isfinite(j.error())) continue;
    if (!std::isfinite(j.kappa())) {
      ++infinite_kappa;
      continue;
    }
    const std::string name = series(r);
    auto at = std::find(names.begin(), names.end(), name);
    if (at == names.end()) {
      names.push_back(name);
      blocks.emplace_back();
      blocks.back() << std::setprecision(6);
      at = names.end() - 1;
    }
    const double e = std::max(j.error(), kZeroFloor);
    blocks[static_cast<std::size_t>(at - names.begin())] << j.kappa() << " " << e << "\n";
    kappa_max = std::max(kappa_max, j.kappa());
    error_min = std::min(error_min, e);
    error_max = std::max(error_max, e);
  }
  if (names.empty()) throw io::IoError(png_path + ": nothing to plot (no full-rank state with a finite error)");
  std::string data;
  for (const auto& b : blocks) data += b.str() + "\n\n";

  const std::string data_path = work_dir + "/stability_plot.dat";
  const std::string script_path = work_dir + "/stability_plot.gp";
  std::ostringstream script;
  script << std::setprecision(6);
  // Colour by variant, filled marks for pivoted_ldlt and open ones for damped.
  script << "# Written by `sweepgen report --stability`: run `gnuplot " << script_path << "` to redraw.\n"
         << terminal << "set output " << gnuplot_string(png_path) << "\n"
         << "set title 'sweepgen report --stability: error against the binary128 referee, full-rank states"
         << (infinite_kappa > 0 ? " (" + std::to_string(infinite_kappa) + " with kappa = inf not drawn)" : std::string())
         << "' noenhanced\n"
         << "set logscale xy\n"
         << "set format x '10^{%L}'\nset format y '10^{%L}'\n"
         << "set xlabel 'kappa = max(1, cond_s(E^A_{cstr,0}), 1/min rho_D)'\n"
         << "set ylabel 'max relative error of qdd, tau_{cmd}, nu (exact: drawn at 10^{-20})'\n"
         << "set grid xtics ytics\n"
         << kKeyBelowPlot << " box\n"
         << "set xrange [0.5:" << kappa_max * 3 << "]\n"
         << "set yrange [" << error_min / 10 << ":" << std::max(error_max * 10, 1.0) << "]\n"
         << "eps_double = " << std::numeric_limits<double>::epsilon() << "\n"
         << "eps_float = " << std::numeric_limits<float>::epsilon() << "\n"
         << "plot ";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const bool damped = names[i].find("damped") != std::string::npos;
    const char* colour = names[i].rfind("reference", 0) == 0 ? "#1b7837"
                         : names[i].find("float") != std::string::npos ? "#d95f02" : "#1f5fa8";
    script << gnuplot_string(data_path) << " index " << i << " using 1:2 with points pointtype "
           << (damped ? 6 : 7) << " pointsize " << (damped ? 1.6 : 1.0) << " linecolor rgb '" << colour
           << "' title " << gnuplot_string(names[i]) << " noenhanced, \\\n     ";
  }
  script << "eps_double * x with lines dashtype 2 linewidth 2 linecolor rgb '#555555' title 'eps_{double} kappa', \\\n"
         << "     eps_float * x with lines dashtype 3 linewidth 2 linecolor rgb '#555555' title 'eps_{float} kappa'\n";
  io::write_files_atomically({{data_path, data}, {script_path, script.str()}});
  run_gnuplot(script_path, png_path, work_dir);
}

}  // namespace sweepgen::report

#include "report/study_output.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "report/gnuplot.hpp"
#include "report/study_reasons.hpp"
#include "report/text_format.hpp"

namespace sweepgen::report {
namespace {

// Log axes take no zeros: exact answers are drawn at this floor (the captions say so).
constexpr double kPlotFloor = 1e-20;

std::string ns(double value) { return format("%.0f", value); }
// An error statistic of `e`'s judged states, or why there is none.
std::string error_cell(const FamilyErrors& e, double value) { return e.judged == 0 ? "none judged" : scientific(value); }
std::string share(std::size_t part, std::size_t whole) {
  return whole == 0 ? "-" : format("%.1f%%", 100.0 * static_cast<double>(part) / static_cast<double>(whole));
}

// KDL's median time over this variant's (how many times faster than KDL), "" without a KDL row.
std::string kdl_ratio(const SceneStudy& s, const VariantStudy& v) {
  for (const VariantStudy& kdl : s.variants)
    if (kdl.name == "KDL" && kdl.note.empty() && v.note.empty() && v.ns_median > 0)
      return format("%.1f", kdl.ns_median / v.ns_median);
  return "";
}

std::vector<std::string> summary_cells(const SceneStudy& s, const VariantStudy& v) {
  if (!v.note.empty()) return {v.name, v.scalar, v.note};
  const std::string operations = v.operations > 0 ? std::to_string(v.operations) : "";
  if (v.referee)
    return {v.name, v.scalar, operations, ns(v.ns_median), ns(v.ns_p99), ns(v.ns_max), kdl_ratio(s, v), "0 (referee)",
            "", "", "", ""};
  return {v.name,
          v.scalar,
          operations,
          ns(v.ns_median),
          ns(v.ns_p99),
          ns(v.ns_max),
          kdl_ratio(s, v),
          error_cell(v.all, v.all.median),
          error_cell(v.all, v.all.p99),
          error_cell(v.all, v.all.max),
          error_cell(v.all, v.all.max_residual),
          share(v.all.status_raised, v.all.states)};
}

const std::vector<std::string>& summary_header() {
  static const std::vector<std::string> header = {"variant", "scalar",     "ops",     "ns_median", "ns_p99",
                                                  "ns_max",  "kdl_x",      "err_median", "err_p99", "err_max",
                                                  "max_residual", "status"};
  return header;
}

// The column of the summary table named `name`.
std::size_t summary_column(const std::string& name) {
  const std::vector<std::string>& header = summary_header();
  return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
}

// A scene's summary rows with the reasons beside their large numbers: an err_max or max_residual
// that is large for a stated reason (study_reasons.hpp, row_reasons) carries a marker [k], and
// note k, right under the table, says why; rows with the same reason share a note. The bullets
// per family further down give the counts.
struct SummaryTable {
  std::vector<std::vector<std::string>> rows;
  std::vector<Finding> notes;  // note k is notes[k - 1]
};

void mark(std::string& cell, const Finding& reason, std::vector<Finding>& notes) {
  if (reason.text.empty()) return;
  auto note = std::find_if(notes.begin(), notes.end(), [&](const Finding& n) { return n.text == reason.text; });
  if (note == notes.end()) note = notes.insert(notes.end(), reason);
  cell += " [" + std::to_string(note - notes.begin() + 1) + "]";
}

SummaryTable summary_table(const SceneStudy& s) {
  SummaryTable table;
  for (const VariantStudy& v : s.variants) {
    std::vector<std::string> cells = summary_cells(s, v);
    if (v.note.empty() && !v.referee) {
      const RowReasons reasons = row_reasons(v);
      mark(cells[summary_column("err_max")], reasons.error, table.notes);
      mark(cells[summary_column("max_residual")], reasons.residual, table.notes);
    }
    table.rows.push_back(std::move(cells));
  }
  return table;
}

// Note k (from 0) of a summary table, as its marker names it; in Markdown, **unexpected** in bold.
std::string note_line(std::size_t k, const Finding& note, bool markdown) {
  const std::string unexpected = markdown ? "**unexpected**: " : "unexpected: ";
  return "[" + std::to_string(k + 1) + "] " + (note.expected ? "" : unexpected) + note.text;
}

// The rows --quick left out of a scene, and why ("" when none was).
std::string left_out_text(const SceneStudy& s) {
  if (s.left_out.empty()) return "";
  std::string rows;
  for (const std::string& name : s.left_out) rows += (rows.empty() ? "" : ", ") + name;
  return "--quick left out " + rows + ": each needs a compile of its own, and --quick compiles each scene once (the "
         "x86-64 -O2 build with every policy); the report without --quick measures them";
}

std::vector<std::string> csv_fields(const SceneStudy& s, const VariantStudy& v, const FamilyErrors& e) {
  const bool timed = v.note.empty();
  return {s.name,
          v.name,
          v.scalar,
          e.family,
          std::to_string(e.states),
          std::to_string(e.judged),
          v.referee ? "0" : scientific(e.median),
          v.referee ? "0" : scientific(e.p99),
          v.referee ? "0" : scientific(e.max),
          v.referee ? "0" : scientific(e.max_residual),
          std::to_string(e.status_raised),
          timed ? format("%.1f", v.ns_median) : "",
          timed ? format("%.1f", v.ns_p99) : "",
          timed ? format("%.1f", v.ns_max) : "",
          v.operations > 0 ? std::to_string(v.operations) : "",
          v.note,
          v.solves};
}

double floored(double error) { return std::max(error, kPlotFloor); }

// The variants drawn: measured ones with errors (the referee has none), the recommended one last,
// so that it is drawn on top of the others (the reference solver's markers sit on its own).
std::vector<const VariantStudy*> drawn(const SceneStudy& s) {
  std::vector<const VariantStudy*> variants;
  for (const VariantStudy& v : s.variants)
    if (v.note.empty() && !v.referee && v.all.judged > 0) variants.push_back(&v);
  std::stable_partition(variants.begin(), variants.end(), [&s](const VariantStudy* v) { return v->name != s.recommended; });
  return variants;
}

// One marker and colour per kind of row, the same in every figure of every scene: the row's name
// says its kind (study.cpp names them), the first match below decides.
struct Style {
  int pointtype;
  const char* colour;
};
Style style_of(const std::string& variant) {
  static const std::vector<std::pair<std::string, Style>> styles = {
      {"x86-64-v3", {7, "#d62728"}},           {" damped", {9, "#8c564b"}},
      {" pivoted_ldlt", {9, "#8c564b"}},       {"generated float", {13, "#ff7f0e"}},
      {"saturate_exact", {11, "#17becf"}},     {"saturate", {10, "#bcbd22"}},
      {"prioritize_external", {4, "#9467bd"}}, {"generated double", {5, "#1f77b4"}},
      {"reference double", {6, "#7f7f7f"}},    {"KDL", {2, "#2ca02c"}},
      {"dense KKT", {3, "#e377c2"}}};
  for (const auto& [part, style] : styles)
    if (variant.find(part) != std::string::npos) return style;
  return {1, "#000000"};
}

// A series' marker, colour and title; the recommended row's marker larger.
std::string series_style(const SceneStudy& s, const VariantStudy& v) {
  const Style style = style_of(v.name);
  const bool recommended = v.name == s.recommended;
  return "pointtype " + std::to_string(style.pointtype) + " pointsize " + (recommended ? "2.2" : "1.3") +
         " linecolor rgb '" + style.colour + "' title " +
         gnuplot_string(v.name + (recommended ? " (recommended)" : ""));
}

void write_text(const std::filesystem::path& path, const std::string& text) {
  io::write_files_atomically({{path.string(), text}});
}

// Error on the nominal family (median, whiskers to p99) against time per call (median, whiskers
// to p99): the states a controller meets; the κ figure shows the others.
std::string time_figure(const SceneStudy& s, const std::filesystem::path& work_dir) {
  std::ostringstream data;
  data << std::setprecision(17);
  std::vector<std::string> series;
  int index = 0;
  for (const VariantStudy* v : drawn(s)) {
    const FamilyErrors& e = v->families.front();
    data << v->ns_median << " " << floored(e.median) << " " << v->ns_median << " " << v->ns_p99 << " "
         << floored(e.median) << " " << floored(e.p99) << "\n\n\n";
    series.push_back("'' index " + std::to_string(index) + " using 1:2:3:4:5:6 with xyerrorbars linewidth 1.5 " +
                     series_style(s, *v));
    ++index;
  }
  const std::filesystem::path data_path = work_dir / (s.name + "_time.dat");
  write_text(data_path, data.str());
  series.front().replace(0, 2, gnuplot_string(data_path.string()));
  std::ostringstream plot;
  plot << "set title " << gnuplot_string(s.name + ": error on " + drawn(s).front()->families.front().family +
                                         " states against time per solve (" + std::to_string(s.dof) +
                                         " joints, Nc = " + std::to_string(s.constraints) + ")")
       << " noenhanced\n"
       << "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid xtics ytics mxtics\n"
       << kKeyBelowPlot << " noenhanced\n"
       << "set xlabel 'time per solve [ns]: median, whisker to p99'\n"
       << "set ylabel 'error vs binary128: median, whisker to p99'\n"
       << "set offsets graph 0.1, graph 0.1, graph 0.3, graph 0.3\n"
       << "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) plot << (k ? ", \\\n     " : "") << series[k];
  plot << "\n";
  return plot.str();
}

// Error of every judged state against κ, per variant, with ε κ of double and float and the
// shaded domain where float meets kFloatGoal.
std::string kappa_figure(const SceneStudy& s, const std::filesystem::path& work_dir) {
  std::ostringstream plot;
  plot << "set title " << gnuplot_string(s.name + ": error against kappa, every judged state") << " noenhanced\n"
       << "set logscale xy\nset format x '10^{%L}'\nset format y '10^{%L}'\nset grid\n"
       << kKeyBelowPlot << " noenhanced\n"
       << "set xlabel 'kappa = max(1, cond_s(E^A_{cstr,0}), 1/min rho_i)'\n"
       << "set ylabel 'error vs binary128 (floor " << kPlotFloor << ")'\n"
       << "set yrange [" << kPlotFloor / 10 << ":*]\n";
  if (std::isfinite(s.float_domain_kappa) && s.float_domain_kappa > 0)
    plot << "set object 1 rect from graph 0, graph 0 to first " << std::setprecision(6) << s.float_domain_kappa
         << ", graph 1 fillcolor rgb '#e8f0e0' fillstyle solid noborder behind\n"
         << "set label 1 'float domain (error <= " << kFloatGoal << ")' at graph 0.02, graph 0.04\n";
  std::vector<std::string> series;
  for (const VariantStudy* v : drawn(s)) {
    std::ostringstream data;
    data << std::setprecision(17);
    for (const StatePoint& p : v->states)
      if (p.judged) data << p.kappa << " " << floored(p.error()) << "\n";
    std::string file = v->name;
    std::replace(file.begin(), file.end(), ' ', '_');
    const std::filesystem::path data_path = work_dir / (s.name + "_kappa_" + file + ".dat");
    write_text(data_path, data.str());
    series.push_back(gnuplot_string(data_path.string()) + " using 1:2 with points " + series_style(s, *v));
  }
  series.push_back("x * " + format("%.17g", std::numeric_limits<double>::epsilon()) +
                   " with lines dashtype 2 linecolor rgb 'black' title 'eps_double kappa'");
  series.push_back("x * " + format("%.17g", std::numeric_limits<float>::epsilon()) +
                   " with lines dashtype 3 linecolor rgb 'black' title 'eps_float kappa'");
  plot << "plot ";
  for (std::size_t k = 0; k < series.size(); ++k) plot << (k ? ", \\\n     " : "") << series[k];
  plot << "\n";
  return plot.str();
}

std::string markdown_row(const std::vector<std::string>& cells) {
  std::string row = "|";
  for (const std::string& c : cells) row += " " + c + " |";
  return row + "\n";
}

}  // namespace

void print_study(const SceneStudy& study, std::ostream& out) {
  out << "\n== " << study.name << " (" << study.source << "): " << study.dof << " joints, Nc = " << study.constraints
      << "\nstates:";
  for (const auto& [family, count] : study.families) out << " " << family << " " << count << ";";
  out << " " << study.singular_note << "\n";
  const SummaryTable summary = summary_table(study);
  std::vector<std::vector<std::string>> table = {summary_header()};
  table.insert(table.end(), summary.rows.begin(), summary.rows.end());
  print_aligned(table, out);
  for (std::size_t k = 0; k < summary.notes.size(); ++k) out << note_line(k, summary.notes[k], false) << "\n";
  if (!study.left_out.empty()) out << left_out_text(study) << "\n";
  out << "recommendation: " << study.recommendation << "\n";
}

std::string report_csv(const std::vector<SceneStudy>& studies) {
  std::string text = csv_line({"scene", "variant", "scalar", "family", "states", "judged", "err_median", "err_p99",
                               "err_max", "max_residual", "status_raised", "ns_median", "ns_p99", "ns_max", "operations",
                               "note", "solves"});
  for (const SceneStudy& s : studies)
    for (const VariantStudy& v : s.variants) {
      if (!v.note.empty() || v.referee) {
        FamilyErrors none;
        none.family = "all";
        text += csv_line(csv_fields(s, v, none));
        continue;
      }
      for (const FamilyErrors& e : v.families) text += csv_line(csv_fields(s, v, e));
      text += csv_line(csv_fields(s, v, v.all));
    }
  return text;
}

std::string states_csv(const std::vector<SceneStudy>& studies) {
  std::string text = csv_line({"scene", "variant", "family", "kappa", "err_qdd", "err_tau", "err_nu", "residual",
                               "status", "referee_status", "judged"});
  for (const SceneStudy& s : studies)
    for (const VariantStudy& v : s.variants)
      for (const StatePoint& p : v.states)
        text += csv_line({s.name, v.name, p.family, format("%.17g", p.kappa), format("%.17g", p.qdd),
                          format("%.17g", p.tau), format("%.17g", p.nu), format("%.17g", p.residual),
                          std::to_string(p.status), std::to_string(p.referee_status), p.judged ? "1" : "0"});
  return text;
}

std::vector<std::string> draw_figures(const std::vector<SceneStudy>& studies, const std::filesystem::path& dir,
                                      const std::filesystem::path& work_dir) {
  std::vector<std::string> written;
  for (const SceneStudy& s : studies) {
    if (drawn(s).empty()) continue;
    for (const auto& [suffix, body] : {std::pair<std::string, std::string>{"_time", time_figure(s, work_dir)},
                                       std::pair<std::string, std::string>{"_kappa", kappa_figure(s, work_dir)}}) {
      const std::string stem = s.name + suffix;
      draw_png_and_svg(body, (dir / stem).string(), (work_dir / stem).string(), work_dir.string(), 1000, 650);
      written.push_back(stem + ".png");
      written.push_back(stem + ".svg");
    }
  }
  return written;
}

std::string report_markdown(const std::vector<SceneStudy>& studies, const std::string& command,
                            const std::string& setup) {
  std::ostringstream md;
  md << "# sweepgen report\n\n"
     << "Made by `" << command << "`. " << setup << "\n\n"
     << "Errors are against `ReferenceSolver<binary128>` solving the same problem (policy, factorisation, the "
        "scalar's tolerances), scale-invariant and per state the largest of q̈, τcmd and ν "
        "(docs/stability.md, \"Errors and condition numbers\"); quantiles run over the states where neither the "
        "variant nor its referee dropped a direction, locked a joint or returned a value that is not finite "
        "(`judged` in report.csv; a saturating policy's clamp is judged), `status` is the share of states where "
        "the variant raised any status bit. Times are per call (the clock's own cost subtracted), after one "
        "untimed pass; `kdl_x` is KDL's median time over the row's. Exact answers are drawn at 1e-20 on the log axes.\n\n"
     << "## Recommendations\n\n";
  for (const SceneStudy& s : studies) md << "- **" << s.name << "**: " << s.recommendation << ".\n";
  for (const SceneStudy& s : studies) {
    md << "\n## " << s.name << "\n\n`" << s.source << "`, " << s.dof << " joints, Nc = " << s.constraints
       << ". States:";
    for (const auto& [family, count] : s.families) md << " " << family << " " << count << ";";
    md << " " << s.singular_note << ".\n\n";
    md << markdown_row(summary_header()) << markdown_row(std::vector<std::string>(summary_header().size(), "---"));
    const SummaryTable summary = summary_table(s);
    for (std::vector<std::string> cells : summary.rows) {
      cells.resize(summary_header().size());
      md << markdown_row(cells);
    }
    if (!summary.notes.empty()) md << "\n";
    for (std::size_t k = 0; k < summary.notes.size(); ++k) md << "- " << note_line(k, summary.notes[k], true) << "\n";
    if (!s.left_out.empty()) md << "\n" << left_out_text(s) << ".\n";
    md << "\nMaximum error per family (share of states with a status raised):\n\n";
    std::vector<std::string> header{"variant"};
    for (const auto& [family, count] : s.families) header.push_back(family);
    md << markdown_row(header) << markdown_row(std::vector<std::string>(header.size(), "---"));
    for (const VariantStudy& v : s.variants) {
      if (!v.note.empty() || v.referee) continue;
      std::vector<std::string> cells{v.name};
      for (const FamilyErrors& e : v.families)
        cells.push_back(error_cell(e, e.max) + " (" + share(e.status_raised, e.states) + ")");
      md << markdown_row(cells);
    }
    const std::vector<Reason> reasons = study_reasons(s);
    if (!reasons.empty()) {
      md << "\nWhy rows have no answer or a large error, per family (and whether it is expected):\n";
      std::string family;
      for (const Reason& r : reasons) {
        if (r.family != family) md << "\n- **" << (family = r.family) << "**\n";
        std::string rows;
        for (const std::string& v : r.variants) rows += (rows.empty() ? "" : ", ") + v;
        md << "  - " << (r.expected ? "" : "**unexpected**: ") << rows << ": " << r.text << "\n";
      }
    }
    if (s.constraints > 0) {
      md << "\nPath of ν (docs/derivation.md, (C4)), share of states on the natural-order path / on the pivoted one:";
      for (std::size_t f = 0; f < s.families.size(); ++f)
        md << " " << s.families[f].first << " " << share(s.families[f].second - s.pivoted_path[f], s.families[f].second)
           << " / " << share(s.pivoted_path[f], s.families[f].second) << (f + 1 < s.families.size() ? ";" : ".");
      md << "\n";
    }
    md << "\nWhat each row solves:\n\n";
    for (const VariantStudy& v : s.variants) md << "- " << v.name << ": " << v.solves << "\n";
    if (!drawn(s).empty())
      md << "\n![" << s.name << ": error against time](" << s.name << "_time.png)\n\n![" << s.name
         << ": error against kappa](" << s.name << "_kappa.png)\n";
  }
  return md.str();
}

}  // namespace sweepgen::report

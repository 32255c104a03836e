// `sweepgen report` end to end on the small planar scene: generate, compile with the system
// compiler, dlopen, measure; its statistics recomputed from its per-state file and its errors
// from an independent computation; its exit codes for a bad scene (1), a bad command line (2), an
// unwritable output folder and a failing compiler (3), with no half-written report. `sweepgen report --stability` on two small cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "report/extreme_states.hpp"
#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"
#include "support/run_command.hpp"
#include "support/one_joint_robot.hpp"
#include "support/temp_dir.hpp"
#include "support/rounding_bound.hpp"
#include "support/skip_count.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using test::run_command;
using test::shell_command;
using test::TempDir;

std::string planar_scene() { return std::string(SWEEPGEN_SOURCE_DIR) + "/robots/planar/planar_nc2.yaml"; }


// Splits one CSV line (fields may be double-quoted, "" an embedded quote).
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

double number(const std::string& field) {
  std::size_t used = 0;
  const double value = std::stod(field, &used);
  EXPECT_EQ(used, field.size()) << "not a number: " << field;
  return value;
}

// The CSV files as rows of named fields.
using CsvRow = std::map<std::string, std::string>;
std::vector<CsvRow> read_csv(const std::filesystem::path& path) {
  std::istringstream csv(test::read_text(path));
  std::string line;
  std::vector<CsvRow> rows;
  if (!std::getline(csv, line)) return rows;
  const std::vector<std::string> header = split_csv(line);
  while (std::getline(csv, line)) {
    const auto fields = split_csv(line);
    EXPECT_EQ(fields.size(), header.size()) << line;
    CsvRow row;
    for (std::size_t k = 0; k < header.size() && k < fields.size(); ++k) row[header[k]] = fields[k];
    rows.push_back(row);
  }
  return rows;
}

// The report's quantile: linear between order statistics (report/measure.hpp states it; written
// again here so that the test does not take the report's word for it).
double quantile_of(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double at = q * static_cast<double>(v.size() - 1);
  const std::size_t below = static_cast<std::size_t>(at), above = std::min(below + 1, v.size() - 1);
  return v[below] + (at - static_cast<double>(below)) * (v[above] - v[below]);
}

// |a − b| within `relative` of b (report.csv prints 4 significant digits: 5e-4 relative).
void expect_close(double a, double b, double relative, const std::string& what) {
  EXPECT_LE(std::abs(a - b), relative * std::abs(b)) << what << ": " << a << " vs " << b;
}

struct PlanarReport {
  std::filesystem::path out;
  test::CommandResult result;
};

// One quick report on the planar scene, shared by the tests below (it compiles three variants).
const PlanarReport& planar_report() {
  static TempDir dir;
  static const PlanarReport report = [] {
    PlanarReport r{dir.path() / "report", {}};
    r.result = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--states", "8",
                                          "--repetitions", "3", "--seed", "3", "--out", r.out.string()}));
    return r;
  }();
  return report;
}

TEST(Report, PlanarSceneEndToEnd) {
  const PlanarReport& report = planar_report();
  ASSERT_EQ(report.result.exit_code, 0) << report.result.out << report.result.err;
  const auto& out = report.out;
  // Progress on standard error with the compile commands; the summary on standard output.
  EXPECT_NE(report.result.err.find("[1/1 planar_nc2] compiling (c++ -std=c++17 -O2 -shared -fPIC"), std::string::npos)
      << report.result.err;
  EXPECT_NE(report.result.out.find("recommendation: generated double original"), std::string::npos) << report.result.out;

  // Every variant the scene can use, each once, with what it solves.
  const std::vector<CsvRow> rows = read_csv(out / "report.csv");
  std::map<std::string, std::vector<CsvRow>> by_variant;
  for (const CsvRow& row : rows) by_variant[row.at("variant")].push_back(row);
  for (const char* variant :
       {"generated double original", "generated double prioritize_external", "generated double saturate",
        "generated double saturate_exact", "generated float original", "generated double original x86-64-v3",
        "generated double original damped", "reference double", "reference binary128", "KDL", "dense KKT"}) {
    ASSERT_EQ(by_variant.count(variant), 1u) << variant;
    EXPECT_FALSE(by_variant[variant].front().at("solves").empty()) << variant;
  }
  // The operation count is the generated header's (the committed generated/planar_nc2.hpp lists it).
  {
    const std::string header = test::read_text(std::string(SWEEPGEN_SOURCE_DIR) + "/generated/planar_nc2.hpp");
    const std::string key = "f64: outward + decompose + solve_original: ";
    const std::size_t line = header.find(key), total = header.find("(total ", line);
    ASSERT_NE(line, std::string::npos);
    const std::string count = header.substr(total + 7, header.find(')', total) - total - 7);
    EXPECT_EQ(by_variant["generated double original"].back().at("operations"), count);
  }
  // Times: per call, ordered quantiles, for every measured row.
  for (const auto& [variant, family_rows] : by_variant) {
    const CsvRow& row = family_rows.back();
    if (!row.at("note").empty()) continue;
    const double median = number(row.at("ns_median")), p99 = number(row.at("ns_p99")), max = number(row.at("ns_max"));
    EXPECT_GT(median, 0) << variant;
    EXPECT_LE(median, p99) << variant;
    EXPECT_LE(p99, max) << variant;
  }

  // report.csv's statistics are states.csv's, recomputed here: counts, status, quantiles.
  const std::vector<CsvRow> states = read_csv(out / "states.csv");
  std::size_t checked = 0;
  for (const CsvRow& row : rows) {
    if (!row.at("note").empty() || row.at("variant") == "reference binary128") continue;
    std::vector<double> errors, residuals;
    std::size_t count = 0, raised = 0;
    for (const CsvRow& s : states) {
      if (s.at("variant") != row.at("variant") || (row.at("family") != "all" && s.at("family") != row.at("family")))
        continue;
      ++count;
      if (s.at("status") != "0") ++raised;
      if (s.at("judged") != "1") continue;
      errors.push_back(std::max({number(s.at("err_qdd")), number(s.at("err_tau")), number(s.at("err_nu"))}));
      residuals.push_back(number(s.at("residual")));
    }
    const std::string what = row.at("variant") + " / " + row.at("family");
    EXPECT_EQ(std::to_string(count), row.at("states")) << what;
    EXPECT_EQ(std::to_string(raised), row.at("status_raised")) << what;
    ASSERT_EQ(std::to_string(errors.size()), row.at("judged")) << what;
    if (errors.empty()) continue;
    expect_close(number(row.at("err_median")), quantile_of(errors, 0.5), 1e-3, what + " median");
    expect_close(number(row.at("err_p99")), quantile_of(errors, 0.99), 1e-3, what + " p99");
    expect_close(number(row.at("err_max")), *std::max_element(errors.begin(), errors.end()), 1e-3, what + " max");
    expect_close(number(row.at("max_residual")), *std::max_element(residuals.begin(), residuals.end()), 1e-3,
                 what + " residual");
    ++checked;
  }
  EXPECT_GE(checked, 10u * 3u);  // ten measured variants, at least the nominal, fast and huge_force families

  // Float's domain in the recommendation, recomputed: the smallest κ of a float state that missed
  // 1e-4 where judged or dropped a direction, locked a joint or returned a non-finite value
  // (status bits 1, 8, 4); planar_nc2's float answers every state of this run.
  double float_domain = INFINITY;
  for (const CsvRow& s : states)
    if (s.at("variant") == "generated float original") {
      const bool judged = s.at("judged") == "1";
      const double error = std::max({number(s.at("err_qdd")), number(s.at("err_tau")), number(s.at("err_nu"))});
      const bool answered = judged ? error <= 1e-4 : (std::stoul(s.at("status")) & 13u) == 0;
      if (!answered) float_domain = std::min(float_domain, number(s.at("kappa")));
    }
  EXPECT_TRUE(std::isinf(float_domain)) << float_domain;
  EXPECT_NE(report.result.out.find("; float met 1e-04 on every state"), std::string::npos) << report.result.out;

  // The figures, PNG and SVG, and report.md linking them.
  for (const char* figure : {"planar_nc2_time", "planar_nc2_kappa"}) {
    const std::string png = test::read_text(out / (std::string(figure) + ".png"));
    ASSERT_GE(png.size(), 8u);
    EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
    EXPECT_NE(test::read_text(out / (std::string(figure) + ".svg")).find("<svg"), std::string::npos);
  }
  const std::string md = test::read_text(out / "report.md");
  EXPECT_NE(md.find("## planar_nc2"), std::string::npos);
  EXPECT_NE(md.find("- **planar_nc2**: generated double original"), std::string::npos);
  EXPECT_NE(md.find("](planar_nc2_time.png)"), std::string::npos);
  EXPECT_NE(md.find("](planar_nc2_kappa.png)"), std::string::npos);

  // Why rows have a status or no answer, per family, and whether it is expected: the saturating
  // policies clamp on the fast states (their torques exceed the effort limits).
  const std::size_t why = md.find("Why rows have no answer or a large error, per family (and whether it is expected):");
  ASSERT_NE(why, std::string::npos) << md;
  const std::size_t fast = md.find("- **fast**", why);
  ASSERT_NE(fast, std::string::npos) << md;
  const std::size_t clamp = md.find("clamped torques at their effort limits (status_saturated) on ", fast);
  ASSERT_NE(clamp, std::string::npos) << md;
  const std::string line = md.substr(md.rfind('\n', clamp) + 1, md.find('\n', clamp) - md.rfind('\n', clamp) - 1);
  EXPECT_NE(line.find("generated double saturate"), std::string::npos) << line;
  EXPECT_NE(line.find(": expected, the policy's job"), std::string::npos) << line;
  EXPECT_EQ(line.find("generated double original:"), std::string::npos) << line;
}

// A scene that returns fewer results than the report judges (the lean peer-comparison scenes:
// `outputs: [qdd]`, no input checks): the report compiles every result (report_scene), so the
// generated rows must be read in that layout, not the scene's own. Read in the scene's, each
// state's q̈ came from the wrong offset, and the solve wrote past the report's buffer.
TEST(Report, ASceneWithFewerOutputsIsReadInTheLayoutItWasCompiledWith) {
  TempDir dir;
  const std::filesystem::path out = dir.path() / "report";
  const test::CommandResult result = run_command(
      shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", std::string(SWEEPGEN_SOURCE_DIR) + "/robots/iiwa14/iiwa14_lean_nc0.yaml",
                     "--quick", "--states", "8", "--repetitions", "1", "--seed", "3", "--out", out.string()}));
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  std::map<std::string, double> err_max;
  for (const CsvRow& row : read_csv(out / "report.csv"))
    if (row.at("family") == "all" && row.at("note").empty() && !row.at("err_max").empty())
      err_max[row.at("variant")] = number(row.at("err_max"));
  ASSERT_EQ(err_max.count("generated double original"), 1u);
  ASSERT_EQ(err_max.count("reference double"), 1u);
  // The generated solve and the reference run the same equations in double: within a few times
  // each other's rounding (the referee's error of each, relative, is ~1e-13 on these states); a
  // q̈ read from another state's row is off by O(1).
  EXPECT_LE(err_max["generated double original"], 100 * err_max["reference double"] + 1e-12);
}

// The summary table of report.md gives the reason for a large err_max or max_residual in the row
// itself: such a number (above √ε of the row's scalar, where study_reasons starts to speak) carries
// a marker [k], and note k stands right under the table, before the per-family tables.
TEST(Report, LargeSummaryNumbersCarryTheirReasonBesideThem) {
  const PlanarReport& report = planar_report();
  ASSERT_EQ(report.result.exit_code, 0) << report.result.err;
  const std::string md = test::read_text(report.out / "report.md");
  std::istringstream lines(md.substr(md.find("| variant | scalar |")));
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, std::vector<std::string>> row_of;  // variant -> cells
  while (std::getline(lines, line) && line.rfind("| ", 0) == 0) {
    std::vector<std::string> cells;
    for (std::size_t at = 2, bar; (bar = line.find(" |", at)) != std::string::npos; at = bar + 3)
      cells.push_back(line.substr(at, bar - at));
    if (header.empty()) header = cells;
    else if (cells.front() != "---") row_of[cells.front()] = cells;
  }
  std::map<std::string, std::string> notes;  // "[k]" -> its text, the list right under the table
  while (std::getline(lines, line) && line.rfind("- [", 0) == 0)
    notes[line.substr(2, line.find(']') - 1)] = line.substr(line.find(']') + 2);
  ASSERT_FALSE(notes.empty()) << md;

  const auto column = [&header](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  // The note a cell points at ("" where it has no marker).
  const auto note_of = [&notes](const std::string& cell) -> std::string {
    const std::size_t open = cell.find(" [");
    if (open == std::string::npos) return "";
    const std::string marker = cell.substr(open + 1);
    EXPECT_EQ(notes.count(marker), 1u) << cell << ": no note " << marker << " under the table";
    return notes.count(marker) ? notes.at(marker) : "";
  };
  std::size_t marked = 0;
  for (const auto& [variant, cells] : row_of) {
    if (cells.size() != header.size() || cells[column("err_max")].empty()) continue;  // a note row or the referee
    const double noticeable = std::sqrt(cells[column("scalar")] == "float" ? std::numeric_limits<float>::epsilon()
                                                                          : std::numeric_limits<double>::epsilon());
    for (const char* name : {"err_max", "max_residual"}) {
      const std::string& cell = cells[column(name)];
      if (cell == "none judged") continue;
      const double value = std::stod(cell);
      if (value <= noticeable) continue;
      EXPECT_FALSE(note_of(cell).empty()) << variant << ": " << name << " " << cell << " has no reason beside it";
      ++marked;
    }
  }
  EXPECT_GE(marked, 2u) << md;
  // The policies that give way say why in their rows: Alg. 4 under the tool's load, the clamps.
  EXPECT_NE(note_of(row_of.at("generated double prioritize_external")[column("max_residual")])
                .find("Alg. 4 leaves the external forces out of the constraint's reaction"),
            std::string::npos)
      << md;
  EXPECT_NE(note_of(row_of.at("generated double saturate")[column("max_residual")])
                .find("where a torque is clamped at its effort limit"),
            std::string::npos)
      << md;
}

// --quick compiles each scene once, the x86-64 build with every policy, and leaves out the rows
// that need a compile of their own, saying so in report.md. Compiles counted twice: the progress
// line each one prints, and the build folders holding a library.
TEST(Report, QuickCompilesEachSceneOnce) {
  TempDir dir;
  const auto out = dir.path() / "report";
  const auto result = run_command(
      shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--quick", "--out", out.string()}));
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  std::size_t compiles = 0;
  for (std::size_t at = result.err.find("] compiling ("); at != std::string::npos;
       at = result.err.find("] compiling (", at + 1))
    ++compiles;
  EXPECT_EQ(compiles, 1u) << result.err;
  std::size_t libraries = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out / "build" / "planar_nc2"))
    libraries += entry.path().extension() == ".so";
  EXPECT_EQ(libraries, 1u);

  std::set<std::string> variants;
  for (const CsvRow& row : read_csv(out / "report.csv")) variants.insert(row.at("variant"));
  for (const char* measured : {"generated double original", "generated double prioritize_external",
                               "generated double saturate", "generated double saturate_exact",
                               "generated float original", "reference double", "KDL", "dense KKT"})
    EXPECT_EQ(variants.count(measured), 1u) << measured;
  for (const char* left_out : {"generated double original x86-64-v3", "generated double original damped"})
    EXPECT_EQ(variants.count(left_out), 0u) << left_out;
  EXPECT_NE(test::read_text(out / "report.md")
                .find("--quick left out generated double original x86-64-v3, generated double original damped: "
                      "each needs a compile of its own"),
            std::string::npos);
}

// Both figures draw each row with the same marker and colour (a kind of row has one in every
// scene's figures), and the recommended row last, on top of the others, with the legend below.
TEST(Report, FiguresShareOneStylePerRowAndDrawTheRecommendedLast) {
  const PlanarReport& report = planar_report();
  ASSERT_EQ(report.result.exit_code, 0) << report.result.err;
  const std::string& printed = report.result.out;
  const std::size_t at = printed.find("recommendation: ");
  ASSERT_NE(at, std::string::npos) << printed;
  const std::string recommended_row = printed.substr(at + 16, printed.find(':', at + 16) - at - 16);
  const test::Pattern series(R"(pointtype (\d+) pointsize [0-9.]+ linecolor rgb '(#[0-9a-f]+)' title '([^']+)')");
  std::map<std::string, std::string> style_of_row;  // title -> "pointtype colour", from both figures
  for (const char* figure : {"planar_nc2_time.gp", "planar_nc2_kappa.gp"}) {
    const std::string script = test::read_text(report.out / "build" / "plots" / figure);
    std::string last;
    std::size_t rows = 0;
    for (const test::Match& plotted : series.all(script)) {
      ++rows;
      std::string title = plotted[3];
      last = title;
      const std::string recommended = " (recommended)";
      if (title.size() > recommended.size() && title.compare(title.size() - recommended.size(), recommended.size(), recommended) == 0)
        title.resize(title.size() - recommended.size());
      const std::string style = plotted[1] + " " + plotted[2];
      const auto [at, inserted] = style_of_row.emplace(title, style);
      EXPECT_EQ(at->second, style) << figure << ": " << title;
    }
    EXPECT_GE(rows, 9u) << figure;
    EXPECT_EQ(last, recommended_row + " (recommended)") << figure;
    // The legend under the plot: beside it, the long row names took half the width.
    EXPECT_NE(script.find("set key outside bottom center horizontal"), std::string::npos) << script;
  }
  std::set<std::string> styles;
  for (const auto& [title, style] : style_of_row) EXPECT_TRUE(styles.insert(style).second) << title << " shares " << style;
}

// The q̈ errors of the "reference double" row against a computation of the same numbers without
// the report: the same states (report::extreme_states, the seed the report was given),
// ReferenceSolver<double> judged against ReferenceSolver<long double> (not the report's binary128
// referee), the scale written out: per joint kind, ‖Δq̈‖∞ / max(‖q̈‖∞, ‖q̈_free‖∞), the larger.
// Tolerance: the two referees differ by the long double's own rounding, at most
// kRefereeRounding · eps_ld · κ (the double solver reaches 8.6 eps κ on the stability suite, and
// long double runs the same operations), plus 1e-2 of the value for the report's 17-digit output
// and the float128 referee's own (negligible) error; ceiling 1e-6 (the states have κ < 1e8).
TEST(Report, ReferenceErrorsMatchAnIndependentComputation) {
  const PlanarReport& report = planar_report();
  ASSERT_EQ(report.result.exit_code, 0) << report.result.err;
  const scene::Scene s = scene::load_scene(planar_scene());
  const model::Chain chain = scene::load_scene_chain(s);
  std::vector<CsvRow> reported;
  for (const CsvRow& row : read_csv(report.out / "states.csv"))
    if (row.at("variant") == "reference double") reported.push_back(row);
  std::set<std::string> families;
  for (const CsvRow& row : reported) families.insert(row.at("family"));
  std::vector<report::LabelledProblem> states =
      report::extreme_states(s, chain, 8, std::vector<double>(chain.dof(), 0.0), 3);
  states.erase(std::remove_if(states.begin(), states.end(), [&](const auto& x) { return !families.count(x.kind); }),
               states.end());
  ASSERT_EQ(states.size(), reported.size());

  constexpr double kRefereeRounding = 10;
  constexpr double kEpsLd = std::numeric_limits<long double>::epsilon();
  solver::ReferenceSolver<double> solver_double(chain, s.layout, s.solver_options());
  solver::ReferenceSolver<long double> referee(chain, s.layout, s.solver_options());
  double worst = 0;
  std::size_t compared = 0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    if (reported[k].at("judged") != "1") continue;
    const report::Problem& p = states[k].problem;
    const Eigen::VectorXd qdd = solver_double.run(p, solver::Policy::original).qdd;
    const auto precise = p.cast<long double>();
    const Eigen::Matrix<long double, Eigen::Dynamic, 1> exact = referee.run(precise, solver::Policy::original).qdd;
    for (auto& alpha : referee.drivers().constraint_directions) alpha = spatial::Force<long double>{};
    referee.decompose();
    const Eigen::Matrix<long double, Eigen::Dynamic, 1> free =
        referee.solve(solver::Policy::original, precise.beta).qdd;
    long double error = 0;
    for (const model::JointType kind : {model::JointType::revolute, model::JointType::prismatic}) {
      long double difference = 0, scale = 0;
      for (std::size_t i = 1; i <= chain.dof(); ++i) {
        const bool same_kind = (chain.joints[i].type == model::JointType::prismatic) ==
                               (kind == model::JointType::prismatic);
        if (!same_kind) continue;
        const auto at = static_cast<Eigen::Index>(i - 1);
        difference = std::max(difference, std::abs(static_cast<long double>(qdd[at]) - exact[at]));
        scale = std::max({scale, std::abs(exact[at]), std::abs(free[at])});
      }
      if (scale > 0) error = std::max(error, difference / scale);
    }
    const double kappa = number(reported[k].at("kappa"));
    const double tolerance = 1e-2 * static_cast<double>(error) + kRefereeRounding * kEpsLd * kappa;
    ASSERT_LE(tolerance, 1e-6) << "state " << k << " kappa " << kappa;
    EXPECT_NEAR(number(reported[k].at("err_qdd")), static_cast<double>(error), tolerance)
        << "state " << k << " (" << states[k].kind << ")";
    worst = std::max(worst, std::abs(number(reported[k].at("err_qdd")) - static_cast<double>(error)) / tolerance);
    ++compared;
  }
  std::printf("[report] reference double: %zu judged states recomputed, worst |difference| / tolerance %.3f\n", compared,
              worst);
  EXPECT_GE(compared, states.size() / 2);
}

// --quick: the seed draws the same states whichever variants are compiled (one compile a run
// instead of three).
TEST(Report, SameSeedSameErrors) {
  TempDir dir;
  std::vector<std::string> errors;
  for (const char* run : {"a", "b"}) {
    const auto out = dir.path() / run;
    const auto result =
        run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--quick", "--seed", "7",
                                   "--out", out.string()}));
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(test::read_text(out / "report.md").find("(seed 7)"), std::string::npos);
    errors.push_back(test::read_text(out / "states.csv"));
  }
  EXPECT_EQ(errors[0], errors[1]);
}

// --quick's 6 states and 3 passes are defaults: given beside it, --states and --repetitions count
// (every variant has exactly that many states of each family, and report.md says so).
TEST(Report, QuickKeepsTheStatesAndPassesGiven) {
  TempDir dir;
  const auto out = dir.path() / "report";
  const auto result = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--quick",
                                                 "--states", "2", "--repetitions", "1", "--out", out.string()}));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  std::map<std::string, int> states_of;  // variant and family
  for (const CsvRow& row : read_csv(out / "states.csv")) ++states_of[row.at("variant") + " / " + row.at("family")];
  ASSERT_FALSE(states_of.empty());
  for (const auto& [which, count] : states_of) EXPECT_EQ(count, 2) << which;
  EXPECT_NE(test::read_text(out / "report.md").find("2 states per random family (seed 1), 1 timed passes"),
            std::string::npos);
}

// A robot whose every state locks a joint (a massless free base above a joint about its z axis:
// the base cannot turn about z, J1): no state can be judged, and the report says why instead of
// printing NaN statistics.
TEST(Report, SceneWhereNoStateCanBeJudgedSaysWhy) {
  TempDir dir;
  dir.write("massless_base.urdf", test::massless_base_turning_arm());
  const std::string scene = dir.write("locked.yaml",
                                      "sweepgen_scene: 1\nsolver: locked\nurdf: massless_base.urdf\nbase: floating\n"
                                      "drivers:\n  torques: [tau_ff]\n");
  const auto out = dir.path() / "report";
  const auto result = run_command(shell_command(
      {SWEEPGEN_EXECUTABLE, "report", "--scene", scene, "--states", "4", "--repetitions", "1", "--out", out.string()}));
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  EXPECT_NE(result.out.find(": no state could be judged: in every one, a joint locked (J1)"), std::string::npos)
      << result.out;
  const std::string md = test::read_text(out / "report.md");
  EXPECT_NE(md.find("| none judged | none judged | none judged | none judged | 100.0% |"), std::string::npos) << md;
  EXPECT_EQ(md.find("nan"), std::string::npos) << md;
}

TEST(Report, BadSceneIsAnInputError) {
  TempDir dir;
  const std::string scene = dir.write("bad.yaml", "sweepgen_scene: 1\nsolver: x\nurdf: missing.urdf\n");
  const auto result = run_command(
      shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", scene, "--out", (dir.path() / "out").string()}));
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("missing.urdf"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "out"));  // every scene is read before anything is written
}

TEST(Report, BadCommandLinesAreUsageErrors) {
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"--root", "base"}, {"--scene", planar_scene(), "--urdf", "x.urdf"},
        {"--states", "0"}, {"--quick", "--stability"}}) {
    std::vector<std::string> command{SWEEPGEN_EXECUTABLE, "report"};
    command.insert(command.end(), arguments.begin(), arguments.end());
    const auto result = run_command(shell_command(command));
    EXPECT_EQ(result.exit_code, 2) << arguments.front() << "\n" << result.err;
  }
}

// An output folder that cannot be made (a file is in the way): exit 3, naming it, no report.
TEST(Report, UnwritableOutputIsAToolError) {
  TempDir dir;
  const std::string file = dir.write("file", "in the way\n");
  const auto result = run_command(shell_command(
      {SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--quick", "--out", file + "/report"}));
  EXPECT_EQ(result.exit_code, 3) << result.err;
  EXPECT_NE(result.err.find(file + "/report"), std::string::npos) << result.err;
  EXPECT_EQ(test::read_text(file), "in the way\n");
}

TEST(Report, CompilerFailureIsAToolError) {
  TempDir dir;
  for (const char* compiler : {"false", "sweepgen-no-such-compiler"}) {
    const auto result = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--states",
                                                   "5", "--cxx", compiler, "--out", (dir.path() / "out").string()}));
    EXPECT_EQ(result.exit_code, 3) << compiler << "\n" << result.err;
    EXPECT_NE(result.err.find("compiler"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find(compiler), std::string::npos) << result.err;
    // Found missing before the scene is studied (report/external_tools.hpp).
    EXPECT_EQ(result.err.find("[1/1"), std::string::npos) << result.err;
    // No report, and no staging folder left behind.
    for (const auto& entry : std::filesystem::directory_iterator(dir.path() / "out"))
      EXPECT_EQ(entry.path().filename(), "build") << entry.path();
  }
}

// A "compiler" that succeeds but writes something that is no shared library: dlopen fails.
TEST(Report, DlopenFailureIsAToolError) {
  TempDir dir;
  const std::string fake = dir.write("fake-cxx", "#!/bin/sh\n[ \"$1\" = --version ] && exit 0\nfor a; do out=$a; done\n"
                                                 "echo 'not a library' > \"$out\"\n");
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  const auto result = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--scene", planar_scene(), "--states",
                                                 "5", "--cxx", fake, "--out", (dir.path() / "out").string()}));
  EXPECT_EQ(result.exit_code, 3) << result.err;
  EXPECT_NE(result.err.find("dlopen"), std::string::npos) << result.err;
}

// `sweepgen report --stability` on two small cases (a bundled scene and a scaled family arm):
// both policies, the three variants, the documented columns, and generated double within the
// stability suite's bound (100 eps kappa, tests/test_stability.cpp) on the full-rank states.
TEST(Report, StabilityReportOnTwoCases) {
  const std::vector<std::string> columns = {
      "case",        "policy",          "variant",    "scalar",              "state",
      "kind",        "cond_s_E",        "min_rho_D",  "cond_M",              "kappa",
      "rel_err_qdd", "rel_err_tau_cmd", "rel_err_nu", "constraint_residual", "status",
      "referee_status", "finite",       "representable", "bias_vs_pivoted"};
  TempDir dir;
  const auto out = dir.path() / "stability";
  const auto result = run_command(shell_command({SWEEPGEN_EXECUTABLE, "report", "--stability", "--cases",
                                                 "planar_nc2,arm_micro", "--states-per-kind", "2", "--out",
                                                 out.string()}));
  ASSERT_EQ(result.exit_code, 0) << result.out << result.err;
  for (const char* heading : {"max_err/(eps*kappa)", "max_cond_M", "max_residual_full_rank"})
    EXPECT_NE(result.out.find(heading), std::string::npos) << heading << "\n" << result.out;

  std::istringstream csv(test::read_text(out / "stability.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  ASSERT_EQ(split_csv(line), columns) << line;
  const auto column = [&columns](const char* name) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
  };
  std::map<std::string, int> rows;  // "case policy variant scalar" -> states
  int checked[2] = {0, 0}, planar_checked = 0;  // generated double, float states judged
  // The full-rank generated states of arm_micro (near-singular by design) and planar_nc2 beyond
  // the scalars' domains: measured 28 of 88 (32%); at most 80%.
  test::SkipCount skips("stability report, generated states beyond their scalar's domain", 0.8);
  while (std::getline(csv, line)) {
    const auto f = split_csv(line);
    ASSERT_EQ(f.size(), columns.size()) << line;
    ++rows[f[column("case")] + " " + f[column("policy")] + " " + f[column("variant")] + " " + f[column("scalar")]];
    EXPECT_EQ(f[column("bias_vs_pivoted")].empty(), f[column("policy")] == "pivoted_ldlt") << line;
    // planar_nc2 where nothing was dropped or locked: M(q) is positive definite, and generated
    // double meets its two constraints to rounding.
    if (f[column("case")] == "planar_nc2" && f[column("status")] == "0") {
      const double cond_M = number(f[column("cond_M")]);
      EXPECT_TRUE(std::isfinite(cond_M)) << line;
      EXPECT_GE(cond_M, 1) << line;
      if (f[column("variant")] == "generated" && f[column("scalar")] == "double") {
        EXPECT_LE(number(f[column("constraint_residual")]), 1e-9) << line;
        ++planar_checked;
      }
    }
    const bool full_rank = f[column("representable")] == "1" && f[column("status")] == "0" &&
                           f[column("referee_status")] == "0";
    if (f[column("variant")] != "generated" || !full_rank) continue;
    // Each scalar inside its domain (docs/stability.md; tests/generated/scene_test.cpp.in):
    // error ≤ 100 eps κ where κ ≤ 1e8 in double (ceiling 2.2e-6) and κ ≤ 1e3 in float (ceiling
    // 1.2e-2); states beyond are counted.
    const bool single = f[column("scalar")] == "float";
    const double kappa = number(f[column("kappa")]);
    if (skips.skip(kappa > (single ? test::kFloatMaxKappa : test::kDoubleMaxKappa),
                   single ? "float, kappa > 1e3" : "double, kappa > 1e8"))
      continue;
    const double eps = single ? std::numeric_limits<float>::epsilon() : std::numeric_limits<double>::epsilon();
    const double error = std::max({number(f[column("rel_err_qdd")]), number(f[column("rel_err_tau_cmd")]),
                                   number(f[column("rel_err_nu")])});
    EXPECT_LE(error, 100 * eps * kappa) << line;
    ++checked[single];
  }
  EXPECT_GT(checked[0], 0) << "no full-rank generated double state inside its domain";
  EXPECT_GT(checked[1], 0) << "no full-rank generated float state inside its domain";
  EXPECT_GT(planar_checked, 0) << "no planar_nc2 generated double state with status 0";
  for (const char* c : {"planar_nc2", "arm_micro"})
    for (const char* policy : {"pivoted_ldlt", "damped"})
      for (const char* variant : {"reference double", "generated double", "generated float"})
        EXPECT_GT(rows[std::string(c) + " " + policy + " " + variant], 0) << c << " " << policy << " " << variant;

  EXPECT_GT(std::filesystem::file_size(out / "stability.png"), 0u);
}

// What the report needs from outside (the compiler, gnuplot) is checked before any work: without
// gnuplot on PATH both reports stop at once with exit 3 naming it, not after measuring every
// case and drawing the first figure.
TEST(Report, MissingGnuplotStopsBeforeAnyWork) {
  TempDir dir;
  const std::string without_gnuplot = "PATH=" + dir.path().string() + " ";
  for (const std::vector<std::string>& arguments :
       {std::vector<std::string>{"--scene", planar_scene(), "--quick"}, {"--stability", "--cases", "planar_nc2"}}) {
    std::vector<std::string> command{SWEEPGEN_EXECUTABLE, "report", "--cxx", "/usr/bin/c++", "--out",
                                     (dir.path() / "out").string()};
    command.insert(command.end(), arguments.begin(), arguments.end());
    const auto result = run_command(without_gnuplot + shell_command(command));
    EXPECT_EQ(result.exit_code, 3) << arguments.front() << "\n" << result.err;
    EXPECT_NE(result.err.find("gnuplot: cannot be run"), std::string::npos) << result.err;
    // Nothing was studied: no scene's or case's progress line.
    EXPECT_EQ(result.err.find("[1/1"), std::string::npos) << result.err;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out" / "report.md"));
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out" / "stability.csv"));
  }
}

TEST(Report, StabilityUnknownCaseIsAnInputError) {
  TempDir dir;
  const auto out = dir.path() / "stability";
  const auto result = run_command(shell_command(
      {SWEEPGEN_EXECUTABLE, "report", "--stability", "--cases", "planar_nc2,arm_mikro", "--out", out.string()}));
  EXPECT_EQ(result.exit_code, 1) << result.err;
  EXPECT_NE(result.err.find("--cases 'arm_mikro'"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("did you mean 'arm_micro'"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(out / "stability.csv"));
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

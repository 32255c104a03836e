// `sweepgen report`'s outputs from the scene studies (README, "sweepgen report"): the summary
// printed per scene, report.csv (one line per scene, variant and family), states.csv (one line
// per scene, variant and state), two figures per scene in PNG and SVG (error against time with
// p50–p99 whiskers; error against κ with the ε κ lines and float's domain), and report.md, which
// embeds the figures and says which variant to use in a sentence per scene.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "io/output_files.hpp"
#include "report/study.hpp"

namespace sweepgen::report {

// The summary table of one scene: one row per variant, all families together.
void print_study(const SceneStudy& study, std::ostream& out);

// report.csv: scene, variant, scalar, family ("all" for every family together), states, judged,
// err_median, err_p99, err_max, max_residual, status_raised, ns_median, ns_p99, ns_max, note, solves.
std::string report_csv(const std::vector<SceneStudy>& studies);
// states.csv: scene, variant, family, kappa, err_qdd, err_tau, err_nu, residual, status,
// referee_status, judged (1/0).
std::string states_csv(const std::vector<SceneStudy>& studies);

// Draws `<name>_time` and `<name>_kappa` (.png and .svg) of each study into `dir` with gnuplot
// (scripts and data in `work_dir`) and returns the file names written, relative to `dir`.
std::vector<std::string> draw_figures(const std::vector<SceneStudy>& studies, const std::filesystem::path& dir,
                                      const std::filesystem::path& work_dir);

// report.md: how it was made (`command`, `setup`), then per scene its recommendation, summary
// table, per-family table and figures (PNG, linked relatively).
std::string report_markdown(const std::vector<SceneStudy>& studies, const std::string& command,
                            const std::string& setup);

}  // namespace sweepgen::report

// sweepgen command line: one subcommand per job.
#include <CLI/CLI.hpp>
#include <csignal>
#include <iostream>

#include "cli/family_command.hpp"
#include "cli/generate_command.hpp"
#include "io/output_files.hpp"
#include "cli/solve_command.hpp"
#include "model/error.hpp"
#include "report/report_command.hpp"

int main(int argc, char** argv) {
  // A write beyond the file-size limit (RLIMIT_FSIZE, a full quota) then fails with EFBIG
  // instead of killing the process: the writer reports it (exit 3) and removes its temporaries.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"sweepgen: robot-specific Popov-Vereshchagin (ACHD) solvers from URDF"};
  app.set_version_flag("--version", std::string("sweepgen ") + SWEEPGEN_VERSION);
  app.require_subcommand(1);
  sweepgen::cli::SolveOptions solve_options;
  sweepgen::cli::add_solve_command(app, solve_options);
  sweepgen::cli::GenerateOptions generate_options;
  sweepgen::cli::add_generate_command(app, generate_options);
  sweepgen::cli::SceneOptions info_options;
  sweepgen::cli::add_info_command(app, info_options);
  sweepgen::report::ReportOptions report_options;
  sweepgen::report::add_report_command(app, report_options);
  sweepgen::cli::FamilyOptions family_options;
  sweepgen::cli::add_family_command(app, family_options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (app.got_subcommand("solve")) return sweepgen::cli::run_solve(solve_options);
    if (app.got_subcommand("generate")) return sweepgen::cli::run_generate(generate_options);
    if (app.got_subcommand("info")) return sweepgen::cli::run_info(info_options);
    if (app.got_subcommand("report")) return sweepgen::report::run_report(report_options);
    if (app.got_subcommand("family")) return sweepgen::cli::run_family(family_options);
  } catch (const sweepgen::InputError& e) {
    std::cerr << "sweepgen: error: " << e.what() << "\n";
    return 1;
  } catch (const sweepgen::io::IoError& e) {
    std::cerr << "sweepgen: error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}

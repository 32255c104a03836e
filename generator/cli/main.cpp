// sweepgen command line: one subcommand per job; `report` is the program sweepgen-report
// (cli/report_program.hpp).
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/command_line.hpp"
#include "cli/family_command.hpp"
#include "cli/generate_command.hpp"
#include "cli/report_program.hpp"
#include "cli/solve_command.hpp"

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && args.front() == "report")
    return sweepgen::cli::run_report_program(std::vector<std::string>(args.begin() + 1, args.end()));
  CLI::App app{"sweepgen: robot-specific Popov-Vereshchagin (ACHD) solvers from URDF"};
  app.set_version_flag("--version", std::string("sweepgen ") + SWEEPGEN_VERSION);
  app.require_subcommand(1);
  sweepgen::cli::SolveOptions solve_options;
  sweepgen::cli::add_solve_command(app, solve_options);
  sweepgen::cli::GenerateOptions generate_options;
  sweepgen::cli::add_generate_command(app, generate_options);
  sweepgen::cli::SceneOptions info_options;
  sweepgen::cli::add_info_command(app, info_options);
  // Listed in --help; `sweepgen report ...` is handed to sweepgen-report above.
  CLI::App* report = app.add_subcommand("report",
                     "Study scenes' generated solvers against the reference solver, KDL and a dense KKT: error and "
                     "time per variant, report.md with figures (runs sweepgen-report; sweepgen report --help)");
  report->allow_extras();
  sweepgen::cli::FamilyOptions family_options;
  sweepgen::cli::add_family_command(app, family_options);
  return sweepgen::cli::run_command_line(app, args, [&] {
    if (app.got_subcommand("solve")) return sweepgen::cli::run_solve(solve_options);
    if (app.got_subcommand("generate")) return sweepgen::cli::run_generate(generate_options);
    if (app.got_subcommand("info")) return sweepgen::cli::run_info(info_options);
    if (app.got_subcommand("family")) return sweepgen::cli::run_family(family_options);
    return sweepgen::cli::run_report_program(report->remaining());
  });
}

// sweepgen-report: the program behind `sweepgen report` (cli/report_program.hpp), which runs it
// with the words that follow `report`; its command line reads as `sweepgen report ...`.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "cli/command_line.hpp"
#include "report/report_command.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sweepgen: robot-specific Popov-Vereshchagin (ACHD) solvers from URDF", "sweepgen"};
  app.set_version_flag("--version", std::string("sweepgen ") + SWEEPGEN_VERSION);
  app.require_subcommand(1);
  sweepgen::report::ReportOptions options;
  sweepgen::report::add_report_command(app, options);
  std::vector<std::string> args{"report"};
  args.insert(args.end(), argv + 1, argv + argc);
  return sweepgen::cli::run_command_line(app, args, [&] { return sweepgen::report::run_report(options); });
}

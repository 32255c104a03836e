// sweepgen command line: one subcommand per job.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli/solve_command.hpp"
#include "model/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sweepgen: robot-specific Popov-Vereshchagin (ACHD) solvers from URDF"};
  app.set_version_flag("--version", std::string("sweepgen ") + SWEEPGEN_VERSION);
  app.require_subcommand(1);
  sweepgen::cli::SolveOptions solve_options;
  sweepgen::cli::add_solve_command(app, solve_options);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (app.got_subcommand("solve")) return sweepgen::cli::run_solve(solve_options);
  } catch (const sweepgen::InputError& e) {
    std::cerr << "sweepgen: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

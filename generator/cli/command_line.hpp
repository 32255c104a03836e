// What both programs of the command line share, sweepgen and sweepgen-report (the program behind
// `sweepgen report`, cli/report_program.hpp): parsing with CLI11 and the exit codes of README.md,
// "Exit codes" (0 success, 1 bad input, 2 usage, 3 I/O or a failing external tool).
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <csignal>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "io/output_files.hpp"
#include "model/error.hpp"

namespace sweepgen::cli {

// A path option's check: an empty one names no file or directory (a usage error, exit 2).
inline const CLI::Validator kNonEmptyPath(
    [](const std::string& path) { return path.empty() ? std::string("an empty path") : std::string(); }, "PATH");

// The exit code of an internal error (docs/exit-codes.md, "Exit codes").
constexpr int kInternalError = 5;

// Parses `args` (the words after the program's name) with `app`, then returns `run()`'s exit
// code, or the exit code of the error it throws, said on standard error.
inline int run_command_line(CLI::App& app, std::vector<std::string> args, const std::function<int()>& run) {
  // A write beyond the file-size limit (RLIMIT_FSIZE, a full quota) then fails with EFBIG
  // instead of killing the process: the writer reports it (exit 3) and removes its temporaries.
  std::signal(SIGXFSZ, SIG_IGN);
  std::reverse(args.begin(), args.end());  // CLI11 takes the words last first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return run();
  } catch (const InputError& e) {
    std::cerr << "sweepgen: error: " << e.what() << "\n";
    return 1;
  } catch (const io::IoError& e) {
    std::cerr << "sweepgen: error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    // Anything else is sweepgen's own fault, not the input's: said, with its own exit code,
    // instead of std::terminate's abort.
    std::cerr << "sweepgen: internal error (please report it with the input): " << e.what() << "\n";
    return kInternalError;
  }
}

}  // namespace sweepgen::cli

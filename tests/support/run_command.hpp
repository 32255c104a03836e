// Runs a shell command and captures its exit code, standard output and standard error
// separately; optional text is fed to its standard input (otherwise it reads /dev/null).
#pragma once

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace sweepgen::test {

struct CommandResult {
  int exit_code = -1;  // the exit status, or 128 + signal number if killed by a signal
  std::string out;     // standard output
  std::string err;     // standard error
};

// `text` quoted for /bin/sh (single quotes, embedded ones escaped).
inline std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) {
    if (c == '\'')
      quoted += "'\\''";
    else
      quoted += c;
  }
  return quoted + "'";
}

// The words quoted and joined by spaces: a command line for /bin/sh.
inline std::string shell_command(const std::vector<std::string>& words) {
  std::string command;
  for (const auto& word : words) command += (command.empty() ? "" : " ") + shell_quote(word);
  return command;
}

// Runs `command` through /bin/sh. Standard input comes from a temporary file holding `input`
// (from /dev/null when there is none), standard error goes to a temporary file; both are
// removed afterwards.
inline CommandResult run_command(const std::string& command, const std::string* input = nullptr) {
  std::random_device device;
  const auto base = std::filesystem::temp_directory_path() /
                    ("sweepgen-run-" + std::to_string(device()) + "-" + std::to_string(device()));
  const std::string in_path = base.string() + ".in", err_path = base.string() + ".err";
  if (input) {
    std::ofstream in(in_path, std::ios::binary);
    in << *input;
    if (!in) throw std::runtime_error("run_command: cannot write " + in_path);
  }
  const std::string full = "(" + command + ") < " + shell_quote(input ? in_path : "/dev/null") + " 2> " +
                           shell_quote(err_path);
  CommandResult result;
  FILE* pipe = ::popen(full.c_str(), "r");
  if (!pipe) throw std::runtime_error("run_command: popen failed for " + command);
  char buffer[4096];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, got);
  const int status = ::pclose(pipe);
  if (status != -1 && WIFEXITED(status))
    result.exit_code = WEXITSTATUS(status);
  else if (status != -1 && WIFSIGNALED(status))
    result.exit_code = 128 + WTERMSIG(status);
  {
    std::ifstream err(err_path, std::ios::binary);
    std::ostringstream text;
    text << err.rdbuf();
    result.err = text.str();
  }
  std::error_code ignored;
  std::filesystem::remove(in_path, ignored);
  std::filesystem::remove(err_path, ignored);
  return result;
}

inline CommandResult run_command(const std::string& command, const std::string& input) {
  return run_command(command, &input);
}

}  // namespace sweepgen::test

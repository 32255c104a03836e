#include "report/native_library.hpp"

#include <dlfcn.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <deque>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/output_files.hpp"

extern char** environ;

namespace sweepgen::report {

int run_process(const std::vector<std::string>& argv, const std::string& log_path) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 127;
}

std::string command_line(const std::vector<std::string>& argv) {
  std::string line;
  for (const auto& word : argv) {
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
                                            "+-_./=:,@%") == std::string::npos;
    std::string quoted = word;
    if (!plain) {
      quoted = "'";
      for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      quoted += "'";
    }
    line += (line.empty() ? "" : " ") + quoted;
  }
  return line;
}

std::string tail_of_file(const std::string& path, std::size_t max_lines) {
  std::ifstream in(path);
  std::deque<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    lines.push_back(line);
    if (lines.size() > max_lines) lines.pop_front();
  }
  std::string text;
  for (const auto& line : lines) text += "  " + line + "\n";
  return text;
}

std::string wrapper_source(const std::string& header_name, const std::string& solver_namespace, bool with_float,
                           const std::vector<std::string>& policies, const std::vector<std::string>& derivative_policies) {
  std::ostringstream s;
  s << "// Written by `sweepgen report`: C entry points around the flat solves, for dlsym().\n"
    << "#include \"" << header_name << "\"\n\n"
    << "extern \"C\" {\n";
  for (const std::string& policy : policies)
    s << "void report_solve_f64_" << policy << "(const double* in, double* out) { " << solver_namespace << "::f64::solve_"
      << policy << "_flat(in, out); }\n";
  if (with_float)
    s << "void report_solve_f32(const float* in, float* out) { " << solver_namespace
      << "::f32::solve_original_flat(in, out); }\n";
  for (const std::string& policy : derivative_policies)
    s << "void report_derivatives_f64_" << policy << "(const double* in, double* out) { " << solver_namespace
      << "::f64::derivatives_" << policy << "_flat(in, out); }\n";
  s << "int report_flat_in_size(void) { return " << solver_namespace << "::f64::flat_in_size; }\n"
    << "int report_flat_out_size(void) { return " << solver_namespace << "::f64::flat_out_size; }\n"
    << "}\n";
  return s.str();
}

std::string isa_name(Isa isa) { return isa == Isa::x86_64_v3 ? "x86-64-v3" : "x86-64"; }

bool cpu_supports(Isa isa) {
  if (isa == Isa::baseline) return true;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2");
#else
  return false;
#endif
}

std::vector<std::string> compile_command(const std::string& compiler, const std::vector<std::string>& sources,
                                         const std::string& include_dir, const std::string& output, Isa isa,
                                         Optimisation optimisation) {
  std::vector<std::string> argv = {compiler, "-std=c++17"};
  if (optimisation == Optimisation::checked && isa != Isa::baseline)
    throw std::invalid_argument("compile_command: checked (-O0) code is compiled for the x86-64 baseline only");
  if (optimisation == Optimisation::checked)
    argv.push_back("-O0");
  else if (isa == Isa::x86_64_v3)
    argv.insert(argv.end(), {"-O3", "-march=x86-64-v3"});
  else
    argv.push_back("-O2");
  argv.insert(argv.end(), {"-shared", "-fPIC", "-I" + include_dir});
  argv.push_back("-DSWEEPGEN_BATCH_STATE_BY_STATE");  // templates/lanes.mustache
  argv.insert(argv.end(), sources.begin(), sources.end());
  argv.push_back("-o");
  argv.push_back(output);
  return argv;
}

SharedLibrary::SharedLibrary(const std::string& path) : path_(path) {
  handle_ = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle_) {
    const char* error = ::dlerror();
    throw io::IoError(path + ": dlopen failed (" + (error ? error : "unknown error") + ")");
  }
}

SharedLibrary::~SharedLibrary() {
  if (handle_) ::dlclose(handle_);
}

void* SharedLibrary::symbol(const std::string& name) const {
  ::dlerror();
  void* address = ::dlsym(handle_, name.c_str());
  if (!address) {
    const char* error = ::dlerror();
    throw io::IoError(path_ + ": dlsym(" + name + ") failed (" + (error ? error : "null symbol") + ")");
  }
  return address;
}

}  // namespace sweepgen::report

// `sweepgen report`: the generated solver compiled by the system compiler into a shared
// library and loaded into the running process, and other external tools (gnuplot).
#pragma once

#include <string>
#include <vector>

namespace sweepgen::report {

// Runs argv[0] (searched in PATH) with argv, standard input from /dev/null and standard output
// and error appended to `log_path`. Returns the exit status (128 + signal when killed, -1 when
// it could not be started).
int run_process(const std::vector<std::string>& argv, const std::string& log_path);

// The command line as a shell would take it (words quoted where needed), for messages.
std::string command_line(const std::vector<std::string>& argv);

// The last `max_lines` lines of a text file ("" if unreadable).
std::string tail_of_file(const std::string& path, std::size_t max_lines = 30);

// The C++ source of the wrapper: extern "C" entry points around the flat solves of
// `solver_namespace` (f64 for each of `policies`, the original one in f32 when `with_float`) plus
// the flat sizes:
//   void report_solve_f64_<policy>(const double* in, double* out);
//   void report_solve_f32(const float* in, float* out);
//   int report_flat_in_size(void);  int report_flat_out_size(void);
// and f64 derivatives (scene key derivatives) for each of `derivative_policies`:
//   void report_derivatives_f64_<policy>(const double* in, double* out);
std::string wrapper_source(const std::string& header_name, const std::string& solver_namespace, bool with_float,
                           const std::vector<std::string>& policies,
                           const std::vector<std::string>& derivative_policies = {});

// Instruction sets the report compiles generated code for: the x86-64 baseline (SSE2, what a
// default build deploys) and x86-64-v3 (AVX2, FMA, BMI2; Haswell and Zen or newer).
enum class Isa { baseline, x86_64_v3 };
std::string isa_name(Isa isa);  // "x86-64", "x86-64-v3"
// Whether this CPU runs `isa` (baseline: always).
bool cpu_supports(Isa isa);

// What the compiled code is for. `deployed`: run and timed as a controller would build it, -O2 for
// the baseline and -O3 -march=x86-64-v3 for v3 (the flag pairs the benchmarks quote). `checked`:
// run only for its numbers (the stability study, the tests), at -O0 and for the baseline only.
// There both give the same numbers bit for bit: x86-64 without -march has no fused multiply-add,
// -std=c++17 turns contraction off, and every double and float operation is one SSE2 instruction
// rounding to its type, at any -O (tests/test_emitter.cpp, OptimisationDoesNotChangeTheNumbers).
// A long straight-line generated file compiles ~25x faster at -O0 (a floating base's derivative
// functions: 4.2 s against 110 s at -O2).
enum class Optimisation { deployed, checked };

// The compile command for `sources` into the shared library `output`, whose callers call only the
// flat solves: the batch entry points state by state (SWEEPGEN_BATCH_STATE_BY_STATE), so that the
// batch lanes are not compiled. Throws std::invalid_argument for `checked` code for v3, whose
// contractions differ by -O.
std::vector<std::string> compile_command(const std::string& compiler, const std::vector<std::string>& sources,
                                         const std::string& include_dir, const std::string& output, Isa isa,
                                         Optimisation optimisation = Optimisation::deployed);

// A dlopen()ed shared library, closed on destruction. Throws io::IoError with dlerror()'s text.
class SharedLibrary {
 public:
  explicit SharedLibrary(const std::string& path);
  ~SharedLibrary();
  SharedLibrary(const SharedLibrary&) = delete;
  SharedLibrary& operator=(const SharedLibrary&) = delete;
  // The address of `name`; throws io::IoError when it is missing.
  void* symbol(const std::string& name) const;

 private:
  std::string path_;
  void* handle_ = nullptr;
};

}  // namespace sweepgen::report

// libFuzzer target: one `sweepgen solve` input line (JSON, then cli::parse_problem on the Panda).
// The contract and its checks live in fuzz_entries.cpp, shared with tests/test_fuzz_regressions.cpp;
// anything escaping solve_line_input (another exception type, a ContractViolation) aborts and is a finding.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sweepgen::fuzz::solve_line_input(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}

// How many random states a statistical test draws (or how many times a test repeats a race): the
// full count divided by the state divisor, at least one.
//
// The divisor is the environment's SWEEPGEN_TEST_STATE_DIVISOR where it is set (a positive
// integer), else the build's: 10 in the sanitizer build (SWEEPGEN_SANITIZE; its job is to run
// every code path under AddressSanitizer and UndefinedBehaviorSanitizer, which a tenth of the
// states still does, at several times the cost per state), 1 otherwise. CI's release pass sets 10
// through the `release-ci` test preset (cmake/test-all.sh, docs/building.md): the same tests on a
// tenth of the states; `ctest --preset release` runs the full counts on the same build.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

namespace sweepgen::test {

#ifdef SWEEPGEN_TEST_STATE_DIVISOR
constexpr int kBuildStateDivisor = SWEEPGEN_TEST_STATE_DIVISOR;
#else
constexpr int kBuildStateDivisor = 1;
#endif

// The divisor a value of SWEEPGEN_TEST_STATE_DIVISOR names: the build's where there is none, no
// value where it is not a positive integer below 10^6.
inline std::optional<int> state_divisor_from(const char* value, int build_divisor) {
  if (value == nullptr) return build_divisor;
  const std::string text(value);
  if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) return std::nullopt;
  const int divisor = std::stoi(text);
  if (divisor < 1) return std::nullopt;
  return divisor;
}

// The process's divisor, read once; a value that is not one stops the test program with a message
// (it may be read while namespace-scope constants are initialised, before any test runs).
inline int state_divisor() {
  static const int divisor = [] {
    const char* value = std::getenv("SWEEPGEN_TEST_STATE_DIVISOR");
    const std::optional<int> read = state_divisor_from(value, kBuildStateDivisor);
    if (!read) {
      std::fprintf(stderr, "SWEEPGEN_TEST_STATE_DIVISOR=\"%s\": not a positive integer (the share of random states the "
                           "statistical tests draw: 1 all, 10 a tenth)\n", value);
      std::exit(2);
    }
    return *read;
  }();
  return divisor;
}

inline int state_count(int full) { return std::max(1, full / state_divisor()); }

}  // namespace sweepgen::test

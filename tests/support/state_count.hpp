// How many random states a statistical test draws (or how many times a test repeats a race). The
// sanitizer build (SWEEPGEN_SANITIZE, the second pass of .ci/run) takes a tenth: its job is to run
// every code path under AddressSanitizer and UndefinedBehaviorSanitizer, which a tenth of the
// states still does, at several times the cost per state. The release build takes them all.
#pragma once

namespace sweepgen::test {

#ifdef SWEEPGEN_TEST_STATE_DIVISOR
constexpr int kStateDivisor = SWEEPGEN_TEST_STATE_DIVISOR;
#else
constexpr int kStateDivisor = 1;
#endif

constexpr int state_count(int full) { return full / kStateDivisor > 0 ? full / kStateDivisor : 1; }

}  // namespace sweepgen::test

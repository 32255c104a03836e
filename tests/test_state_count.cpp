// The state divisor of the statistical tests (support/state_count.hpp): the build's unless the
// environment names one, and a value that names none refused rather than read as some count.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;

TEST(StateCount, TheEnvironmentNamesTheDivisorOrLeavesTheBuilds) {
  EXPECT_EQ(test::state_divisor_from(nullptr, 1), 1);
  EXPECT_EQ(test::state_divisor_from(nullptr, 10), 10);
  EXPECT_EQ(test::state_divisor_from("10", 1), 10);  // CI's release pass (the release-ci test preset)
  EXPECT_EQ(test::state_divisor_from("1", 10), 1);   // full counts in the sanitizer build
  for (const char* refused : {"", "0", "-3", "+2", " 4", "4 ", "2.5", "ten", "1000000"})
    EXPECT_EQ(test::state_divisor_from(refused, 1), std::nullopt) << '"' << refused << '"';
}

TEST(StateCount, ACountIsTheFullOneDividedAndNeverNone) {
  const int divisor = test::state_divisor();
  EXPECT_EQ(test::state_count(10000), 10000 / divisor);
  EXPECT_EQ(test::state_count(1), 1);
  std::printf("[states] divisor %d: 10000 states become %d\n", divisor, test::state_count(10000));
}

// This test program itself, run again with the variable set: read, or refused with a message and
// exit status 2 before any test runs.
TEST(StateCount, TheTestProgramReadsTheVariableOrStops) {
  const auto run = [](const std::string& value) {
    return test::run_command("SWEEPGEN_TEST_STATE_DIVISOR=" + test::shell_quote(value) + " " +
                             test::shell_command({fs::read_symlink("/proc/self/exe").string(),
                                                  "--gtest_filter=StateCount.ACountIsTheFullOneDividedAndNeverNone"}));
  };
  const test::CommandResult tenth = run("10");
  EXPECT_EQ(tenth.exit_code, 0) << tenth.err;
  EXPECT_NE(tenth.out.find("[states] divisor 10: 10000 states become 1000\n"), std::string::npos) << tenth.out;
  const test::CommandResult refused = run("ten");
  EXPECT_EQ(refused.exit_code, 2) << refused.out;
  EXPECT_NE(refused.err.find("SWEEPGEN_TEST_STATE_DIVISOR=\"ten\": not a positive integer"), std::string::npos)
      << refused.err;
  EXPECT_EQ(refused.out.find("[states]"), std::string::npos) << "a test ran: " << refused.out;
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

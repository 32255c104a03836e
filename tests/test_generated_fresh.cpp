// generated/ holds the output of every bundled scene (robots/*/*.yaml) byte for byte. That output
// compiles warning-free under -Wall -Wextra -Wpedantic -Werror: the build compiles every bundled
// scene so (cmake/BundledScenes.cmake), with g++ in the release workflow and clang++ in the
// sanitize one, so a warning fails the build of either (a test compiling generated/ again with
// both, as this file did, cost 2 CPU-minutes of CI for nothing the builds do not check).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/run_command.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;

std::vector<fs::path> bundled_scenes() {
  std::vector<fs::path> scenes;
  for (const auto& robot : fs::directory_iterator(fs::path(SWEEPGEN_SOURCE_DIR) / "robots"))
    if (robot.is_directory())
      for (const auto& file : fs::directory_iterator(robot.path()))
        if (file.path().extension() == ".yaml") scenes.push_back(file.path());
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}


const char* kHowToRegenerate = "generated/ is stale: run `cmake --build build --target regenerate` and commit it";

TEST(GeneratedFiles, MatchTheGeneratorByteForByte) {
  const auto scenes = bundled_scenes();
  ASSERT_GE(scenes.size(), 6u);
  test::TempDir dir;
  std::size_t files = 0;
  for (const auto& scene : scenes) {
    const auto run = test::run_command(
        test::shell_command({SWEEPGEN_EXECUTABLE, "generate", "--scene", scene.string(), "--out", dir.path().string()}));
    ASSERT_EQ(run.exit_code, 0) << scene << "\n" << run.err;
  }
  for (const auto& fresh : fs::directory_iterator(dir.path())) {
    const fs::path committed = fs::path(SWEEPGEN_SOURCE_DIR) / "generated" / fresh.path().filename();
    ASSERT_TRUE(fs::exists(committed)) << committed << " is missing; " << kHowToRegenerate;
    EXPECT_EQ(test::read_text(fresh.path()), test::read_text(committed)) << committed << " differs; " << kHowToRegenerate;
    ++files;
  }
  std::size_t committed_files = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(SWEEPGEN_SOURCE_DIR) / "generated"))
    committed_files += entry.path().extension() != ".md" ? 1 : 0;
  EXPECT_EQ(committed_files, files) << "generated/ holds files no bundled scene produces; " << kHowToRegenerate;
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// The fuzz targets' inputs in the normal build: every seed (the bundled robots/ inputs and
// fuzz/corpus/<target>/, collected at configure time by fuzz/FuzzSupport.cmake) and every saved
// finding (fuzz/regressions/<target>/) goes through the same entry function the libFuzzer target
// calls (fuzz/fuzz_entries.hpp). That function already fails (throws ContractViolation or lets
// the foreign exception escape) when a reader throws anything but its documented error, when an
// error message does not name the file or key, the element and a reason, or when an accepted
// result is inconsistent. On top, each file's name says what must happen to it: "reject_*" must be
// rejected with the documented error; a name of 40 hex digits (an input fuzz/run.sh merged into
// fuzz/corpus/ for the coverage it reached, named by libFuzzer after its SHA-1) is held to the
// contract alone; anything else must be accepted.
#include <gtest/gtest.h>

#include <cxxabi.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "fuzz_entries.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {

namespace fs = std::filesystem;

struct Target {
  std::string name;  // as in fuzz/<name>.dict, fuzz/corpus/<name>/, fuzz/regressions/<name>/
  fuzz::Outcome (*entry)(const std::string&);
};

void PrintTo(const Target& target, std::ostream* out) { *out << target.name; }  // test names and failures

const std::vector<Target>& targets() {
  static const std::vector<Target> all = {
      {"urdf", &fuzz::urdf_input}, {"scene", &fuzz::scene_input}, {"solve_line", &fuzz::solve_line_input}};
  return all;
}

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().filename().string()[0] != '.') files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}


bool must_be_rejected(const fs::path& file) { return file.filename().string().rfind("reject_", 0) == 0; }

bool merged_for_coverage(const fs::path& file) {
  const std::string name = file.filename().string();
  return name.size() == 40 && std::all_of(name.begin(), name.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

std::string type_name(const std::type_info& type) {
  int status = 0;
  std::unique_ptr<char, void (*)(void*)> demangled(abi::__cxa_demangle(type.name(), nullptr, nullptr, &status), std::free);
  return status == 0 ? demangled.get() : type.name();
}

// Runs one input through the target's entry and checks the outcome against the file's name.
void check_file(const Target& target, const fs::path& file) {
  const std::string bytes = test::read_text(file);
  try {
    const fuzz::Outcome outcome = target.entry(bytes);
    if (must_be_rejected(file)) {
      EXPECT_FALSE(outcome.accepted) << file << " was accepted, but its name says it must be rejected";
      if (!outcome.accepted) {
        EXPECT_FALSE(outcome.error.empty()) << file << ": rejected with an empty message";
      }
    } else if (!merged_for_coverage(file)) {
      EXPECT_TRUE(outcome.accepted) << file << " was rejected: " << outcome.error;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << file << ": " << type_name(typeid(e)) << " escaped the documented errors: " << e.what();
  } catch (...) {
    ADD_FAILURE() << file << ": an exception not derived from std::exception escaped";
  }
}

class FuzzInputs : public ::testing::TestWithParam<Target> {};

TEST_P(FuzzInputs, SeedsBehaveAsNamed) {
  const fs::path dir = fs::path(SWEEPGEN_FUZZ_SEEDS_DIR) / GetParam().name;
  const auto files = files_in(dir);
  ASSERT_FALSE(files.empty()) << "no seeds in " << dir << " (written by fuzz/FuzzSupport.cmake at configure time)";
  for (const auto& file : files) check_file(GetParam(), file);
}

TEST_P(FuzzInputs, RegressionsBehaveAsNamed) {
  const fs::path dir = fs::path(SWEEPGEN_SOURCE_DIR) / "fuzz" / "regressions" / GetParam().name;
  const auto files = files_in(dir);
  ASSERT_FALSE(files.empty()) << "no regression inputs in " << dir;
  // Each target keeps at least one input that must be rejected, so that a reader that stopped
  // rejecting anything would fail here.
  EXPECT_TRUE(std::any_of(files.begin(), files.end(), must_be_rejected)) << "no reject_* input in " << dir;
  for (const auto& file : files) check_file(GetParam(), file);
}

INSTANTIATE_TEST_SUITE_P(Targets, FuzzInputs, ::testing::ValuesIn(targets()),
                         [](const ::testing::TestParamInfo<Target>& info) { return info.param.name; });

// The entries report rejections with the reader's own message: a malformed input of each kind
// names its file (or key) and the element.
TEST(FuzzEntries, MalformedInputsAreRejectedWithFileAndElement) {
  const fuzz::Outcome urdf = fuzz::urdf_input("<robot name='x'><link name='a'></robot");
  EXPECT_FALSE(urdf.accepted);
  EXPECT_NE(urdf.error.find("input.urdf:1:17: <link>: not well-formed"), std::string::npos) << urdf.error;

  const fuzz::Outcome scene = fuzz::scene_input("sweepgen_scene: 1\nsolver: x\nurdf: panda.urdf\npolicy: [original]\n");
  EXPECT_FALSE(scene.accepted);
  EXPECT_NE(scene.error.find("input.yaml:4:1: policy: unknown key 'policy'"), std::string::npos) << scene.error;

  const fuzz::Outcome line = fuzz::solve_line_input(R"({"q": [0, 0, 0, 0, 0, 0, 0], "qd": [0, 0, 0, 0, 0, 0, "x"]})");
  EXPECT_FALSE(line.accepted);
  EXPECT_EQ(line.error, "key 'qd': entry 6 is not a number");
}

}  // namespace
}  // namespace sweepgen

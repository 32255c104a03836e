// How `sweepgen generate` writes its files, as a careful Unix tool does: temporaries no one can
// prepare a link at, existing outputs compared only when they are regular files, a depfile that
// make and Ninja read alike, and a set of outputs that cannot build mixed from two runs.
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "support/run_command.hpp"
#include "support/state_count.hpp"
#include "support/temp_dir.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;
using test::CommandResult;

const std::string kSource = SWEEPGEN_SOURCE_DIR;
const std::string kPlanarScene = kSource + "/robots/planar/planar_nc2.yaml";
const std::string kPlanarUrdf = kSource + "/robots/planar/planar_rpr.urdf";
const std::vector<std::string> kExtensions = {".hpp", ".cpp", ".cu", ".cmake"};

// Whether the generator runs under AddressSanitizer, which reserves terabytes of address space:
// a limit on virtual memory would stop it at its start.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kAddressSanitizer = true;
#else
constexpr bool kAddressSanitizer = false;
#endif
#else
constexpr bool kAddressSanitizer = false;
#endif

// `sweepgen generate` with `args`, stopped after 60 s (and, but under AddressSanitizer, at 2 GiB
// of memory): a run that reads without end fails instead of hanging the suite or the machine.
CommandResult generate(const std::vector<std::string>& args, const std::string& shell_prefix = "") {
  std::vector<std::string> words{"timeout", "60", SWEEPGEN_EXECUTABLE, "generate", "--quiet"};
  words.insert(words.end(), args.begin(), args.end());
  const std::string limit = kAddressSanitizer ? "" : "ulimit -v 2097152 && ";
  return test::run_command(shell_prefix + limit + test::shell_command(words));
}

std::string describe(const CommandResult& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "\n--- stderr:\n" + r.err;
}

bool is_link(const fs::path& path) { return fs::is_symlink(fs::symlink_status(path)); }

// The four files of one `generate` into `out` under `stem`, by extension.
std::map<std::string, std::string> outputs(const fs::path& out, const std::string& stem) {
  std::map<std::string, std::string> texts;
  for (const auto& extension : kExtensions) texts[extension] = test::read_text(out / (stem + extension));
  return texts;
}

bool has_temporaries(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

// ---- Temporaries --------------------------------------------------------------------------------

// The process ids the next 2000 processes will likely get (Linux hands them out in order).
std::vector<long> next_pids() {
  long last = 0, max = 32768;
  std::ifstream("/proc/sys/kernel/ns_last_pid") >> last;
  std::ifstream("/proc/sys/kernel/pid_max") >> max;
  std::vector<long> pids;
  for (long k = 1; k <= 2000; ++k) pids.push_back((last + k) % max);
  return pids;
}

// Links planted at every name `<out>/<stem>.<ext>.tmp<pid>` a predictable temporary could take,
// all to one file outside --out: the run writes its outputs without touching that file, and
// leaves every link as it was.
TEST(OutputFiles, APlantedLinkAtATemporaryNameIsNeverWrittenThrough) {
  if (!fs::exists("/proc/sys/kernel/ns_last_pid")) GTEST_SKIP() << "no /proc/sys/kernel/ns_last_pid";
  test::TempDir dir;
  const fs::path out = dir.path() / "out", reference = dir.path() / "reference";
  const std::string victim = dir.write("victim", "not to be overwritten\n");
  ASSERT_EQ(generate({"--scene", kPlanarScene, "--out", reference.string()}).exit_code, 0);
  fs::create_directories(out);
  std::vector<fs::path> links;
  for (const long pid : next_pids())
    for (const auto& extension : kExtensions) {
      links.push_back(out / ("planar_nc2" + extension + ".tmp" + std::to_string(pid)));
      fs::create_symlink(victim, links.back());
    }
  const CommandResult r = generate({"--scene", kPlanarScene, "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_TRUE(test::read_text(victim) == "not to be overwritten\n") << victim << " was written through a link";
  for (const auto& link : links) ASSERT_TRUE(is_link(link)) << link;
  for (const auto& extension : kExtensions) EXPECT_FALSE(is_link(out / ("planar_nc2" + extension))) << extension;
  EXPECT_EQ(outputs(out, "planar_nc2"), outputs(reference, "planar_nc2"));
}

// New outputs get the permissions the umask gives any new file, not a temporary's 0600.
TEST(OutputFiles, OutputsHaveTheModeTheUmaskGives) {
  test::TempDir dir;
  for (const auto& [umask, mode] : std::vector<std::pair<std::string, fs::perms>>{
           {"022", fs::perms(0644)}, {"027", fs::perms(0640)}, {"077", fs::perms(0600)}}) {
    SCOPED_TRACE("umask " + umask);
    const fs::path out = dir.path() / umask;
    const CommandResult r = generate({"--urdf", kPlanarUrdf, "--out", out.string()}, "umask " + umask + " && ");
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    for (const auto& extension : kExtensions)
      EXPECT_EQ(fs::status(out / ("planar_rpr" + extension)).permissions(), mode) << extension;
  }
}

// ---- Existing outputs ---------------------------------------------------------------------------

// What stands at an output's name is read only when it is a regular file: a link to /dev/zero
// (an endless read), a FIFO (a read that waits for a writer forever) and a link to a file
// that holds exactly the output are all replaced by regular files, and the link's target is
// left as it was.
TEST(OutputFiles, AnExistingOutputIsComparedOnlyWhenARegularFile) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out", reference = dir.path() / "reference";
  ASSERT_EQ(generate({"--scene", kPlanarScene, "--out", reference.string()}).exit_code, 0);
  const auto expected = outputs(reference, "planar_nc2");
  fs::create_directories(out);
  fs::create_symlink("/dev/zero", out / "planar_nc2.hpp");
  ASSERT_EQ(::mkfifo((out / "planar_nc2.cpp").c_str(), 0644), 0);
  const std::string target = dir.write("elsewhere.cu", expected.at(".cu"));
  fs::create_symlink(target, out / "planar_nc2.cu");
  fs::create_symlink(dir.path() / "missing", out / "planar_nc2.cmake");
  const CommandResult r = generate({"--scene", kPlanarScene, "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << describe(r);  // 124: a read that never ended
  for (const auto& extension : kExtensions) {
    const fs::path path = out / ("planar_nc2" + extension);
    EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(path))) << path;
  }
  EXPECT_EQ(outputs(out, "planar_nc2"), expected);
  EXPECT_EQ(test::read_text(target), expected.at(".cu"));
  EXPECT_FALSE(fs::exists(dir.path() / "missing"));
  EXPECT_FALSE(has_temporaries(out));
}

// ---- Depfile ------------------------------------------------------------------------------------

// An edit that changes a number the generated code depends on (a comment would not: the outputs
// stay byte for byte, their time stamps too, and make, which has no restat, would run the rule again
// on every build): the scene's gravity, the URDF's first mass.
void change_scene(const std::string& path) {
  const std::string text = test::Pattern("gravity: [^\n]*\n").replace(test::read_text(path), "");
  static int edits = 0;
  std::ofstream(path, std::ios::trunc) << text << "gravity: [0, 0, -" << 9 + ++edits << "]\n";
}
void change_urdf(const std::string& path) {
  const std::string text = test::read_text(path);
  const std::size_t at = text.find("<mass value=\"") + 13;
  std::ofstream(path, std::ios::trunc) << text.substr(0, at) << "1" << text.substr(at);  // "5" becomes "15"
}

// A scene and its URDF whose paths hold ':', '\\' and a space, generated by a real make and a
// real Ninja build that read the depfile: each builds once, then has nothing to do, and builds
// again when either input changes.
TEST(OutputFiles, MakeAndNinjaReadTheDepfileAndRebuildOnAChange) {
  const auto has = [](const char* tool) { return test::run_command(std::string("command -v ") + tool).exit_code == 0; };
  test::TempDir dir;
  const fs::path inputs = dir.path() / "in puts";
  fs::create_directories(inputs);
  const std::string urdf = (inputs / "a\\b.urdf").string();
  fs::copy_file(kPlanarUrdf, urdf);
  const std::string scene = (inputs / "a:b.yaml").string();
  std::ofstream(scene) << "sweepgen_scene: 1\nsolver: planar\nurdf: '" << urdf << "'\ntip: tool\nscalars: [double]\n";
  const std::string command = test::shell_command({SWEEPGEN_EXECUTABLE, "generate", "--quiet", "--scene", scene, "--out",
                                                   "out", "--depfile", "out.d"}) +
                              " && echo run >> runs.log";

  const auto runs_after = [&](const std::string& build) {
    const CommandResult r = test::run_command("cd " + test::shell_quote(dir.path().string()) + " && " + build);
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    const fs::path log = dir.path() / "runs.log";
    const std::string text = fs::exists(log) ? test::read_text(log) : "";
    return std::count(text.begin(), text.end(), '\n');
  };
  const auto expect_rebuilds_on_a_change = [&](const std::string& build) {
    fs::remove(dir.path() / "runs.log");
    fs::remove_all(dir.path() / "out");
    EXPECT_EQ(runs_after(build), 1);
    EXPECT_EQ(runs_after(build), 1) << "rebuilt with nothing changed";
    change_scene(scene);
    EXPECT_EQ(runs_after(build), 2) << "not rebuilt after " << scene << " changed";
    EXPECT_EQ(runs_after(build), 2);
    change_urdf(urdf);
    EXPECT_EQ(runs_after(build), 3) << "not rebuilt after " << urdf << " changed";
    EXPECT_EQ(runs_after(build), 3);
  };
  if (has("make")) {
    SCOPED_TRACE("make");
    dir.write("Makefile", "out/planar.hpp:\n\t" + command + "\n-include out.d\n");
    expect_rebuilds_on_a_change("make -s");
    const std::string inputs_spelt = test::Pattern(" ").replace(inputs.string(), "\\ ");
    EXPECT_EQ(test::read_text(dir.path() / "out.d"),
              "out/planar.hpp: " + inputs_spelt + "/a\\:b.yaml " + inputs_spelt + "/a\\b.urdf\n");
  }
  if (has("ninja")) {
    SCOPED_TRACE("ninja");
    // restat: an output left unchanged keeps its time stamp, which Ninja then need not compare.
    dir.write("build.ninja", "rule generate\n  command = " + command +
                                 "\n  depfile = out.d\n  deps = gcc\n  restat = 1\nbuild out/planar.hpp: generate\n");
    expect_rebuilds_on_a_change("ninja --quiet >/dev/null");
  }
  if (!has("make") && !has("ninja")) GTEST_SKIP() << "neither make nor ninja installed";
}

// A backslash that make and Ninja would read differently (before a space, '#' or ':', or last)
// is refused, and nothing is written.
TEST(OutputFiles, APathTheDepfileCannotSpellIsRefused) {
  test::TempDir dir;
  for (const std::string name : {"x\\ y.urdf", "x\\:y.urdf", "x\\#y.urdf", "x\\"}) {
    SCOPED_TRACE(name);
    const std::string urdf = (dir.path() / name).string();
    fs::copy_file(kPlanarUrdf, urdf, fs::copy_options::overwrite_existing);
    const fs::path out = dir.path() / "out";
    const CommandResult r = generate({"--urdf", urdf, "--out", out.string(), "--depfile", (dir.path() / "x.d").string()});
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    EXPECT_NE(r.err.find("cannot be written to --depfile"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "planar_rpr.hpp"));
    EXPECT_FALSE(fs::exists(dir.path() / "x.d"));
  }
}

// ---- A set of outputs ---------------------------------------------------------------------------

// Which run wrote each of a set's files: 'A' or 'B' per extension, in kExtensions' order.
using Origins = std::string;

// One way to build a set in a folder (stem "set"): the files it reads (positions in
// kExtensions) and the compiler's command, -fsyntax-only.
struct SetBuild {
  std::vector<std::size_t> reads;
  std::vector<std::string> command;
};

// The three ways a set is built: the .cpp alone (a project's own build), the .cpp with the
// definition its .cmake gives it, and the .cu, as device code by clang with tests/device_code's
// stand-ins for CUDA's headers (as tests/device_code/check.sh checks it).
std::vector<SetBuild> set_builds(const fs::path& dir) {
  const std::string cmake = test::read_text(dir / "set.cmake");
  test::Match definition;
  EXPECT_TRUE(test::Pattern(R"(SWEEPGEN_OUTPUT_SET=([0-9a-fx]+ull))").search(cmake, definition)) << cmake;
  const std::string cpp = (dir / "set.cpp").string(), device_code = kSource + "/tests/device_code";
  return {{{0, 1}, {"c++", "-std=c++17", "-fsyntax-only", cpp}},
          {{0, 1, 3}, {"c++", "-std=c++17", "-fsyntax-only", "-DSWEEPGEN_OUTPUT_SET=" + definition[1], cpp}},
          {{0, 1, 2},
           {"clang++", "-x", "cuda", "--cuda-device-only", "--cuda-gpu-arch=sm_80", "-nocudainc", "-nocudalib",
            "-std=c++17", "-Wno-unknown-cuda-version", "-I", device_code + "/include", "-include",
            device_code + "/prelude.hpp", "-fsyntax-only", (dir / "set.cu").string()}}};
}

// Each way of building the set in `dir` succeeds exactly when the files it reads come from one
// run, and fails with the check's message otherwise.
void expect_builds_only_unmixed(const fs::path& dir, const Origins& origins) {
  for (const SetBuild& build : set_builds(dir)) {
    std::set<char> runs;
    for (std::size_t k : build.reads) runs.insert(origins[k]);
    const CommandResult r = test::run_command(test::shell_command(build.command));
    SCOPED_TRACE(test::shell_command(build.command));
    if (runs.size() == 1) {
      EXPECT_EQ(r.exit_code, 0) << r.err;
    } else {
      EXPECT_NE(r.exit_code, 0) << "a mixed set built";
      EXPECT_NE(r.err.find("come from different `sweepgen generate` runs"), std::string::npos) << r.err;
    }
  }
}

// Two runs A and B (the same solver and file stem, URDFs differing only in one mass, so that a
// mixed set would otherwise compile) into one --out, 100 times at once (10 in the sanitizer build,
// support/state_count.hpp: there 37 s with 100, 8.6 s with 10): every file is whole, one
// run's or the other's, and each way of building the set succeeds exactly when the files it reads
// come from one run. Mixed sets
// are also assembled on purpose, since concurrent runs rarely interleave their renames; each
// distinct set is compiled once.
TEST(OutputFiles, ASetMixedFromTwoRunsDoesNotBuild) {
  test::TempDir dir;
  const std::string urdf_a = dir.write("a.urdf", test::read_text(kPlanarUrdf));
  std::string heavier = test::read_text(kPlanarUrdf);
  heavier.replace(heavier.find("<mass value=\"5\"/>"), 17, "<mass value=\"6\"/>");
  const std::string urdf_b = dir.write("b.urdf", heavier);
  const fs::path out = dir.path() / "out";
  const auto args = [&](const std::string& urdf) {
    return std::vector<std::string>{SWEEPGEN_EXECUTABLE, "generate", "--quiet", "--urdf", urdf, "--solver", "planar",
                                    "--scalar", "double", "--file-stem", "set", "--out", out.string()};
  };
  std::map<char, std::map<std::string, std::string>> run;
  for (const auto& [name, urdf] : {std::pair{'A', urdf_a}, std::pair{'B', urdf_b}}) {
    ASSERT_EQ(test::run_command(test::shell_command(args(urdf))).exit_code, 0);
    run[name] = outputs(out, "set");
  }
  for (const auto& extension : kExtensions) ASSERT_NE(run['A'][extension], run['B'][extension]) << extension;

  std::set<Origins> checked;
  const auto check = [&](const Origins& origins) {
    if (!checked.insert(origins).second) return;
    SCOPED_TRACE("origins (hpp, cpp, cu, cmake) " + origins);
    const fs::path set = dir.path() / ("set_" + origins);
    fs::create_directories(set);
    for (std::size_t k = 0; k < kExtensions.size(); ++k)
      std::ofstream(set / ("set" + kExtensions[k])) << run[origins[k]][kExtensions[k]];
    expect_builds_only_unmixed(set, origins);
  };
  for (const char* origins : {"AAAA", "BAAA", "ABAA", "AABA", "AAAB"}) check(origins);

  const std::string pair = test::shell_command(args(urdf_a)) + " & " + test::shell_command(args(urdf_b)) + " & wait";
  for (int k = 0; k < test::state_count(100); ++k) {
    const CommandResult r = test::run_command(pair);
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    Origins origins;
    for (const auto& extension : kExtensions) {
      const std::string text = test::read_text(out / ("set" + extension));
      ASSERT_TRUE(text == run['A'][extension] || text == run['B'][extension]) << extension << " is neither run's";
      origins += text == run['A'][extension] ? 'A' : 'B';
    }
    check(origins);
  }
  EXPECT_FALSE(has_temporaries(out));
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

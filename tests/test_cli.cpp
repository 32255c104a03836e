// The sweepgen command line, run as a program: `solve` answers JSON lines in order and reports
// every unreadable line without stopping; `generate` writes byte-stable files atomically;
// `info` summarises a chain; exit codes as in README.md (0 ok, 1 bad input, 2 usage, 3 I/O).
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_command.hpp"
#include "support/one_joint_robot.hpp"
#include "support/temp_dir.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

namespace fs = std::filesystem;
using nlohmann::ordered_json;
using test::CommandResult;

const std::string kSource = SWEEPGEN_SOURCE_DIR;
const std::string kPanda = kSource + "/robots/panda/panda.urdf";
const std::string kPlanar = kSource + "/robots/planar/planar_rpr.urdf";
const std::string kUr5 = kSource + "/robots/ur5/ur5.urdf";

// Runs sweepgen with `args` (optionally in `cwd`), feeding `input` on standard input.
CommandResult sweepgen(const std::vector<std::string>& args, const std::string* input = nullptr,
                       const std::string& cwd = "") {
  std::vector<std::string> words{SWEEPGEN_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  std::string command = test::shell_command(words);
  if (!cwd.empty()) command = "cd " + test::shell_quote(cwd) + " && " + command;
  return test::run_command(command, input);
}

CommandResult sweepgen(const std::vector<std::string>& args, const std::string& input) { return sweepgen(args, &input); }

std::string describe(const CommandResult& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "\n--- stderr:\n" + r.err;
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' missing in:\n" << text;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}


// Every regular file under `dir` (recursively) by relative path, with its bytes.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  if (!fs::exists(dir)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.is_regular_file()) files[fs::relative(entry.path(), dir).string()] = test::read_text(entry.path());
  return files;
}

std::vector<std::string> names(const std::map<std::string, std::string>& files) {
  std::vector<std::string> result;
  for (const auto& [name, text] : files) result.push_back(name);
  return result;
}

bool has_temporaries(const fs::path& dir) {
  for (const auto& entry : fs::recursive_directory_iterator(dir))
    if (entry.path().filename().string().find(".tmp") != std::string::npos) return true;
  return false;
}

// ---- sweepgen solve ------------------------------------------------------------------------

const std::string kQ = R"("q": [0.1, -0.5, 0.2, -2.0, 0.1, 1.8, 0.6])";
const std::string kQd = R"("qd": [0.3, -0.2, 0.1, 0.4, -0.1, 0.2, 0.5])";
const std::string kState = kQ + ", " + kQd;

// Three valid problems with distinct answers.
const std::vector<std::string> kValid = {
    "{" + kState + "}",
    R"({"q": [0, -0.785, 0, -2.356, 0, 1.571, 0.785], "qd": [0, 0, 0, 0, 0, 0, 0], "tau_ff": [0, 1, 0, -1, 0, 0.5, 0],
        "alpha": [[0,0,0,0,0,1]], "beta": [9.81]})",
    "{" + kState + R"(, "f_ext": {"panda_hand": [0, 0, 0, 0, 0, -5]}, "alpha": [[0,0,0,1,0,0],[0,0,0,0,1,0]],
        "beta": [0.5, -0.5], "policy": "prioritize_external"})",
};

std::string join_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (auto line : lines) {
    // one problem per input line
    for (char& c : line)
      if (c == '\n') c = ' ';
    text += line + "\n";
  }
  return text;
}

std::vector<std::string> solve_lines(const std::vector<std::string>& input, CommandResult* result = nullptr,
                                     std::vector<std::string> extra_args = {}) {
  std::vector<std::string> args{"solve", "--urdf", kPanda};
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  CommandResult r = sweepgen(args, join_lines(input));
  if (result) *result = r;
  return lines_of(r.out);
}

TEST(CliSolve, ValidLinesAnswerOneObjectEachInOrder) {
  CommandResult r;
  const auto out = solve_lines(kValid, &r);
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  ASSERT_EQ(out.size(), kValid.size()) << describe(r);
  const std::vector<std::size_t> nc = {0, 1, 2};
  for (std::size_t k = 0; k < out.size(); ++k) {
    const ordered_json answer = ordered_json::parse(out[k]);
    std::vector<std::string> keys;
    for (const auto& [key, value] : answer.items()) keys.push_back(key);
    EXPECT_EQ(keys, (std::vector<std::string>{"qdd", "tau_ctrl", "tau_cmd", "nu", "xdd_tip", "status", "saturated_joints"}));
    for (const char* key : {"qdd", "tau_ctrl", "tau_cmd"}) EXPECT_EQ(answer[key].size(), 7u) << key;
    EXPECT_EQ(answer["nu"].size(), nc[k]);
    EXPECT_EQ(answer["xdd_tip"].size(), 6u);
    EXPECT_EQ(answer["status"], "ok");
    EXPECT_TRUE(answer["saturated_joints"].is_array() && answer["saturated_joints"].empty());
  }
  // The answers are in input order: the constrained lines meet their setpoints (alphaᵀ Ẍ_tip = beta).
  EXPECT_NEAR(ordered_json::parse(out[1])["xdd_tip"][5].get<double>(), 9.81, 1e-8);
  // prioritize_external keeps the constraint from reacting to the external force, so the
  // setpoints are met only under the original policy, which answers differently.
  std::string original = kValid[2];
  original.replace(original.find("prioritize_external"), std::string("prioritize_external").size(), "original");
  const auto original_out = solve_lines({original});
  ASSERT_EQ(original_out.size(), 1u);
  EXPECT_NEAR(ordered_json::parse(original_out[0])["xdd_tip"][3].get<double>(), 0.5, 1e-8);
  EXPECT_NEAR(ordered_json::parse(original_out[0])["xdd_tip"][4].get<double>(), -0.5, 1e-8);
  EXPECT_NE(original_out[0], out[2]);
  // Without drivers, tau_ctrl and tau_cmd are zero.
  const ordered_json bias_only = ordered_json::parse(out[0]);  // (the range-for must not iterate a temporary)
  for (const auto& t : bias_only["tau_cmd"]) EXPECT_EQ(t.get<double>(), 0.0);
}

// Constraint sets on any links, and a tree (--branch-tip): the dual Panda with a set on the left
// hand and one on the right elbow answers with each set's link acceleration, which meets its
// setpoints; on the Panda, a set listed on the tip answers as alpha and beta on the tip do.
TEST(CliSolve, ConstraintSetsOnATree) {
  const std::string q = "[0.1,-0.2,0.3,-0.4,0.5,-0.6,0.7,0.1,-0.2,0.3,-1.4,0.5,1.6,0.7,0.2]";
  const std::string line = R"({"q": )" + q + R"(, "qd": )" + q + R"(, "constraints": [
      {"link": "left_panda_hand", "alpha": [[0,0,0,1,0,0],[0,0,0,0,1,0]], "beta": [0.5, -0.5]},
      {"link": "right_panda_link4", "alpha": [[1,0,0,0,0,0]], "beta": [1]}]})";
  CommandResult r = sweepgen({"solve", "--urdf", kSource + "/robots/dual_panda/dual_panda.urdf", "--root", "station",
                              "--tip", "left_panda_hand", "--branch-tip", "right_panda_hand"},
                             join_lines({line}));
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const ordered_json answer = ordered_json::parse(lines_of(r.out).at(0));
  EXPECT_EQ(answer["status"], "ok");
  EXPECT_EQ(answer["qdd"].size(), 15u);
  EXPECT_EQ(answer["nu"].size(), 3u);
  // The setpoints are met to rounding of terms of order 10 (relative 1e-12 would do; 1e-9 leaves room).
  EXPECT_NEAR(answer["xdd_links"]["left_panda_hand"][3].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(answer["xdd_links"]["left_panda_hand"][4].get<double>(), -0.5, 1e-9);
  EXPECT_NEAR(answer["xdd_links"]["right_panda_link4"][0].get<double>(), 1.0, 1e-9);

  const std::string on_tip = "{" + kState + R"(, "alpha": [[0,0,0,1,0,0]], "beta": [0.5]})";
  const std::string as_set = "{" + kState + R"(, "constraints": [{"link": "panda_hand", "alpha": [[0,0,0,1,0,0]], "beta": [0.5]}]})";
  const auto out = solve_lines({on_tip, as_set});
  ASSERT_EQ(out.size(), 2u);
  const ordered_json a = ordered_json::parse(out[0]), b = ordered_json::parse(out[1]);
  for (const char* key : {"qdd", "tau_cmd", "nu", "xdd_tip"}) EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(b["xdd_links"]["panda_hand"], a["xdd_tip"]);
}

// A floating base (--floating-base, F5): the quadruped at rest, turned a quarter turn about x
// (world_R_base first in q), falls freely: its base accelerates by gravity in its own frame,
// R^T g = (0, -9.81, 0), and no joint moves (uniform gravity). A q whose first nine numbers are no
// rotation is refused by name.
TEST(CliSolve, FloatingBaseFallsFreely) {
  const std::vector<std::string> args = {"solve", "--urdf", kSource + "/robots/quadruped/quadruped.urdf", "--root", "trunk",
                                         "--tip", "FL_foot", "--branch-tip", "FR_foot", "--branch-tip", "RL_foot",
                                         "--branch-tip", "RR_foot", "--floating-base"};
  const std::string joints = "0.1,0.8,-1.5, -0.1,0.7,-1.4, 0.2,0.9,-1.6, -0.2,0.6,-1.3";
  const std::string qd = R"(, "qd": [0,0,0,0,0,0, 0,0,0,0,0,0,0,0,0,0,0,0]})";
  CommandResult r = sweepgen(args, join_lines({R"({"q": [1,0,0, 0,0,-1, 0,1,0, )" + joints + "]" + qd}));
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const ordered_json answer = ordered_json::parse(lines_of(r.out).at(0));
  EXPECT_EQ(answer["status"], "ok");
  ASSERT_EQ(answer["qdd"].size(), 18u);
  // Terms of order g (9.81) rounded in a few hundred operations: 1e-12 is ~500 eps g.
  const std::vector<double> expected = {0, 0, 0, 0, -9.81, 0};
  for (std::size_t i = 0; i < 18; ++i)
    EXPECT_NEAR(answer["qdd"][i].get<double>(), i < 6 ? expected[i] : 0.0, 1e-12) << "qdd[" << i << "]";

  r = sweepgen(args, join_lines({R"({"q": [1,0,0, 0,1,0, 0,0,2, )" + joints + "]" + qd}));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("key 'q': the first 9 numbers (world_R_base, row-major) are not a rotation matrix"),
            std::string::npos) << describe(r);
}

struct BadLine {
  const char* what;
  std::string line;
  std::vector<std::string> message_parts;  // besides the line number
};

const std::vector<BadLine> kBadLines = {
    {"wrong-length q", R"({"q": [0, 0], )" + kQd + "}", {"key 'q'", "expected 7 numbers, got 2"}},
    {"missing qd", "{" + kQ + "}", {"key 'qd'", "missing"}},
    {"non-number entry", R"({"q": [0.1, -0.5, "x", -2.0, 0.1, 1.8, 0.6], )" + kQd + "}", {"key 'q'", "entry 2 is not a number"}},
    {"non-number tau_ff", "{" + kState + R"(, "tau_ff": [0, 0, 0, null, 0, 0, 0]})", {"key 'tau_ff'", "not a number"}},
    {"unknown key", "{" + kState + R"(, "qq": 1})", {"key 'qq'", "unknown key", "did you mean 'q'"}},
    {"f_ext on an unknown link", "{" + kState + R"(, "f_ext": {"panda_hnd": [0, 0, 0, 0, 0, 1]}})",
     {"key 'f_ext.panda_hnd'", "not on the chain", "did you mean 'panda_hand'"}},
    {"f_ext on the base", "{" + kState + R"(, "f_ext": {"panda_link0": [0, 0, 0, 0, 0, 1]}})",
     {"key 'f_ext.panda_link0'", "fixed to the base"}},
    {"f_ext of wrong length", "{" + kState + R"(, "f_ext": {"panda_link3": [0, 0, 1]}})",
     {"key 'f_ext.panda_link3'", "expected 6 numbers"}},
    {"alpha without beta", "{" + kState + R"(, "alpha": [[0, 0, 0, 1, 0, 0]]})", {"key 'beta'", "missing"}},
    {"beta without alpha", "{" + kState + R"(, "beta": [1]})", {"key 'alpha'", "missing"}},
    {"beta of wrong length", "{" + kState + R"(, "alpha": [[0, 0, 0, 1, 0, 0]], "beta": [1, 2]})",
     {"key 'beta'", "expected 1 numbers, got 2"}},
    {"alpha direction of wrong length", "{" + kState + R"(, "alpha": [[0, 0, 0, 1, 0]], "beta": [1]})",
     {"key 'alpha[0]'", "expected 6 numbers"}},
    {"more than 6 alpha directions",
     "{" + kState + R"(, "alpha": [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1],[0,0,0,0,0,1]],
        "beta": [0, 0, 0, 0, 0, 0, 0]})",
     {"key 'alpha'", "0 to 6 directions"}},
    {"unknown policy", "{" + kState + R"(, "policy": "fastest"})", {"key 'policy'", "saturate_exact"}},
    {"constraint set on an unknown link",
     "{" + kState + R"(, "constraints": [{"link": "panda_lnk4", "alpha": [[1,0,0,0,0,0]], "beta": [0]}]})",
     {"key 'constraints[0].link'", "not on the chain", "did you mean 'panda_link4'"}},
    {"two constraint sets on one link",
     "{" + kState + R"(, "constraints": [{"link": "panda_link4", "alpha": [[1,0,0,0,0,0]], "beta": [0]},
        {"link": "panda_link4", "alpha": [[0,1,0,0,0,0]], "beta": [0]}]})",
     {"key 'constraints[1].link'", "a second set on 'panda_link4'"}},
    {"alpha and constraints",
     "{" + kState + R"(, "alpha": [[0,0,0,1,0,0]], "beta": [1], "constraints": [{"link": "panda_link4", "alpha": [[1,0,0,0,0,0]], "beta": [0]}]})",
     {"key 'constraints'", "not both"}},
    {"constraint sets that over-determine the robot",
     "{" + kState + R"(, "constraints": [{"link": "panda_link2", "alpha": [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0]], "beta": [0,0,0]}]})",
     {"key 'constraints'", "3 constraint directions on link 'panda_link2' but only 2 joints move them"}},
    {"invalid JSON", R"({"q": [0.1, -0.5,)", {"not valid JSON"}},
    {"a JSON array", "[1, 2, 3]", {"expected a JSON object"}},
    {"a JSON number", "42", {"expected a JSON object"}},
    // JSON has no NaN or Inf; a number beyond double's range is the closest a line can come.
    {"a number that overflows double", R"({"q": [1e999, -0.5, 0.2, -2.0, 0.1, 1.8, 0.6], )" + kQd + "}",
     {"number overflow", "1e999"}},
    // ... and one that underflows it, which would read as 0.
    {"a number that underflows double", R"({"q": [0.1, -0.5, 0.2, -2.0, 0.1, 1.8, 0.6], "qd": [0.3, 1E-400, 0, 0, 0, 0, 0]})",
     {"key 'qd[1]'", "1E-400 is too small for a double", "it would read as 0"}},
    // A key given twice would keep the last value.
    {"a key given twice", "{" + kState + R"(, "q": [0, 0, 0, 0, 0, 0, 0]})", {"key 'q'", "given twice in one object"}},
    {"a key given twice in a nested object",
     "{" + kState + R"(, "constraints": [{"link": "panda_link4", "alpha": [[1,0,0,0,0,0]], "beta": [0], "link": "panda_hand"}]})",
     {"key 'constraints[0].link'", "given twice in one object"}},
    // Answered like any other line, so that answers and lines pair one to one.
    {"a blank line", "", {"a blank line; each line is one problem"}},
    {"a line of white space", " \t ", {"a blank line; each line is one problem"}},
};

// A joint whose articulated inertia vanishes is locked (J1) and the status says so: a massless
// base set free (--floating-base) above a continuous joint about its z axis cannot turn about z
// (the link beyond turns freely), so the base's rz coordinate is locked, q̈ there is 0.
TEST(CliSolve, LockedJointIsReported) {
  test::TempDir dir;
  const std::string urdf = dir.write("massless_base.urdf", test::massless_base_turning_arm());
  const CommandResult r = sweepgen({"solve", "--urdf", urdf, "--floating-base"},
                                   join_lines({R"({"q": [1,0,0, 0,1,0, 0,0,1, 0.3], "qd": [0,0,0,0,0,0, 1]})"}));
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const ordered_json answer = ordered_json::parse(lines_of(r.out).at(0));
  EXPECT_EQ(answer["status"], "joint_inertia_singular") << r.out;
  EXPECT_EQ(answer["qdd"][2].get<double>(), 0.0) << r.out;
}

// Finite inputs whose results overflow: the line is answered, the non-finite values are null
// and the status says not_finite (README, "sweepgen solve"); a result, not an input error.
TEST(CliSolve, ResultsThatOverflowAreFlaggedNotFinite) {
  CommandResult r;
  const auto out = solve_lines({"{" + kState + R"(, "tau_ff": [1e308, -1e308, 1e308, 0, 0, 0, 0]})", kValid[0]}, &r);
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  ASSERT_EQ(out.size(), 2u) << describe(r);
  const ordered_json overflow = ordered_json::parse(out[0]);
  EXPECT_EQ(overflow["status"], "not_finite") << out[0];
  EXPECT_TRUE(std::any_of(overflow["qdd"].begin(), overflow["qdd"].end(), [](const auto& v) { return v.is_null(); }))
      << out[0];
  EXPECT_EQ(ordered_json::parse(out[1])["status"], "ok");
}

// Each bad line between valid ones: only that line is answered with an error, the valid lines
// still get their answers in order, and the exit code is 1.
TEST(CliSolve, EachBadLineIsReportedAloneAndTheOthersAreAnswered) {
  const auto reference = solve_lines(kValid);
  ASSERT_EQ(reference.size(), 3u);
  for (const auto& bad : kBadLines) {
    SCOPED_TRACE(bad.what);
    CommandResult r;
    const auto out = solve_lines({kValid[0], kValid[1], bad.line, kValid[2]}, &r);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    ASSERT_EQ(out.size(), 4u) << describe(r);
    EXPECT_EQ(out[0], reference[0]);
    EXPECT_EQ(out[1], reference[1]);
    EXPECT_EQ(out[3], reference[2]);
    const ordered_json error = ordered_json::parse(out[2]);
    ASSERT_TRUE(error.is_object());
    ASSERT_EQ(error.size(), 2u) << out[2];
    EXPECT_EQ(error.begin().key(), "line");  // {"line": N, "error": "..."} as documented
    EXPECT_EQ(error["line"], 3);
    const std::string message = error["error"];
    expect_contains(message, "<stdin>:3:");
    for (const auto& part : bad.message_parts) expect_contains(message, part);
    // The same message on standard error, and nothing else there.
    EXPECT_EQ(lines_of(r.err), std::vector<std::string>{"sweepgen: error: " + message});
  }
}

// All bad lines in one stream, valid lines between: one answer per input line, in order.
TEST(CliSolve, LineNumbersCountEveryInputLine) {
  std::vector<std::string> input;
  std::vector<int> expected_lines;  // for each output line: 0 = valid answer, else the error's line number
  for (std::size_t k = 0; k < kBadLines.size(); ++k) {
    input.push_back(kValid[k % 3]);
    expected_lines.push_back(0);
    input.push_back(kBadLines[k].line);
    expected_lines.push_back(static_cast<int>(input.size()));
  }
  input.push_back(kValid[2]);
  expected_lines.push_back(0);
  CommandResult r;
  const auto out = solve_lines(input, &r);
  EXPECT_EQ(r.exit_code, 1);
  ASSERT_EQ(out.size(), expected_lines.size()) << describe(r);
  EXPECT_EQ(lines_of(r.err).size(), kBadLines.size());
  for (std::size_t k = 0; k < out.size(); ++k) {
    const ordered_json answer = ordered_json::parse(out[k]);
    if (expected_lines[k] == 0) {
      EXPECT_TRUE(answer.contains("qdd")) << out[k];
    } else {
      EXPECT_EQ(answer["line"], expected_lines[k]) << out[k];
      expect_contains(answer["error"].get<std::string>(), "<stdin>:" + std::to_string(expected_lines[k]) + ":");
    }
  }
}

TEST(CliSolve, SaturationIsReportedWithTheSaturatedJoints) {
  const std::string demand = "{" + kState + R"(, "alpha": [[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0,0,0,1]], "beta": [1000, 1000, 1000])";
  CommandResult r;
  const auto out = solve_lines({demand + R"(, "policy": "saturate_exact"})", demand + R"(, "policy": "saturate"})",
                                demand + "}"},
                               &r);
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  ASSERT_EQ(out.size(), 3u) << describe(r);
  const std::vector<double> effort = {87, 87, 87, 87, 12, 12, 12};  // robots/panda/panda.urdf
  for (std::size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE(k == 0 ? "saturate_exact" : "saturate");
    const ordered_json answer = ordered_json::parse(out[k]);
    expect_contains(answer["status"].get<std::string>(), "saturated");
    ASSERT_FALSE(answer["saturated_joints"].empty());
    std::vector<bool> listed(7, false);
    for (const auto& joint : answer["saturated_joints"]) {
      const std::string name = joint;
      ASSERT_EQ(name.rfind("panda_joint", 0), 0u) << name;
      const int i = std::stoi(name.substr(11)) - 1;
      ASSERT_TRUE(i >= 0 && i < 7) << name;
      listed[i] = true;
    }
    // Saturated joints are exactly those whose clamped torque sits at the effort limit.
    const char* clamped = k == 0 ? "tau_cmd" : "tau_ctrl";
    for (std::size_t i = 0; i < 7; ++i) {
      const double t = answer[clamped][i];
      EXPECT_LE(std::abs(t), effort[i] * (1 + 1e-12)) << clamped << "[" << i << "]";
      if (listed[i]) {
        EXPECT_NEAR(std::abs(t), effort[i], 1e-9) << clamped << "[" << i << "]";
      }
    }
  }
  // Without a saturating policy the same demand is met exactly, unbounded.
  const ordered_json original = ordered_json::parse(out[2]);
  EXPECT_EQ(original["status"], "ok");
  EXPECT_TRUE(original["saturated_joints"].empty());
  EXPECT_NEAR(original["xdd_tip"][5].get<double>(), 1000, 1e-6);
}

TEST(CliSolve, InputFileWorksLikeStandardInput) {
  test::TempDir dir;
  const std::vector<std::string> input = {kValid[0], kBadLines[0].line, kValid[1]};
  const std::string file = dir.write("states.jsonl", join_lines(input));
  CommandResult from_stdin;
  const auto expected = solve_lines(input, &from_stdin);
  const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--input", file});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  const auto out = lines_of(r.out);
  ASSERT_EQ(out.size(), 3u) << describe(r);
  EXPECT_EQ(out[0], expected[0]);
  EXPECT_EQ(out[2], expected[2]);
  expect_contains(out[1], file + ":2:");  // errors name the input file
  expect_contains(r.err, file + ":2:");

  // "--input -" is standard input.
  const CommandResult dash = sweepgen({"solve", "--urdf", kPanda, "--input", "-"}, join_lines(input));
  EXPECT_EQ(dash.out, from_stdin.out);
  EXPECT_EQ(dash.exit_code, 1);

  // The bundled example runs cleanly.
  const CommandResult example = sweepgen({"solve", "--urdf", kPanda, "--input", kSource + "/robots/panda/example_states.jsonl"});
  EXPECT_EQ(example.exit_code, 0) << describe(example);
  EXPECT_FALSE(example.out.empty());
}

TEST(CliSolve, BadFilesAreBadInput) {
  test::TempDir dir;
  const std::string one = join_lines({kValid[0]});
  {
    const std::string missing = (dir.path() / "missing.jsonl").string();
    const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--input", missing});
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, missing);
    EXPECT_EQ(r.out, "");
  }
  {
    const std::string urdf = dir.write("broken.urdf", "<robot name='x'><link name='a'></robot");
    const CommandResult r = sweepgen({"solve", "--urdf", urdf}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, urdf);
    EXPECT_EQ(r.out, "");
  }
  {
    const std::string urdf = (dir.path() / "missing.urdf").string();
    const CommandResult r = sweepgen({"solve", "--urdf", urdf}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, urdf);
  }
  {
    const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--tip", "panda_hnd"}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, "did you mean 'panda_hand'");
  }
}

TEST(CliSolve, RotorInertiaEntriesAreChecked) {
  const std::string one = join_lines({kValid[0]});
  {
    const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--rotor-inertia", "panda_joint9=0.1"}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, "--rotor-inertia");
    expect_contains(r.err, "'panda_joint9'");
    expect_contains(r.err, "did you mean 'panda_joint");
    EXPECT_EQ(r.out, "");
  }
  for (const std::string entry : {"x", "j=abc", "=1", "panda_joint1=", "panda_joint1=1x"}) {
    SCOPED_TRACE(entry);
    const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--rotor-inertia", entry}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, "--rotor-inertia");
    expect_contains(r.err, "'" + entry + "'");
    EXPECT_EQ(r.out, "");
  }
  {
    const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--rotor-inertia", "panda_joint1=-1"}, one);
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, "panda_joint1");
  }
  // A valid entry is used: it changes the answer.
  const CommandResult plain = sweepgen({"solve", "--urdf", kPanda}, one);
  const CommandResult r = sweepgen({"solve", "--urdf", kPanda, "--rotor-inertia", "panda_joint1=0.5",
                                    "--rotor-inertia", "panda_joint7=0.1"},
                                   one);
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(lines_of(r.out).size(), 1u);
  EXPECT_NE(r.out, plain.out);
}

// ---- usage -----------------------------------------------------------------------------------

std::string project_version() {
  const std::string cmake = test::read_text(kSource + "/CMakeLists.txt");
  test::Match match;
  EXPECT_TRUE(test::Pattern(R"(project\(sweepgen VERSION ([0-9.]+))").search(cmake, match));
  return match.size() > 1 ? match[1] : "";
}

TEST(CliUsage, UsageErrorsExitWith2) {
  const std::vector<std::vector<std::string>> cases = {
      {},
      {"frobnicate"},
      {"solve", "--urdf", kPanda, "--bogus"},
      {"solve"},                                   // --urdf is required
      {"generate", "--out", "/nonexistent/out"},   // neither --scene nor --urdf
      {"info"},
      {"generate", "--urdf", kPlanar, "--scalar", "long double"},
      {"generate", "--urdf", kPlanar, "--expose", "some"},
  };
  for (const auto& args : cases) {
    SCOPED_TRACE(test::shell_command(args));
    const CommandResult r = sweepgen(args, "");
    EXPECT_EQ(r.exit_code, 2) << describe(r);
    expect_contains(r.err, "--help");
  }
  EXPECT_FALSE(fs::exists("/nonexistent/out"));
}

TEST(CliUsage, VersionAndHelp) {
  const CommandResult version = sweepgen({"--version"});
  EXPECT_EQ(version.exit_code, 0) << describe(version);
  EXPECT_EQ(version.out, "sweepgen " + project_version() + "\n");

  const CommandResult help = sweepgen({"--help"});
  EXPECT_EQ(help.exit_code, 0) << describe(help);
  for (const char* command : {"solve", "generate", "info"}) expect_contains(help.out, command);
  for (const char* command : {"solve", "generate", "info"}) {
    const CommandResult sub = sweepgen({command, "--help"});
    EXPECT_EQ(sub.exit_code, 0) << describe(sub);
    expect_contains(sub.out, "--urdf");
  }
}

// ---- sweepgen generate / info ----------------------------------------------------------------

const std::vector<std::string> kPlanarFiles = {"planar_rpr.cmake", "planar_rpr.cpp", "planar_rpr.cu", "planar_rpr.hpp"};

TEST(CliGenerate, DefaultSceneFilesAreNamedAfterTheUrdfAndByteStable) {
  test::TempDir dir;
  const fs::path a = dir.path() / "a", b = dir.path() / "nested" / "b";
  const CommandResult r = sweepgen({"generate", "--urdf", kPlanar, "--out", a.string()});
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.err, "");
  const auto first = snapshot(a);
  EXPECT_EQ(names(first), kPlanarFiles);
  for (const auto& name : kPlanarFiles) expect_contains(r.out, (a / name).string());
  expect_contains(first.at("planar_rpr.cpp"), "#include \"planar_rpr.hpp\"");
  expect_contains(first.at("planar_rpr.hpp"), "namespace planar_rpr");
  expect_contains(first.at("planar_rpr.cmake"), "/planar_rpr.cpp");
  // No path of this run leaks into the files.
  for (const auto& [name, text] : first) EXPECT_EQ(text.find(dir.path().string()), std::string::npos) << name;

  // Again into the same directory (replacing) and into a new one (created): identical bytes.
  const CommandResult again = sweepgen({"generate", "--urdf", kPlanar, "--out", a.string()});
  EXPECT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_EQ(snapshot(a), first);
  const CommandResult other = sweepgen({"generate", "--urdf", kPlanar, "--out", b.string()});
  EXPECT_EQ(other.exit_code, 0) << describe(other);
  EXPECT_EQ(snapshot(b), first);
  EXPECT_FALSE(has_temporaries(dir.path()));
}

// --floating-base (the scene key base: floating) for the default scene of a URDF and over a scene
// file: six base coordinates before the joints, q of nq = dof + 3 values (F5); info says so.
TEST(CliGenerate, FloatingBaseFlag) {
  test::TempDir dir;
  const CommandResult fixed = sweepgen({"generate", "--urdf", kPlanar, "--out", (dir.path() / "fixed").string()});
  ASSERT_EQ(fixed.exit_code, 0) << describe(fixed);
  expect_contains(snapshot(dir.path() / "fixed").at("planar_rpr.hpp"), "constexpr int dof = 3;");
  const CommandResult floating =
      sweepgen({"generate", "--urdf", kPlanar, "--floating-base", "--out", (dir.path() / "floating").string()});
  ASSERT_EQ(floating.exit_code, 0) << describe(floating);
  const std::string header = snapshot(dir.path() / "floating").at("planar_rpr.hpp");
  expect_contains(header, "constexpr int dof = 9;");
  expect_contains(header, "constexpr int nq = 12;  // values of q: world_R_base (9, row-major), then the joints'");
  const std::string scene = kSource + "/robots/panda/panda_nc0.yaml";
  const CommandResult over_scene =
      sweepgen({"generate", "--scene", scene, "--floating-base", "--out", (dir.path() / "scene").string()});
  ASSERT_EQ(over_scene.exit_code, 0) << describe(over_scene);
  expect_contains(snapshot(dir.path() / "scene").at("panda_nc0.hpp"), "constexpr int dof = 13;");
  const CommandResult info = sweepgen({"info", "--urdf", kPlanar, "--floating-base"});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  expect_contains(info.out, "1. floating_base_rx (floating-base coordinate");
}

// A URDF joint's <dynamics> (damping, friction) is not part of the model: info and generate say so
// by joint, with the values, instead of dropping it silently.
TEST(CliGenerate, UnmodelledJointDynamicsAreNoted) {
  test::TempDir dir;
  const std::string urdf = dir.write("damped.urdf", test::one_joint_robot(R"(<joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit effort="10" velocity="1" lower="-1" upper="1"/>
    <dynamics damping="0.5" friction="0.25"/></joint>)"));
  const std::string note =
      "sweepgen: note: joint 'shoulder': the URDF's <dynamics> (damping 0.5, friction 0.25) is not modelled; add the "
      "torques it stands for to tau_ff";
  const CommandResult info = sweepgen({"info", "--urdf", urdf});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  expect_contains(info.out, note);
  const CommandResult generate = sweepgen({"generate", "--urdf", urdf, "--out", (dir.path() / "out").string()});
  ASSERT_EQ(generate.exit_code, 0) << describe(generate);
  expect_contains(generate.out, note);
  // Without <dynamics>, no note.
  const CommandResult planar = sweepgen({"info", "--urdf", kPlanar});
  EXPECT_EQ(planar.out.find("<dynamics>"), std::string::npos) << planar.out;
}

// Constraint sets on two links: `info` and the generated header list each set with its link, its
// directions' numbers and where its α comes from.
TEST(CliGenerate, ConstraintSetsAreListed) {
  const std::string scene = kSource + "/robots/panda/panda_sets.yaml";
  test::TempDir dir;
  const CommandResult info = sweepgen({"info", "--scene", scene});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  const CommandResult generate = sweepgen({"generate", "--scene", scene, "--out", (dir.path() / "out").string()});
  ASSERT_EQ(generate.exit_code, 0) << describe(generate);
  const std::string header = snapshot(dir.path() / "out").at("panda_sets.hpp");
  for (const std::string& text : {info.out, header}) {
    expect_contains(text, "set 0 on link panda_link4: direction 0 (nu, beta), link acceleration set_acceleration[0..5]; "
                          "alpha[0] at run time");
    expect_contains(text, "set 1 on link panda_hand: directions 1..3 (nu, beta), link acceleration "
                          "set_acceleration[6..11]; fixed alpha [0, 0, 0, 1, 0, 0] [0, 0, 0, 0, 1, 0] [0, 0, 0, 0, 0, 1]");
  }
  expect_contains(header, "Scalar set_acceleration[12];");
}

// A URDF with side branches (tests/data/side_branches.urdf): `info` and the generated header
// list every lumped, locked and left-out link with its mass; `generate` says which joints it
// locked at a default position.
TEST(CliGenerate, LumpedLockedAndLeftOutLinksAreListed) {
  const std::string urdf = kSource + "/tests/data/side_branches.urdf";
  test::TempDir dir;
  const std::string scene = dir.write("side.yaml", "sweepgen_scene: 1\nsolver: side\nurdf: " + urdf +
                                                       "\nroot: base\ntip: wrist\nlocked_joints: {side_joint: 0.7}\n");
  const CommandResult info = sweepgen({"info", "--scene", scene});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  const CommandResult generate = sweepgen({"generate", "--scene", scene, "--out", (dir.path() / "out").string()});
  ASSERT_EQ(generate.exit_code, 0) << describe(generate);
  const std::string header = snapshot(dir.path() / "out").at("side.hpp");
  for (const std::string& text : {info.out, header}) {
    expect_contains(text, "body 2 (joint j2): 4.1 kg = link2 2.5 kg + lumped side_arm 1.2 kg behind locked joint side_joint, "
                          "side_tool 0.4 kg behind locked joint side_joint");
    expect_contains(text, "locked joint side_joint at 0.7 (scene), carried by link2");
    expect_contains(text, "locked joint finger_left_joint at 0.005 (default), carried by wrist");
    expect_contains(text, "left out pedestal 2 kg: carried by the fixed base");
  }
  expect_contains(generate.out, "note: joint 'finger_right_joint' off the chain is locked at 0.005");
  EXPECT_EQ(generate.out.find("note: joint 'side_joint'"), std::string::npos) << generate.out;
}

TEST(CliGenerate, AFailedRunLeavesTheOutputUntouched) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", out.string()}).exit_code, 0);
  const auto before = snapshot(out);
  ASSERT_EQ(before.size(), 4u);

  const std::string bad_tip = dir.write("bad_tip.yaml", "sweepgen_scene: 1\nsolver: planar_rpr\nurdf: " + kPlanar +
                                                            "\ntip: tol\n");
  const std::string bad_yaml = dir.write("bad_yaml.yaml", "sweepgen_scene: 1\nsolver: planar_rpr\nurdf: [" + kPlanar + "\n");
  const std::string bad_key = dir.write("bad_key.yaml", "sweepgen_scene: 1\nsolver: planar_rpr\nurdf: " + kPlanar +
                                                            "\npolicy: [original]\n");
  for (const std::string& scene : {bad_tip, bad_yaml, bad_key}) {
    SCOPED_TRACE(scene);
    const CommandResult r = sweepgen({"generate", "--scene", scene, "--out", out.string()});
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    EXPECT_TRUE(test::Pattern(test::Pattern(R"([.^$|()\[\]{}*+?\\])").replace(scene, R"(\$&)") + ":[0-9]+:[0-9]+: ")
                    .search(r.err))
        << "no file:line:column in: " << r.err;
    EXPECT_EQ(snapshot(out), before);
    EXPECT_FALSE(has_temporaries(out));
  }
  const CommandResult tip = sweepgen({"generate", "--scene", bad_tip, "--out", out.string()});
  expect_contains(tip.err, bad_tip + ":4:6: tip:");

  // A failure while writing (the depfile cannot be created) replaces none of the files either.
  const std::string unwritable_depfile = (dir.path() / "missing-dir" / "x.d").string();
  const CommandResult r = sweepgen({"generate", "--urdf", kPlanar, "--solver", "renamed", "--file-stem", "planar_rpr",
                                    "--out", out.string(), "--depfile", unwritable_depfile});
  EXPECT_EQ(r.exit_code, 3) << describe(r);
  expect_contains(r.err, unwritable_depfile);
  EXPECT_EQ(snapshot(out), before);
  EXPECT_FALSE(has_temporaries(out));
}

// --solver takes what the scene's `solver` takes, qualified names too, and the files are named
// one to one after it: "a::b" and "a_b" write files of their own.
TEST(CliGenerate, SolverNamesTheFilesOneToOne) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  for (const std::string solver : {"a::b", "a_b"}) {
    const CommandResult r = sweepgen({"generate", "--urdf", kPlanar, "--solver", solver, "--out", out.string()});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
  }
  EXPECT_EQ(names(snapshot(out)), (std::vector<std::string>{"a__b.cmake", "a__b.cpp", "a__b.cu", "a__b.hpp", "a_b.cmake",
                                                            "a_b.cpp", "a_b.cu", "a_b.hpp"}));
  expect_contains(test::read_text(out / "a__b.hpp"), "namespace a::b {");
  const CommandResult macro = sweepgen({"generate", "--urdf", kPlanar, "--solver", "arm::M_PI", "--out", out.string()});
  EXPECT_EQ(macro.exit_code, 1) << describe(macro);
  expect_contains(macro.err, "--solver: solver: 'arm::M_PI' is not a C++ namespace name: 'M_PI' is a macro");
}

// A full disk, simulated by a file-size limit (ulimit -f, 512-byte blocks in sh) smaller than
// the generated source: the write fails part-way, and the previous output stays as it was.
TEST(CliGenerate, AFullDiskLeavesTheOutputUntouched) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPanda, "--out", out.string()}).exit_code, 0);
  const auto before = snapshot(out);
  ASSERT_EQ(before.size(), 4u);
  const std::string command =
      "ulimit -f 16 && " + test::shell_command({SWEEPGEN_EXECUTABLE, "generate", "--urdf", kPanda, "--solver",
                                                 "renamed", "--file-stem", "panda", "--out", out.string()});
  const CommandResult r = test::run_command(command);
  EXPECT_EQ(r.exit_code, 3) << describe(r);
  expect_contains(r.err, "cannot write");
  expect_contains(r.err, (out / "panda").string());
  EXPECT_EQ(snapshot(out), before);
  EXPECT_FALSE(has_temporaries(out));
}

TEST(CliGenerate, AnUnwritableOutputDirectoryIsAnIoError) {
  test::TempDir dir;
  const std::string file = dir.write("file.txt", "not a directory");
  const auto before = snapshot(dir.path());
  std::vector<std::string> outs = {file, (fs::path(file) / "sub").string()};
  if (fs::is_directory("/proc")) outs.push_back("/proc/sweepgen-test-out");
  for (const auto& out : outs) {
    SCOPED_TRACE(out);
    const CommandResult r = sweepgen({"generate", "--urdf", kPlanar, "--out", out});
    EXPECT_EQ(r.exit_code, 3) << describe(r);
    expect_contains(r.err, out);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(snapshot(dir.path()), before);
  }
  EXPECT_FALSE(fs::exists("/proc/sweepgen-test-out"));
}

TEST(CliGenerate, DepfileListsTheSceneAndUrdfAbsolute) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  const std::string depfile = (dir.path() / "planar.d").string();
  // Relative scene path, run from the source tree: the depfile still lists absolute paths.
  const CommandResult r = sweepgen(
      {"generate", "--scene", "robots/planar/planar_nc2.yaml", "--out", out.string(), "--depfile", depfile}, nullptr, kSource);
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(names(snapshot(out)),
            (std::vector<std::string>{"planar_nc2.cmake", "planar_nc2.cpp", "planar_nc2.cu", "planar_nc2.hpp"}));
  const std::string text = test::read_text(depfile);
  const auto lines = lines_of(text);
  ASSERT_EQ(lines.size(), 1u) << text;
  const auto colon = lines[0].find(": ");
  ASSERT_NE(colon, std::string::npos) << text;
  EXPECT_EQ(lines[0].substr(0, colon), (out / "planar_nc2.hpp").string());
  std::istringstream rest(lines[0].substr(colon + 2));
  std::vector<std::string> deps;
  for (std::string dep; rest >> dep;) deps.push_back(dep);
  ASSERT_EQ(deps.size(), 2u) << text;
  EXPECT_TRUE(fs::path(deps[0]).is_absolute()) << deps[0];
  EXPECT_TRUE(fs::path(deps[1]).is_absolute()) << deps[1];
  EXPECT_TRUE(fs::equivalent(deps[0], kSource + "/robots/planar/planar_nc2.yaml")) << deps[0];
  EXPECT_TRUE(fs::equivalent(deps[1], kPlanar)) << deps[1];

  // Without a scene file only the URDF is listed.
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", out.string(), "--depfile", depfile}).exit_code, 0);
  EXPECT_EQ(test::read_text(depfile), (out / "planar_rpr.hpp").string() + ": " + fs::absolute(kPlanar).string() + "\n");
}

TEST(CliGenerate, FileStemNamesTheFilesAndTheirReferences) {
  test::TempDir dir;
  const fs::path plain = dir.path() / "plain", stem = dir.path() / "stem";
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", plain.string()}).exit_code, 0);
  const CommandResult r = sweepgen({"generate", "--urdf", kPlanar, "--out", stem.string(), "--file-stem", "mystem"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const auto files = snapshot(stem), reference = snapshot(plain);
  ASSERT_EQ(names(files), (std::vector<std::string>{"mystem.cmake", "mystem.cpp", "mystem.cu", "mystem.hpp"}));
  EXPECT_EQ(files.at("mystem.hpp"), reference.at("planar_rpr.hpp"));
  expect_contains(files.at("mystem.cpp"), "#include \"mystem.hpp\"");
  EXPECT_EQ(files.at("mystem.cpp").find("planar_rpr.hpp"), std::string::npos);
  expect_contains(files.at("mystem.cpp"), "namespace planar_rpr");  // the namespace is unchanged
  expect_contains(files.at("mystem.cu"), "#include \"mystem.cpp\"");
  EXPECT_EQ(files.at("mystem.cu").find("planar_rpr.cpp"), std::string::npos);
  expect_contains(files.at("mystem.cmake"), "${CMAKE_CURRENT_LIST_DIR}/mystem.cpp");
  EXPECT_EQ(files.at("mystem.cmake").find("planar_rpr.cpp"), std::string::npos);
}

TEST(CliGenerate, SceneAndFlagNameTyposGetHints) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  const std::string scene = dir.write("typo.yaml", "sweepgen_scene: 1\nsolver: planar_typo\nurdf: " + kPlanar +
                                                       "\ntip: tol\ndrivers:\n  external_forces:\n    - {name: load, link: tool}\n");
  const CommandResult r = sweepgen({"generate", "--scene", scene, "--out", out.string()});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  expect_contains(r.err, scene + ":4:6");
  expect_contains(r.err, "'tol'");
  expect_contains(r.err, "did you mean 'tool'");
  EXPECT_FALSE(fs::exists(out / "planar_typo.hpp"));

  const std::string link = dir.write("link.yaml", "sweepgen_scene: 1\nsolver: planar_typo\nurdf: " + kPlanar +
                                                      "\ntip: tool\ndrivers:\n  external_forces:\n    - {name: load, link: tol}\n");
  const CommandResult l = sweepgen({"generate", "--scene", link, "--out", out.string()});
  EXPECT_EQ(l.exit_code, 1) << describe(l);
  expect_contains(l.err, link + ":7:");
  expect_contains(l.err, "did you mean 'tool'");

  const CommandResult flag = sweepgen({"generate", "--urdf", kPlanar, "--tip", "tol", "--out", out.string()});
  EXPECT_EQ(flag.exit_code, 1) << describe(flag);
  expect_contains(flag.err, "--tip");
  expect_contains(flag.err, "did you mean 'tool'");
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliInfo, ListsTheJointsAndOperationCounts) {
  const CommandResult r = sweepgen({"info", "--urdf", kUr5});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  expect_contains(r.out, "6 moving joints");
  int index = 0;
  for (const char* joint : {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint", "wrist_2_joint",
                            "wrist_3_joint"})
    expect_contains(r.out, std::to_string(++index) + ". " + joint + " (revolute");
  expect_contains(r.out, "operation counts");
  for (const char* function : {"outward:", "decompose:", "full solve_original:", "full solve_saturate_exact:"})
    expect_contains(r.out, function);
  EXPECT_TRUE(test::Pattern(R"(full solve_original: add [0-9]+, mul [0-9]+.*\(total [1-9][0-9]*\))").search(r.out))
      << r.out;

  // A scene file works too; a bad URDF is bad input.
  const CommandResult scene = sweepgen({"info", "--scene", kSource + "/robots/planar/planar_nc2.yaml"});
  EXPECT_EQ(scene.exit_code, 0) << describe(scene);
  expect_contains(scene.out, "3 moving joints");
  expect_contains(scene.out, "solver planar_nc2");
  // A derivative scene names the Jacobians it returns and those it leaves out.
  const CommandResult derivatives =
      sweepgen({"info", "--scene", kSource + "/robots/panda/panda_lean_nc6_fixed_derivatives.yaml"});
  EXPECT_EQ(derivatives.exit_code, 0) << describe(derivatives);
  expect_contains(derivatives.out, "Derivatives: derivatives_<policy> return the Jacobians of qdd, nu (scene: "
                                   "derivatives); not computed: tau_cmd");
  const CommandResult missing = sweepgen({"info", "--urdf", "/nonexistent/robot.urdf"});
  EXPECT_EQ(missing.exit_code, 1) << describe(missing);
  expect_contains(missing.err, "/nonexistent/robot.urdf");
}

// --branch-tip names a tree's further tips for info and generate as for solve (without a scene
// file, a tree's joint order can be listed): the mobile Panda with Franka's two fingers, whose
// second finger is a <mimic> of the first, each a joint of its own and said so.
TEST(CliInfo, BranchTipListsATreeAndItsMimicJoints) {
  const std::string urdf = kSource + "/robots/mobile_panda_gripper/mobile_panda_gripper.urdf";
  const CommandResult r = sweepgen({"info", "--urdf", urdf, "--root", "mobile_base", "--tip", "panda_leftfinger",
                                    "--branch-tip", "panda_rightfinger", "--floating-base"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  expect_contains(r.out, "tree mobile_base -> panda_leftfinger, panda_rightfinger in " + urdf + ": 15 moving joints");
  expect_contains(r.out, "14. panda_finger_joint1 (prismatic");
  expect_contains(r.out, "15. panda_finger_joint2 (prismatic");
  expect_contains(r.out, "rotor inertia 0, a <mimic> of 'panda_finger_joint1' (see the notes)\n");
  expect_contains(r.out, "sweepgen: note: joint 'panda_finger_joint2' is a <mimic> of 'panda_finger_joint1' (q = 1 "
                         "q_source + 0): here it is a joint of its own, joint 15 of the chain");
  // Without the branch tip the right finger is off the chain: locked, and still said to be a mimic.
  const CommandResult chain = sweepgen({"info", "--urdf", urdf, "--root", "mobile_base", "--tip", "panda_leftfinger"});
  ASSERT_EQ(chain.exit_code, 0) << describe(chain);
  expect_contains(chain.out, "chain mobile_base -> panda_leftfinger");
  expect_contains(chain.out, "here it is locked at 0 (default); the coupling is not modelled");
}

// The quarter-turn rule is said by info, generate and the header, origin by origin; the flag
// --no-snap-quarter-turns (scene key snap_quarter_turns: false) takes the URDF literally.
TEST(CliGenerate, QuarterTurnsAreSaidAndCanBeTurnedOff) {
  test::TempDir dir;
  const std::string urdf = dir.write("tilted.urdf", test::one_joint_robot(R"(<joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0 0 0.1" rpy="1.57079632679 0 0"/><axis xyz="0 0 1"/>
    <limit effort="10" velocity="1" lower="-1" upper="1"/></joint>)"));
  const std::string note = "joint 'shoulder' <origin>: rpy '1.57079632679 0 0' taken as (pi/2, 0, 0) (changed by 4.89";
  const CommandResult info = sweepgen({"info", "--urdf", urdf});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  expect_contains(info.out, "sweepgen: note: " + note);
  const CommandResult generate = sweepgen({"generate", "--urdf", urdf, "--out", (dir.path() / "snapped").string()});
  ASSERT_EQ(generate.exit_code, 0) << describe(generate);
  expect_contains(generate.out, "sweepgen: note: " + note);
  const std::string snapped = snapshot(dir.path() / "snapped").at("tilted.hpp");
  expect_contains(snapped, "//   " + note);

  const std::string scene = dir.write("literal.yaml", "sweepgen_scene: 1\nsolver: tilted\nurdf: " + urdf +
                                                          "\nsnap_quarter_turns: false\n");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--urdf", urdf, "--no-snap-quarter-turns"}, std::vector<std::string>{"--scene", scene}}) {
    std::vector<std::string> command{"info"};
    command.insert(command.end(), args.begin(), args.end());
    const CommandResult literal_info = sweepgen(command);
    ASSERT_EQ(literal_info.exit_code, 0) << describe(literal_info);
    EXPECT_EQ(literal_info.out.find("quarter"), std::string::npos) << literal_info.out;
    EXPECT_EQ(literal_info.out.find("<origin>"), std::string::npos) << literal_info.out;
  }
  const CommandResult literal = sweepgen(
      {"generate", "--urdf", urdf, "--no-snap-quarter-turns", "--out", (dir.path() / "literal").string()});
  ASSERT_EQ(literal.exit_code, 0) << describe(literal);
  EXPECT_EQ(snapshot(dir.path() / "literal").at("tilted.hpp").find("<origin>"), std::string::npos);
  // cos(1.57079632679) = 4.9e-12 (to the quaternion's rounding, 1e-16) stays in the code as a
  // constant, alone or folded with g (9.81 x 4.8966e-12 = 4.8036e-11); snapped, it folds away.
  const test::Pattern cosine("4\\.8966[0-9]*e-12|4\\.8036[0-9]*e-11");
  EXPECT_TRUE(cosine.search(snapshot(dir.path() / "literal").at("tilted.cpp")))
      << "the literal rotation's cosine is not in the code";
  EXPECT_FALSE(cosine.search(snapshot(dir.path() / "snapped").at("tilted.cpp")));

  // solve takes the flag too: the two models' answers differ by about the rotation's change.
  const std::string line = R"({"q": [0.3], "qd": [0.2]})" "\n";
  const CommandResult solve_snapped = sweepgen({"solve", "--urdf", urdf}, line);
  const CommandResult solve_literal = sweepgen({"solve", "--urdf", urdf, "--no-snap-quarter-turns"}, line);
  ASSERT_EQ(solve_snapped.exit_code, 0) << describe(solve_snapped);
  ASSERT_EQ(solve_literal.exit_code, 0) << describe(solve_literal);
  EXPECT_NE(solve_snapped.out, solve_literal.out);
}

// ---- What a message tells the user to change -------------------------------------------------

// A vendor's URDF with two frames at the flange (ee_link and tool0, both fixed to the last link):
// there is no default tip. Each command says how to name one with its own flag, in its own words.
TEST(CliMessages, NoDefaultTipNamesTheFlagOfTheCommandRun) {
  test::TempDir dir;
  const std::string urdf = dir.write("flange.urdf", test::one_joint_robot(R"(<joint name="shoulder" type="revolute">
    <parent link="base"/><child link="arm"/><axis xyz="0 0 1"/><limit effort="10" velocity="1" lower="-1" upper="1"/></joint>
  <link name="ee_link"/><link name="tool0"/>
  <joint name="to_ee" type="continuous"><parent link="arm"/><child link="ee_link"/></joint>
  <joint name="to_tool" type="continuous"><parent link="arm"/><child link="tool0"/></joint>)"));
  const std::string scene = dir.write("no_tip.yaml", "sweepgen_scene: 1\nsolver: flange\nurdf: " + urdf + "\n");
  const std::string tree = "link 'arm': the tree branches here (children 'ee_link', 'tool0', 2 of them with moving joints below)";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"info", "--urdf", urdf}, "name the tip link: sweepgen info --urdf " + urdf + " --tip LINK"},
      {{"generate", "--urdf", urdf, "--out", (dir.path() / "out").string()},
       "name the tip link: sweepgen generate --urdf " + urdf + " --tip LINK"},
      {{"solve", "--urdf", urdf}, "name the tip link: sweepgen solve --urdf " + urdf + " --tip LINK"},
      {{"info", "--scene", scene}, "name the tip link: the scene key 'tip'"},
  };
  for (const auto& [args, advice] : cases) {
    SCOPED_TRACE(test::shell_command(args));
    const CommandResult r = sweepgen(args, "");
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    expect_contains(r.err, tree);
    expect_contains(r.err, advice);
    for (const char* other : {"sweepgen solve", "sweepgen info", "sweepgen generate"}) {
      if (advice.find(other) == std::string::npos) {
        EXPECT_EQ(r.err.find(other), std::string::npos) << r.err;
      }
    }
  }
}

// An XML syntax error is reported at its line and column (urdfdom's own message has neither).
TEST(CliMessages, UrdfSyntaxErrorsHaveLineAndColumn) {
  test::TempDir dir;
  const std::string urdf = dir.write("broken.urdf", "<robot name=\"r\">\n  <link name=\"a\"/>\n  <link name=\"b\">\n"
                                                    "  </lnk>\n</robot>\n");
  const CommandResult r = sweepgen({"info", "--urdf", urdf});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  expect_contains(r.err, urdf + ":3:3: <link>: not well-formed: this element has no end tag (</lnk> at 4:3 comes first)");
}

// --quiet: nothing on standard output, the same files; warnings still said (on standard error).
TEST(CliMessages, GenerateQuietPrintsOnlyWarnings) {
  test::TempDir dir;
  const CommandResult loud = sweepgen({"generate", "--urdf", kPanda, "--out", (dir.path() / "loud").string()});
  ASSERT_EQ(loud.exit_code, 0) << describe(loud);
  expect_contains(loud.out, "sweepgen: note: ");
  const CommandResult quiet = sweepgen({"generate", "--quiet", "--urdf", kPanda, "--out", (dir.path() / "quiet").string()});
  ASSERT_EQ(quiet.exit_code, 0) << describe(quiet);
  EXPECT_EQ(quiet.out, "");
  EXPECT_EQ(quiet.err, "");
  EXPECT_EQ(snapshot(dir.path() / "quiet"), snapshot(dir.path() / "loud"));
}

// Two constraint sets on one rigid body (the fingers of a gripper that is not on a tip's path are
// locked, so both ride on the hand's body): generate and info warn, naming both sets and the body.
TEST(CliMessages, SetsOnOneRigidBodyAreWarnedAbout) {
  test::TempDir dir;
  const std::string urdf = kSource + "/robots/mobile_panda_gripper/mobile_panda_gripper.urdf";
  const std::string scene = dir.write("fingers.yaml", "sweepgen_scene: 1\nsolver: fingers\nurdf: " + urdf +
                                                          "\ntip: panda_hand\ndrivers:\n  constraints:\n"
                                                          "    - {link: panda_leftfinger, count: 3}\n"
                                                          "    - {link: panda_rightfinger, count: 3}\n");
  const std::string warning = "sweepgen: warning: " + scene + ": constraint sets act on one rigid body: set 0 on "
                              "'panda_leftfinger', set 1 on 'panda_rightfinger' are all carried by the body of link "
                              "'panda_link7'";
  for (const std::vector<std::string>& args : {std::vector<std::string>{"info", "--scene", scene},
                                               {"generate", "--quiet", "--scene", scene, "--out", dir.path().string()}}) {
    const CommandResult r = sweepgen(args);
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    expect_contains(r.err, warning);
    expect_contains(r.err, "status_constraint_rank_deficient");
  }
  // The bundled grasp puts the two sets on the tips of a tree: separate bodies, no warning.
  const CommandResult grasp = sweepgen({"info", "--scene", kSource + "/robots/mobile_panda_gripper/mobile_panda_grasp.yaml"});
  EXPECT_EQ(grasp.exit_code, 0) << describe(grasp);
  EXPECT_EQ(grasp.err.find("warning"), std::string::npos) << grasp.err;
}

// An output that comes out the same is not rewritten: its time stamp stays, so a build that
// regenerates after a touch of the URDF recompiles nothing. A changed file is replaced.
TEST(CliGenerate, UnchangedOutputIsLeftUntouched) {
  test::TempDir dir;
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", out.string()}).exit_code, 0);
  const auto an_hour_ago = fs::file_time_type::clock::now() - std::chrono::hours(1);
  for (const std::string& name : kPlanarFiles) fs::last_write_time(out / name, an_hour_ago);
  std::ofstream(out / "planar_rpr.cmake", std::ios::app) << "# edited\n";
  const auto edited = fs::last_write_time(out / "planar_rpr.cmake");
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", out.string()}).exit_code, 0);
  EXPECT_EQ(fs::last_write_time(out / "planar_rpr.hpp"), an_hour_ago);
  EXPECT_EQ(fs::last_write_time(out / "planar_rpr.cpp"), an_hour_ago);
  EXPECT_EQ(test::read_text(out / "planar_rpr.cmake").find("# edited"), std::string::npos);
  EXPECT_GE(fs::last_write_time(out / "planar_rpr.cmake"), edited);
  EXPECT_FALSE(has_temporaries(dir.path()));
}


// ---- Each input read once --------------------------------------------------------------------

// `args` run while each of `pipes` (a named pipe made here, by path) is filled once from its
// source file by a writer of its own, as `--urdf <(cat r.urdf)` fills one: a second open of a
// pipe waits for a writer that never comes, so the command and each writer run under a timeout
// (the command's exit 124), and a regression fails instead of hanging.
CommandResult sweepgen_with_pipes(const std::vector<std::string>& args, const std::map<fs::path, std::string>& pipes) {
  std::string command;
  for (const auto& [pipe, source] : pipes)
    command += "mkfifo " + test::shell_quote(pipe.string()) + " && { timeout 60 sh -c " +
               test::shell_quote("cat " + test::shell_quote(source) + " > " + test::shell_quote(pipe.string())) +
               " >/dev/null 2>&1 & } && ";
  std::vector<std::string> words{"timeout", "60", SWEEPGEN_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  return test::run_command(command + test::shell_command(words));
}

// A URDF in a pipe: info, generate (the same files as from the file) and solve read it once. The
// URDF was read three times (the default scene's chain, the command's, the provenance hash).
TEST(CliInputs, AUrdfInAPipeIsReadOnce) {
  test::TempDir dir;
  const fs::path pipe = dir.path() / "planar_rpr.urdf";  // the name the files are named after
  const CommandResult info = sweepgen_with_pipes({"info", "--urdf", pipe.string()}, {{pipe, kPlanar}});
  EXPECT_EQ(info.exit_code, 0) << describe(info);
  expect_contains(info.out, "3 moving joints");
  fs::remove(pipe);

  const fs::path from_pipe = dir.path() / "from_pipe", from_file = dir.path() / "from_file";
  const CommandResult piped =
      sweepgen_with_pipes({"generate", "--urdf", pipe.string(), "--out", from_pipe.string()}, {{pipe, kPlanar}});
  EXPECT_EQ(piped.exit_code, 0) << describe(piped);
  fs::remove(pipe);
  ASSERT_EQ(sweepgen({"generate", "--urdf", kPlanar, "--out", from_file.string()}).exit_code, 0);
  EXPECT_EQ(snapshot(from_pipe), snapshot(from_file));

  const CommandResult solve = sweepgen_with_pipes({"solve", "--urdf", pipe.string(), "--tip", "tool", "--input",
                                                   dir.write("in.jsonl", "{\"q\": [0, 0, 0], \"qd\": [0, 0, 0]}\n")},
                                                  {{pipe, kPlanar}});
  EXPECT_EQ(solve.exit_code, 0) << describe(solve);
  expect_contains(solve.out, "\"qdd\"");
}

// A scene in a pipe naming a URDF in a pipe, with rotor inertias (whose names the scene reader
// checks on a chain loaded without them, before the chain with them): each read once. The scene
// was read twice (the reader, the provenance hash), the URDF three times.
TEST(CliInputs, ASceneInAPipeAndItsUrdfInAPipeAreReadOnce) {
  test::TempDir dir;
  const fs::path scene = dir.path() / "planar_nc2.yaml", urdf = dir.path() / "planar_rpr.urdf";
  const std::string scene_source = kSource + "/robots/planar/planar_nc2.yaml";
  const fs::path from_pipes = dir.path() / "from_pipes", from_files = dir.path() / "from_files";
  const CommandResult r = sweepgen_with_pipes({"generate", "--scene", scene.string(), "--out", from_pipes.string()},
                                              {{scene, scene_source}, {urdf, kPlanar}});
  EXPECT_EQ(r.exit_code, 0) << describe(r);
  ASSERT_EQ(sweepgen({"generate", "--scene", scene_source, "--out", from_files.string()}).exit_code, 0);
  EXPECT_EQ(snapshot(from_pipes), snapshot(from_files));
}

// ---- What the provenance line hashes ----------------------------------------------------------

// The header's first line hashes the model and scene as read, not the files' bytes: a comment or
// white space added to the URDF and the scene leaves every output byte as it was (a build
// recompiles nothing); one digit of a mass changes the line.
TEST(CliGenerate, EditsThatChangeNoNumberOrNameLeaveTheOutputAsItWas) {
  test::TempDir dir;
  const std::string urdf = test::read_text(kPlanar);
  const std::string scene = test::read_text(kSource + "/robots/planar/planar_nc2.yaml");
  const auto generate = [&](const std::string& name, const std::string& urdf_text, const std::string& scene_text) {
    fs::create_directories(dir.path() / name);
    std::ofstream(dir.path() / name / "planar_rpr.urdf", std::ios::binary) << urdf_text;
    std::ofstream(dir.path() / name / "planar_nc2.yaml", std::ios::binary) << scene_text;
    const fs::path out = dir.path() / name / "out";
    const CommandResult r = sweepgen({"generate", "--scene", (dir.path() / name / "planar_nc2.yaml").string(), "--out", out.string()});
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    return snapshot(out);
  };
  const auto as_read = generate("as_read", urdf, scene);
  ASSERT_EQ(names(as_read), (std::vector<std::string>{"planar_nc2.cmake", "planar_nc2.cpp", "planar_nc2.cu", "planar_nc2.hpp"}));

  const auto replaced = [](std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return text.replace(at, from.size(), to);
  };
  const std::string commented_urdf = replaced(replaced(urdf, "<mass value=\"5\"/>", "<mass   value = \"5\" />\n<!-- edited -->"),
                                              "</robot>", "\n\n</robot>\n<!-- the end -->");
  const std::string commented_scene =
      replaced(replaced(scene, "tip: tool", "tip:   tool   # the tool\n\n"), "gravity: [0, -9.81, 0]", "gravity: [ 0,-9.81,  0 ]");
  EXPECT_EQ(generate("commented", commented_urdf, commented_scene), as_read);

  const auto heavier = generate("heavier", replaced(urdf, "<mass value=\"5\"/>", "<mass value=\"6\"/>"), scene);
  const auto first_line = [](const std::string& text) { return text.substr(0, text.find('\n')); };
  EXPECT_NE(first_line(heavier.at("planar_nc2.hpp")), first_line(as_read.at("planar_nc2.hpp")));
  expect_contains(first_line(as_read.at("planar_nc2.hpp")), "of their numbers and names as read, not of the files' bytes");
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

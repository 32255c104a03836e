// `sweepgen solve --scene`: the scene's own problem (gravity, locked joints, rotor inertia, drivers
// by their names, fixed directions, policies, outputs), never a retyped approximation of it; chain
// flags beside a scene are a usage error. That its answers agree with every bundled scene's
// generated solver state by state is SolveSceneAgreesWithTheGeneratedSolver of
// tests/generated/scene_test.cpp.in.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"
#include "support/run_command.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using nlohmann::json;
using test::CommandResult;

const std::string kSource = SWEEPGEN_SOURCE_DIR;
const std::string kPlanarScene = kSource + "/robots/planar/planar_nc2.yaml";

CommandResult solve(const std::vector<std::string>& args, const std::string& input) {
  std::vector<std::string> words{SWEEPGEN_EXECUTABLE, "solve"};
  words.insert(words.end(), args.begin(), args.end());
  return test::run_command(test::shell_command(words), &input);
}

std::string describe(const CommandResult& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "\n--- stderr:\n" + r.err;
}

std::vector<json> answers(const CommandResult& r) {
  std::vector<json> lines;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) lines.push_back(json::parse(line));
  return lines;
}

// q̈ of the reference solver for the scene's chain and options on one named state.
std::vector<double> reference_qdd(const std::string& scene_path, const json& line) {
  const scene::Scene s = scene::load_scene(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  solver::ReferenceSolver<double> reference(chain, s.layout, s.solver_options());
  const auto vector = [&](const char* key) {
    const std::vector<double> v = line[key].get<std::vector<double>>();
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  solver::SolveInputs<double> in;
  in.q = vector("q");
  in.qd = vector("qd");
  in.torques = {vector("tau_ff")};
  const auto& solution = reference.run(in, solver::Policy::original);
  return std::vector<double>(solution.qdd.data(), solution.qdd.data() + solution.qdd.size());
}

// The UR5 in the README's first scene's gravity (along −y), and with its last joint locked at a
// position: what `solve --urdf` cannot state. Each answer is the reference solver's for the
// scene's chain and options, bit for bit, and differs from the problem the flags state.
TEST(SolveScene, SolvesTheScenesGravityAndLockedJoints) {
  test::TempDir dir;
  const std::string urdf = kSource + "/robots/ur5/ur5.urdf";
  const std::string head = "sweepgen_scene: 1\nsolver: ur5_scene\nurdf: " + urdf + "\ndrivers: {torques: [tau_ff]}\n";
  const std::string sideways = dir.write("sideways.yaml", head + "gravity: [0, -9.81, 0]\n");
  const std::string locked = dir.write("locked.yaml", head + "tip: wrist_1_link\nlocked_joints: {wrist_2_joint: 1.5}\n");
  const std::string six = R"({"q": [0.1, -0.7, 1.2, 0.3, -0.4, 0.5], "qd": [0.2, 0.1, -0.3, 0.4, 0, 0.1], "tau_ff": [1, 2, 3, 0, 0, 0]})";
  const std::string four = R"({"q": [0.1, -0.7, 1.2, 0.3], "qd": [0.2, 0.1, -0.3, 0.4], "tau_ff": [1, 2, 3, 0]})";

  const CommandResult r = solve({"--scene", sideways}, six + "\n");
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const std::vector<double> qdd = answers(r).at(0)["qdd"].get<std::vector<double>>();
  EXPECT_EQ(qdd, reference_qdd(sideways, json::parse(six)));
  const CommandResult plain = solve({"--urdf", urdf}, six + "\n");  // gravity along −z: another problem
  ASSERT_EQ(plain.exit_code, 0) << describe(plain);
  EXPECT_GT(std::abs(answers(plain).at(0)["qdd"][1].get<double>() - qdd[1]), 1.0);

  const CommandResult held = solve({"--scene", locked}, four + "\n");
  ASSERT_EQ(held.exit_code, 0) << describe(held);
  const std::vector<double> held_qdd = answers(held).at(0)["qdd"].get<std::vector<double>>();
  EXPECT_EQ(held_qdd, reference_qdd(locked, json::parse(four)));
  const CommandResult at_zero = solve({"--urdf", urdf, "--tip", "wrist_1_link"}, four + "\n");  // locked at 0
  ASSERT_EQ(at_zero.exit_code, 0) << describe(at_zero);
  EXPECT_NE(answers(at_zero).at(0)["qdd"].get<std::vector<double>>(), held_qdd);
}

// Named drivers and the flat input are the same problem; the answer lists only the scene's
// outputs beside "flat", the generated solver's out array.
TEST(SolveScene, NamedInputsEqualTheFlatInput) {
  const std::string named =
      R"({"q": [0.3, 0.2, -0.4], "qd": [0.1, -0.2, 0.3], "tau_ff": [0.5, -1, 0.25], "tool_load": [0, 0, 0.1, 1, -2, 0], "beta": [0.5, -0.5], "policy": "saturate"})";
  // planar_nc2's flat input: q (3), q̇ (3), τff (3), the tool load (6), β (2); its directions are fixed.
  const std::string flat =
      R"({"flat": [0.3, 0.2, -0.4, 0.1, -0.2, 0.3, 0.5, -1, 0.25, 0, 0, 0.1, 1, -2, 0, 0.5, -0.5], "policy": "saturate"})";
  const CommandResult r = solve({"--scene", kPlanarScene}, named + "\n" + flat + "\n");
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  const std::vector<json> a = answers(r);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0], a[1]);
  for (const char* key : {"qdd", "tau_cmd", "tau_ctrl", "nu", "xdd_tip", "status", "flat"})
    EXPECT_TRUE(a[0].contains(key)) << key << " in " << a[0].dump();
}

// A set between two links in a JSON line (`at`, `relative_to`, `relative_at`) is the scene's set: the
// four-bar's loop given both ways (the scene at the flags' gravity, along −z) gives one answer, to
// the rounding of the scene's decomposed tracks against the line's single one (1e-12 of values
// below 1e3); a misspelt key of the offset is named.
TEST(SolveScene, ALoopSetInAJsonLineIsTheScenesSet) {
  test::TempDir dir;
  const std::string urdf = kSource + "/robots/four_bar/four_bar.urdf";
  std::string scene = test::read_text(kSource + "/robots/four_bar/four_bar_loop.yaml");
  scene.replace(scene.find("urdf: four_bar.urdf"), 19, "urdf: " + urdf);
  scene.erase(scene.find("gravity: [0, -9.81, 0]\n"), 23);
  const std::string path = dir.write("loop.yaml", scene);
  const std::string state = R"("q": [0.4, 1.9, 1.2], "qd": [1.5, -0.7, 0.3])";
  const CommandResult by_scene = solve({"--scene", path}, "{" + state + R"(, "motor": [2, 0, 0], "beta": [0.3, -0.2]})" + "\n");
  ASSERT_EQ(by_scene.exit_code, 0) << describe(by_scene);
  const std::string set =
      R"({"link": "coupler", "at": {"xyz": [1, 0, 0]}, "relative_to": "rocker", "relative_at": {"xyz": [0.8, 0, 0]}, )"
      R"("alpha": [[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0]], "beta": [0.3, -0.2]})";
  const std::vector<std::string> flags = {"--urdf", urdf, "--root", "ground", "--tip", "coupler", "--branch-tip", "rocker"};
  const CommandResult by_line = solve(flags, "{" + state + R"(, "tau_ff": [2, 0, 0], "constraints": [)" + set + "]}\n");
  ASSERT_EQ(by_line.exit_code, 0) << describe(by_line);
  const json a = answers(by_scene).at(0), b = answers(by_line).at(0);
  for (const char* key : {"qdd", "nu"})
    for (std::size_t i = 0; i < a[key].size(); ++i)
      EXPECT_NEAR(a[key][i].get<double>(), b[key][i].get<double>(), 1e-12) << key << " " << i;
  EXPECT_GT(std::abs(a["nu"][0].get<double>()), 0.1) << "the loop carries a force";
  std::string misspelt = set;
  misspelt.replace(misspelt.find("\"xyz\": [1"), 5, "\"xzy\"");
  const CommandResult bad = solve(flags, "{" + state + R"(, "constraints": [)" + misspelt + "]}\n");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("constraints[0].at.xzy"), std::string::npos) << describe(bad);
}

TEST(SolveScene, RefusesWhatTheSceneDoesNotHave) {
  const std::string state = R"("q": [0.3, 0.2, -0.4], "qd": [0.1, -0.2, 0.3])";
  const struct {
    std::string line, message;
  } cases[] = {
      {"{" + state + R"(, "tau": [0, 0, 0]})", "key 'tau': not an input of scene 'planar_nc2'"},
      {"{" + state + R"(, "tool_lod": [0, 0, 0, 0, 0, 0]})", "did you mean 'tool_load'"},
      {"{" + state + R"(, "alpha": [[0, 0, 0, 1, 0, 0]]})", "the scene fixes every constraint direction"},
      {"{" + state + R"(, "policy": "damped"})", "one of the scene's policies: original, prioritize_external"},
      {"{" + state + R"(, "flat": [0]})", "give either \"flat\" or the named inputs"},
      {R"({"qd": [0, 0, 0]})", "key 'q': missing"},
  };
  for (const auto& c : cases) {
    const CommandResult r = solve({"--scene", kPlanarScene}, c.line + "\n");
    EXPECT_EQ(r.exit_code, 1) << c.line << "\n" << describe(r);
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.line << "\n" << describe(r);
  }
  // A scene of run-time directions needs them.
  const CommandResult r = solve({"--scene", kSource + "/robots/panda/panda_nc3.yaml"},
                                R"({"q": [0, 0, 0, -1, 0, 1, 0], "qd": [0, 0, 0, 0, 0, 0, 0]})"
                                "\n");
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  EXPECT_NE(r.err.find("key 'alpha': missing: the scene's sets have 3 run-time directions"), std::string::npos)
      << describe(r);
}

// A chain flag beside --scene would solve another problem than the scene's generated solver: a
// usage error (exit 2) naming both, as is neither a scene nor a URDF.
TEST(SolveScene, ChainFlagsBesideASceneAreAUsageError) {
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--tip", "tool"}, {"--urdf", kSource + "/robots/planar/planar_rpr.urdf"},
        {"--floating-base"}, {"--rotor-inertia", "planar_joint1=0.02"}, {"--no-snap-quarter-turns"},
        {"--mimic", "coupled"}}) {
    std::vector<std::string> args{"--scene", kPlanarScene};
    args.insert(args.end(), extra.begin(), extra.end());
    const CommandResult r = solve(args, "");
    EXPECT_EQ(r.exit_code, 2) << extra[0] << "\n" << describe(r);
    EXPECT_NE(r.err.find(extra[0] + " and --scene"), std::string::npos) << describe(r);
  }
  const CommandResult neither = solve({}, "");
  EXPECT_EQ(neither.exit_code, 2) << describe(neither);
  EXPECT_NE(neither.err.find("--scene or --urdf"), std::string::npos) << describe(neither);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// The scene file (generator/scene/scene.hpp): a full valid scene, the default scene, the track
// layouts, and one test per kind of error, each checking file:line:column, element and reason.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "model/error.hpp"
#include "scene/cpp_names.hpp"
#include "scene/scene.hpp"
#include "support/bundled_robots.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using scene::Scene;
using solver::Policy;

std::string panda_urdf() { return test::source_path("robots/panda/panda.urdf"); }

// A valid scene using every key; tests replace one piece of it. @URDF@ is the Panda's path.
const std::string kFullScene = R"(sweepgen_scene: 1
solver: panda_nc6
urdf: @URDF@
root: panda_link0
tip: panda_hand
gravity: [0, 0, -9.80665]
rotor_inertia: {panda_joint1: 0.1, panda_joint7: 0.02}
drivers:
  torques: [tau_ff]
  external_forces:
    - {name: contact, link: panda_link5}
    - {name: push, link: panda_hand}
  constraints: 6
decomposition: decomposed
policies: [original, prioritize_external, saturate, saturate_exact]
scalars: [double, float]
expose: all
pivot_tolerance: 1e-12
constraint_factorisation: damped
)";

// `text` with the first occurrence of `from` replaced by `to` (which must exist).
std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the scene";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string with_urdf(const std::string& text, const std::string& urdf = panda_urdf()) {
  return replace(text, "@URDF@", urdf);
}

// "line:column" (1-based) of the `occurrence`-th `token` in line `line` of `text`.
std::string position(const std::string& text, int line, const std::string& token, int occurrence = 1) {
  std::size_t start = 0;
  for (int i = 1; i < line; ++i) start = text.find('\n', start) + 1;
  const std::string row = text.substr(start, text.find('\n', start) - start);
  std::size_t column = std::string::npos;
  for (int k = 0; k < occurrence; ++k) column = row.find(token, column == std::string::npos ? 0 : column + 1);
  EXPECT_NE(column, std::string::npos) << "'" << token << "' not on line " << line << ": " << row;
  return std::to_string(line) + ":" + std::to_string(column + 1);
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' missing in: " << text;
}

struct Loaded {
  std::string path;
  std::string message;  // "" if everything loaded
};

// Writes `text` as scene.yaml, loads it and its chain; returns the error message (or "").
Loaded load(const test::TempDir& dir, const std::string& text) {
  Loaded out{dir.write("scene.yaml", text), ""};
  try {
    const Scene s = scene::load_scene(out.path);
    scene::load_scene_chain(s);
  } catch (const InputError& e) {
    out.message = e.what();
  }
  return out;
}

// Expects an error at `where` ("line:column") on `element`, with `reason` in the message.
void expect_error(const std::string& text, const std::string& where, const std::string& element,
                  const std::string& reason, const std::string& hint = "") {
  test::TempDir dir;
  const Loaded loaded = load(dir, text);
  ASSERT_FALSE(loaded.message.empty()) << "no error for:\n" << text;
  expect_contains(loaded.message, loaded.path + ":" + where + ": " + element + ": ");
  expect_contains(loaded.message, reason);
  if (!hint.empty()) expect_contains(loaded.message, "(did you mean '" + hint + "'?)");
}

// ---------------------------------------------------------------------------------------------
// Valid scenes

TEST(Scene, FullSceneReadsEveryField) {
  test::TempDir dir;
  const std::string text = with_urdf(kFullScene);
  const std::string path = dir.write("scene.yaml", text);
  const Scene s = scene::load_scene(path);

  EXPECT_EQ(s.path, path);
  EXPECT_EQ(s.solver, "panda_nc6");
  EXPECT_EQ(s.chain.urdf, panda_urdf());
  EXPECT_EQ(s.chain.root_link, "panda_link0");
  EXPECT_EQ(s.chain.tip_link, "panda_hand");
  EXPECT_EQ(s.chain.rotor_inertia, (std::map<std::string, double>{{"panda_joint1", 0.1}, {"panda_joint7", 0.02}}));
  EXPECT_EQ(s.chain.rotor_inertia_source, path + ":" + position(text, 7, "{"));
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, 0, -9.80665));

  ASSERT_EQ(s.layout.torques, std::vector<std::string>{"tau_ff"});
  ASSERT_EQ(s.layout.external_forces.size(), 2u);
  EXPECT_EQ(s.layout.external_forces[0].name, "contact");
  EXPECT_EQ(s.layout.external_forces[0].link, "panda_link5");
  EXPECT_EQ(s.layout.external_forces[1].name, "push");
  EXPECT_EQ(s.layout.external_forces[1].link, "panda_hand");
  EXPECT_EQ(s.layout.constraints, 6u);
  EXPECT_EQ(s.layout.run_time_directions(), 6u);
  EXPECT_EQ(s.layout.listed_sets(), 0u);
  ASSERT_EQ(s.layout.tracks.size(), 4u);  // decomposed
  EXPECT_TRUE(s.layout.tracks[0].bias);

  EXPECT_EQ(s.policies, (std::vector<Policy>{Policy::original, Policy::prioritize_external, Policy::saturate,
                                             Policy::saturate_exact}));
  EXPECT_EQ(s.scalars, (std::vector<std::string>{"double", "float"}));
  EXPECT_TRUE(s.expose_all);
  EXPECT_EQ(s.pivot_tolerance, 1e-12);
  EXPECT_EQ(s.constraint_factorisation, solver::ConstraintFactorisation::damped);

  const solver::SolverOptions options = s.solver_options();
  EXPECT_EQ(options.gravity, Eigen::Vector3d(0, 0, -9.80665));
  EXPECT_EQ(options.pivot_tolerance, 1e-12);
  EXPECT_EQ(options.constraint_factorisation, solver::ConstraintFactorisation::damped);

  EXPECT_EQ(s.locations.at("drivers.external_forces[1].link"), path + ":" + position(text, 12, "panda_hand"));
  EXPECT_EQ(s.locations.at("rotor_inertia.panda_joint7"), path + ":" + position(text, 7, "panda_joint7"));

  const model::Chain chain = scene::load_scene_chain(s);
  EXPECT_EQ(chain.dof(), 7u);
  EXPECT_EQ(chain.tip_link, "panda_hand");
  EXPECT_EQ(chain.joints[1].rotor_inertia, 0.1);
  EXPECT_EQ(chain.joints[7].rotor_inertia, 0.02);
  EXPECT_EQ(chain.joints[4].rotor_inertia, 0.0);
}

TEST(Scene, MinimalSceneGetsDefaults) {
  test::TempDir dir;
  const std::string path =
      dir.write("scene.yaml", with_urdf("sweepgen_scene: 1\nsolver: robots::panda\nurdf: @URDF@\n"));
  const Scene s = scene::load_scene(path);
  EXPECT_EQ(s.solver, "robots::panda");
  EXPECT_TRUE(s.chain.root_link.empty());
  EXPECT_TRUE(s.chain.tip_link.empty());
  EXPECT_TRUE(s.chain.rotor_inertia.empty());
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_TRUE(s.layout.torques.empty());
  EXPECT_TRUE(s.layout.external_forces.empty());
  EXPECT_EQ(s.layout.constraints, 0u);
  ASSERT_EQ(s.layout.tracks.size(), 1u);
  EXPECT_TRUE(s.layout.tracks[0].bias);
  EXPECT_EQ(s.policies, std::vector<Policy>{Policy::original});
  EXPECT_EQ(s.scalars, std::vector<std::string>{"double"});
  EXPECT_FALSE(s.expose_all);
  EXPECT_EQ(s.pivot_tolerance, 0.0);
  EXPECT_EQ(s.constraint_factorisation, solver::ConstraintFactorisation::pivoted_ldlt);
  EXPECT_TRUE(s.chain.snap_quarter_turns);
  const model::Chain chain = scene::load_scene_chain(s);
  EXPECT_EQ(chain.root_link, "panda_link0");
  EXPECT_EQ(chain.tip_link, "panda_hand");
}

// derivatives: true (docs/derivation.md, D3) needs the tau_ff columns and a differentiable policy;
// false, the default, asks for nothing.
TEST(Scene, DerivativesNeedATorqueDriverAndADifferentiablePolicy) {
  test::TempDir dir;
  const Scene plain = scene::load_scene(dir.write("plain.yaml", with_urdf(kFullScene)));
  EXPECT_FALSE(plain.derivatives);
  const std::string with = kFullScene + "derivatives: true\n";
  EXPECT_TRUE(scene::load_scene(dir.write("with.yaml", with_urdf(with))).derivatives);
  // The error is at the key's value.
  const auto at_value = [](const std::string& text) {
    const auto line = std::count(text.begin(), text.begin() + static_cast<long>(text.find("derivatives:")), '\n') + 1;
    return position(text, static_cast<int>(line), "true");
  };
  const std::string no_torques = replace(with, "  torques: [tau_ff]\n", "");
  expect_error(with_urdf(no_torques), at_value(no_torques), "derivatives", "need a torque driver");
  const std::string saturating = replace(with, "policies: [original, prioritize_external, saturate, saturate_exact]",
                                         "policies: [saturate]");
  expect_error(with_urdf(saturating), at_value(saturating), "derivatives", "need a differentiable policy");
}

// derivatives: a list names the outputs whose Jacobians are returned; true returns all three.
TEST(Scene, DerivativesListTheOutputsWhoseJacobiansAreReturned) {
  test::TempDir dir;
  const Scene all = scene::load_scene(dir.write("all.yaml", with_urdf(kFullScene + "derivatives: true\n")));
  EXPECT_TRUE(all.derivative_outputs.qdd && all.derivative_outputs.nu && all.derivative_outputs.tau_cmd);
  const Scene listed = scene::load_scene(dir.write("listed.yaml", with_urdf(kFullScene + "derivatives: [nu, qdd]\n")));
  EXPECT_TRUE(listed.derivatives);
  EXPECT_TRUE(listed.derivative_outputs.qdd);
  EXPECT_TRUE(listed.derivative_outputs.nu);
  EXPECT_FALSE(listed.derivative_outputs.tau_cmd);
  const Scene torque = scene::load_scene(dir.write("torque.yaml", with_urdf(kFullScene + "derivatives: [tau_cmd]\n")));
  EXPECT_FALSE(torque.derivative_outputs.qdd || torque.derivative_outputs.nu);
  EXPECT_TRUE(torque.derivative_outputs.tau_cmd);

  const int line = static_cast<int>(std::count(kFullScene.begin(), kFullScene.end(), '\n')) + 1;
  const std::string unknown = kFullScene + "derivatives: [qdd, tau]\n";
  expect_error(with_urdf(unknown), position(unknown, line, "tau"), "derivatives[1]", "unknown derivatives output 'tau'");
  const std::string twice = kFullScene + "derivatives: [qdd, nu, qdd]\n";
  expect_error(with_urdf(twice), position(twice, line, "qdd", 2), "derivatives[2]", "duplicate output 'qdd'");
  const std::string empty = kFullScene + "derivatives: []\n";
  expect_error(with_urdf(empty), position(empty, line, "["), "derivatives", "at least one of qdd, nu, tau_cmd");
  const std::string unconstrained = replace(kFullScene, "  constraints: 6\n", "") + "derivatives: [qdd, nu]\n";
  expect_error(with_urdf(unconstrained), position(unconstrained, line - 1, "nu"), "derivatives[1]",
               "nu has no entries: the scene has no constraint directions");
}

// outputs: the results the solves return; left out, all of them. The flat `out` holds only those
// listed, in the order of solver::FlatLayout, then the status.
TEST(Scene, OutputsListTheResultsTheSolvesReturn) {
  test::TempDir dir;
  const std::string base = replace(kFullScene, "expose: all\n", "expose: outputs\n");
  const Scene all = scene::load_scene(dir.write("all.yaml", with_urdf(base)));
  EXPECT_TRUE(all.outputs.all());
  const Scene listed = scene::load_scene(dir.write("listed.yaml", with_urdf(base + "outputs: [nu, qdd]\n")));
  EXPECT_TRUE(listed.outputs.qdd && listed.outputs.nu);
  EXPECT_FALSE(listed.outputs.tau_cmd || listed.outputs.tau_ctrl || listed.outputs.tip_acceleration);
  const model::Chain chain = scene::load_scene_chain(listed);
  const solver::FlatLayout flat = listed.flat_layout(chain);
  EXPECT_EQ(flat.qdd(), 0u);
  EXPECT_EQ(flat.nu(), chain.dof());
  EXPECT_EQ(flat.status(), chain.dof() + 6);
  EXPECT_EQ(flat.out_size(), chain.dof() + 6 + 1);
  EXPECT_FALSE(flat.has_link_acceleration());
  EXPECT_EQ(all.flat_layout(chain).out_size(), 3 * chain.dof() + 6 + 6 + 1);

  const int line = static_cast<int>(std::count(base.begin(), base.end(), '\n')) + 1;
  const std::string unknown = base + "outputs: [qdd, tau]\n";
  expect_error(with_urdf(unknown), position(unknown, line, "tau"), "outputs[1]", "unknown output 'tau'", "nu");
  const std::string twice = base + "outputs: [qdd, nu, qdd]\n";
  expect_error(with_urdf(twice), position(twice, line, "qdd", 2), "outputs[2]", "duplicate output 'qdd'");
  const std::string empty = base + "outputs: []\n";
  expect_error(with_urdf(empty), position(empty, line, "["), "outputs", "at least one output is needed");
  const std::string unconstrained = replace(base, "  constraints: 6\n", "") + "outputs: [qdd, nu]\n";
  expect_error(with_urdf(unconstrained), position(unconstrained, line - 1, "nu"), "outputs[1]",
               "nu has no entries: the scene has no constraint directions");
  const std::string no_sets = base + "outputs: [qdd, set_acceleration]\n";
  expect_error(with_urdf(no_sets), position(no_sets, line, "set_acceleration"), "outputs[1]",
               "set_acceleration has no entries: the scene lists no constraint sets");
  const std::string exposed = kFullScene + "outputs: [qdd]\n";
  expect_error(with_urdf(exposed), position(exposed, line, "["), "outputs", "'expose: all' returns every intermediate");
}

TEST(Scene, RelativeUrdfPathIsResolvedAgainstTheSceneDirectory) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path() / "scenes");
  const std::string relative = std::filesystem::relative(panda_urdf(), dir.path() / "scenes").string();
  ASSERT_FALSE(std::filesystem::path(relative).is_absolute());
  const std::string path = dir.write("scenes/scene.yaml", with_urdf(kFullScene, relative));
  const Scene s = scene::load_scene(path);
  EXPECT_TRUE(std::filesystem::path(s.chain.urdf).is_absolute());
  EXPECT_TRUE(std::filesystem::equivalent(s.chain.urdf, panda_urdf())) << s.chain.urdf;
  EXPECT_EQ(scene::load_scene_chain(s).dof(), 7u);
}

TEST(Scene, FixedConstraintDirections) {
  test::TempDir dir;
  const std::string path = dir.write(
      "scene.yaml", with_urdf(replace(kFullScene, "constraints: 6",
                                      "constraints: {directions: [[0,0,0,1,0,0], [0.6,0,0.8,0,0,0]]}")));
  const Scene s = scene::load_scene(path);
  EXPECT_EQ(s.layout.constraints, 2u);
  ASSERT_EQ(s.layout.sets.size(), 1u);
  const auto& fixed = s.layout.sets[0].fixed;
  ASSERT_EQ(fixed.size(), 2u);
  EXPECT_EQ(fixed[0].moment, Eigen::Vector3d::Zero());
  EXPECT_EQ(fixed[0].force, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(fixed[1].moment, Eigen::Vector3d(0.6, 0, 0.8));
  EXPECT_EQ(fixed[1].force, Eigen::Vector3d::Zero());
  EXPECT_EQ(s.layout.run_time_directions(), 0u);
  EXPECT_EQ(scene::load_scene_chain(s).dof(), 7u);
}

TEST(Scene, ComposedDecomposition) {
  test::TempDir dir;
  const std::string text = replace(replace(kFullScene, "decomposition: decomposed", "decomposition: composed"),
                                   "original, prioritize_external,", "original,");
  const Scene s = scene::load_scene(dir.write("scene.yaml", with_urdf(text)));
  ASSERT_EQ(s.layout.tracks.size(), 1u);
  const solver::Track& t = s.layout.tracks[0];
  EXPECT_TRUE(t.bias);
  EXPECT_EQ(t.torques, std::vector<std::size_t>{0});
  EXPECT_EQ(t.external_forces, (std::vector<std::size_t>{0, 1}));
  EXPECT_FALSE(s.layout.external_forces_separable());
}

TEST(Scene, DecomposedDecomposition) {
  test::TempDir dir;
  const Scene s = scene::load_scene(dir.write("scene.yaml", with_urdf(kFullScene)));
  const auto& tracks = s.layout.tracks;
  ASSERT_EQ(tracks.size(), 4u);
  EXPECT_EQ(tracks[0].name, "bias");
  EXPECT_TRUE(tracks[0].bias);
  EXPECT_TRUE(tracks[0].torques.empty() && tracks[0].external_forces.empty());
  EXPECT_EQ(tracks[1].name, "tau_ff");
  EXPECT_EQ(tracks[1].torques, std::vector<std::size_t>{0});
  EXPECT_EQ(tracks[2].name, "contact");
  EXPECT_EQ(tracks[2].external_forces, std::vector<std::size_t>{0});
  EXPECT_EQ(tracks[3].name, "push");
  EXPECT_EQ(tracks[3].external_forces, std::vector<std::size_t>{1});
  EXPECT_TRUE(s.layout.external_forces_separable());
}

TEST(Scene, DecompositionGroups) {
  test::TempDir dir;
  {
    const Scene s = scene::load_scene(dir.write(
        "scene.yaml",
        with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[bias, tau_ff], [contact, push]]"))));
    const auto& tracks = s.layout.tracks;
    ASSERT_EQ(tracks.size(), 2u);
    EXPECT_EQ(tracks[0].name, "bias");
    EXPECT_TRUE(tracks[0].bias);
    EXPECT_EQ(tracks[0].torques, std::vector<std::size_t>{0});
    EXPECT_TRUE(tracks[0].external_forces.empty());
    EXPECT_EQ(tracks[1].name, "contact");
    EXPECT_FALSE(tracks[1].bias);
    EXPECT_EQ(tracks[1].external_forces, (std::vector<std::size_t>{0, 1}));
    EXPECT_TRUE(s.layout.external_forces_separable());
    scene::load_scene_chain(s);  // solver::validate accepts it
  }
  {  // Unnamed instances (the bias too) get tracks of their own, after the groups.
    const Scene s = scene::load_scene(
        dir.write("scene.yaml", with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[push]]"))));
    const auto& tracks = s.layout.tracks;
    ASSERT_EQ(tracks.size(), 4u);
    EXPECT_EQ(tracks[0].name, "push");
    EXPECT_EQ(tracks[0].external_forces, std::vector<std::size_t>{1});
    EXPECT_EQ(tracks[1].name, "bias");
    EXPECT_TRUE(tracks[1].bias);
    EXPECT_EQ(tracks[2].name, "tau_ff");
    EXPECT_EQ(tracks[2].torques, std::vector<std::size_t>{0});
    EXPECT_EQ(tracks[3].name, "contact");
    EXPECT_EQ(tracks[3].external_forces, std::vector<std::size_t>{0});
    scene::load_scene_chain(s);
  }
}

TEST(Scene, DefaultScene) {
  const Scene s = scene::default_scene(panda_urdf(), "", "");
  EXPECT_TRUE(s.path.empty());
  EXPECT_EQ(s.solver, "panda");
  EXPECT_EQ(s.chain.urdf, panda_urdf());
  EXPECT_EQ(s.chain.root_link, "panda_link0");
  EXPECT_EQ(s.chain.tip_link, "panda_hand");
  EXPECT_EQ(s.layout.torques, std::vector<std::string>{"tau_ff"});
  ASSERT_EQ(s.layout.external_forces.size(), 1u);
  EXPECT_EQ(s.layout.external_forces[0].name, "f_ext_tip");
  EXPECT_EQ(s.layout.external_forces[0].link, "panda_hand");
  EXPECT_EQ(s.layout.constraints, 6u);
  EXPECT_EQ(s.layout.run_time_directions(), 6u);
  EXPECT_EQ(s.layout.listed_sets(), 0u);
  ASSERT_EQ(s.layout.tracks.size(), 3u);  // decomposed: bias, tau_ff, f_ext_tip
  EXPECT_TRUE(s.layout.tracks[0].bias);
  EXPECT_TRUE(s.layout.external_forces_separable());
  EXPECT_EQ(s.policies, (std::vector<Policy>{Policy::original, Policy::prioritize_external, Policy::saturate,
                                             Policy::saturate_exact}));
  EXPECT_EQ(s.scalars, std::vector<std::string>{"double"});
  EXPECT_FALSE(s.expose_all);
  EXPECT_EQ(s.pivot_tolerance, 0.0);
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_EQ(scene::load_scene_chain(s).dof(), 7u);

  // An explicit tip: the external force follows it.
  const Scene to_link7 = scene::default_scene(panda_urdf(), "panda_link0", "panda_link7");
  EXPECT_EQ(to_link7.layout.external_forces[0].link, "panda_link7");
  EXPECT_EQ(scene::load_scene_chain(to_link7).tip_link, "panda_link7");

  // Every bundled robot gets a usable namespace.
  for (const auto& robot : test::bundled_robots()) {
    const Scene r = scene::default_scene(test::source_path(robot.urdf), robot.root, robot.tip);
    EXPECT_EQ(scene::solver_namespace_problem(r.solver), "");
  }
  EXPECT_EQ(scene::default_scene(test::source_path("robots/planar/planar_rpr.urdf")).solver, "planar_rpr");
}

TEST(Scene, DefaultSceneNamespaceFromAnOddFileName) {
  test::TempDir dir;
  const std::string copy = (dir.path() / "7dof-arm.v2.urdf").string();
  std::filesystem::copy_file(panda_urdf(), copy);
  EXPECT_EQ(scene::default_scene(copy).solver, "robot_7dof_arm_v2");
  // A macro (under -std=gnu++17) and a name longer than a namespace may be.
  const std::string linux_copy = (dir.path() / "linux.urdf").string();
  std::filesystem::copy_file(panda_urdf(), linux_copy);
  EXPECT_EQ(scene::default_scene(linux_copy).solver, "robot_linux");
  const std::string long_copy = (dir.path() / (std::string(240, 'x') + ".urdf")).string();
  std::filesystem::copy_file(panda_urdf(), long_copy);
  EXPECT_EQ(scene::default_scene(long_copy).solver, std::string(200, 'x'));
}

TEST(Scene, DefaultSceneErrorsNameTheFlag) {
  try {
    scene::default_scene(panda_urdf(), "", "panda_hnd");
    FAIL();
  } catch (const InputError& e) {
    expect_contains(e.what(), "--tip: tip: ");
    expect_contains(e.what(), "(did you mean 'panda_hand'?)");
  }
}

// ---------------------------------------------------------------------------------------------
// Errors: each one names file:line:column, the element and the reason.

TEST(SceneErrors, YamlSyntaxError) {
  const std::string text = with_urdf(replace(kFullScene, "gravity: [0, 0, -9.80665]", "gravity: [0, 0, -9.80665"));
  test::TempDir dir;
  const Loaded loaded = load(dir, text);
  expect_contains(loaded.message, loaded.path + ":7:");
  expect_contains(loaded.message, "YAML: syntax error: ");
  expect_contains(loaded.message, "end of sequence flow not found");
}

// What YAML::Load would pass over without a word: a second document (it reads the first), and
// tags, which the reader does not honour.
TEST(SceneErrors, YamlSecondDocumentAndTags) {
  expect_error(with_urdf(kFullScene + "---\nsolver: other\n"), "20:1", "YAML",
               "a second document; a scene file holds one ('---' starts another)");
  expect_error(with_urdf(kFullScene + "---\n"), "20:1", "YAML", "a second document");
  const std::string str_tag = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: !!str panda_nc6"));
  expect_error(str_tag, "2:9", "YAML", "a tag ('tag:yaml.org,2002:str'): the scene reads none; write the value without it");
  const std::string custom_tag = with_urdf(replace(kFullScene, "gravity: [0, 0, -9.80665]", "gravity: !vector [0, 0, -9.80665]"));
  expect_error(custom_tag, "6:10", "YAML", "a tag ('!vector')");
}

TEST(SceneErrors, MissingFile) {
  try {
    scene::load_scene("/nonexistent/scene.yaml");
    FAIL();
  } catch (const InputError& e) {
    expect_contains(e.what(), "/nonexistent/scene.yaml: file: cannot be opened");
  }
}

TEST(SceneErrors, EmptyFileAndNonMapping) {
  expect_error("", "1:1", "scene", "the scene file is empty");
  expect_error("- a\n- b\n", "1:1", "scene", "expected a mapping");
}

TEST(SceneErrors, MissingRequiredKey) {
  const std::string text = with_urdf(replace(kFullScene, "solver: panda_nc6\n", ""));
  expect_error(text, "1:1", "solver", "missing required key 'solver'");
  expect_error(replace(kFullScene, "urdf: @URDF@\n", ""), "1:1", "urdf", "missing required key 'urdf'");
  expect_error(with_urdf(replace(kFullScene, "sweepgen_scene: 1\n", "")), "1:1", "sweepgen_scene",
               "missing required key 'sweepgen_scene'");
}

TEST(SceneErrors, UnsupportedVersion) {
  const std::string text = with_urdf(replace(kFullScene, "sweepgen_scene: 1", "sweepgen_scene: 2"));
  expect_error(text, position(text, 1, "2"), "sweepgen_scene", "unsupported scene version 2");
  const std::string text2 = with_urdf(replace(kFullScene, "sweepgen_scene: 1", "sweepgen_scene: one"));
  expect_error(text2, position(text2, 1, "one"), "sweepgen_scene", "expected an integer, got 'one'");
}

TEST(SceneErrors, UnknownTopLevelKey) {
  const std::string text = with_urdf(replace(kFullScene, "expose: all", "expsoe: all"));
  expect_error(text, position(text, 17, "expsoe"), "expsoe", "unknown key 'expsoe'", "expose");
}

TEST(SceneErrors, UnknownNestedKeys) {
  const std::string text = with_urdf(replace(kFullScene, "{name: push, link:", "{name: push, lnk:"));
  expect_error(text, position(text, 12, "lnk"), "drivers.external_forces[1].lnk", "unknown key 'lnk'", "link");
  const std::string text2 = with_urdf(replace(kFullScene, "  torques:", "  torque:"));
  expect_error(text2, position(text2, 9, "torque"), "drivers.torque", "unknown key 'torque'", "torques");
  const std::string text3 =
      with_urdf(replace(kFullScene, "constraints: 6", "constraints: {direction: [[0,0,0,1,0,0]]}"));
  expect_error(text3, position(text3, 13, "direction"), "drivers.constraints.direction", "unknown key 'direction'",
               "directions");
}

TEST(SceneErrors, DuplicateKey) {
  const std::string text = with_urdf(replace(kFullScene, "expose: all\n", "expose: all\nexpose: outputs\n"));
  expect_error(text, position(text, 18, "expose"), "expose", "duplicate key (first given at ");
  const std::string text2 = with_urdf(replace(kFullScene, "panda_joint7: 0.02", "panda_joint1: 0.02"));
  expect_error(text2, position(text2, 7, "panda_joint1", 2), "rotor_inertia.panda_joint1", "duplicate joint");
}

// snap_quarter_turns (docs/derivation.md, F2): true or false, read into the chain's spec.
TEST(Scene, SnapQuarterTurns) {
  test::TempDir dir;
  const std::string literal = with_urdf("sweepgen_scene: 1\nsolver: a\nurdf: @URDF@\nsnap_quarter_turns: false\n");
  EXPECT_FALSE(scene::load_scene(dir.write("literal.yaml", literal)).chain.snap_quarter_turns);
  const std::string odd = with_urdf("sweepgen_scene: 1\nsolver: a\nurdf: @URDF@\nsnap_quarter_turns: maybe\n");
  expect_error(odd, position(odd, 4, "maybe"), "snap_quarter_turns", "unknown snap_quarter_turns value 'maybe'");
}

TEST(SceneErrors, WrongTypes) {
  const std::string text = with_urdf(replace(kFullScene, "gravity: [0, 0, -9.80665]", "gravity: -9.81"));
  expect_error(text, position(text, 6, "-9.81"), "gravity", "expected a list, got '-9.81'");
  const std::string text2 = with_urdf(replace(kFullScene, "gravity: [0, 0, -9.80665]", "gravity: [0, down, -9.8]"));
  expect_error(text2, position(text2, 6, "down"), "gravity[1]", "expected a number, got 'down'");
  const std::string text3 = with_urdf(replace(kFullScene, "gravity: [0, 0, -9.80665]", "gravity: [0, -9.8]"));
  expect_error(text3, position(text3, 6, "["), "gravity", "expected 3 numbers");
  const std::string text4 = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: [panda]"));
  expect_error(text4, position(text4, 2, "["), "solver", "expected a string, got a list");
  const std::string text5 = with_urdf(replace(kFullScene, "constraints: 6", "constraints: six"));
  expect_error(text5, position(text5, 13, "six"), "drivers.constraints", "expected an integer, got 'six'");
  const std::string text6 = with_urdf("sweepgen_scene: 1\nsolver: a\nurdf: @URDF@\ndrivers: 3\n");
  expect_error(text6, position(text6, 4, "3"), "drivers", "expected a mapping");
  const std::string text7 = with_urdf(replace(kFullScene, "panda_joint7: 0.02", "panda_joint7: heavy"));
  expect_error(text7, position(text7, 7, "heavy"), "rotor_inertia.panda_joint7", "expected a number");
  const std::string text8 = with_urdf(replace(kFullScene, "panda_joint7: 0.02", "panda_joint7: -0.02"));
  expect_error(text8, position(text8, 7, "-0.02"), "rotor_inertia.panda_joint7", "must be >= 0");
  const std::string text9 = with_urdf(replace(kFullScene, "root: panda_link0", "root:"));
  expect_error(text9, "4:1", "root", "expected a string, got nothing");
  const std::string text10 = with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: {a: b}"));
  expect_error(text10, position(text10, 14, "{"), "decomposition", "expected 'composed', 'decomposed' or a list");
  const std::string text11 = with_urdf(replace(kFullScene, "    - {name: push, link: panda_hand}", "    - push"));
  expect_error(text11, position(text11, 12, "push"), "drivers.external_forces[1]", "expected a mapping");
  const std::string text12 = with_urdf(replace(kFullScene, "{name: push, link: panda_hand}", "{name: push}"));
  expect_error(text12, position(text12, 12, "{"), "drivers.external_forces[1]", "missing key 'link'");
}

TEST(SceneErrors, SolverNamespace) {
  for (const std::string bad : {"class", "2fast", "panda-nc6", "robots::new", "::panda", "robots::", "a__b", "_Panda",
                                "std::panda"}) {
    const std::string text = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: '" + bad + "'"));
    expect_error(text, position(text, 2, "'"), "solver", "'" + bad + "' is not a");
  }
  const std::string text = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: robots::new"));
  expect_error(text, position(text, 2, "robots"), "solver", "'new' is a C++ keyword");
}

// Names that pass as identifiers but cannot compile as a namespace: a macro (of <cmath>, or of
// the compiler under -std=gnu++17, CMake's default) is replaced by the preprocessor; a nested
// `std` would hide the standard library's from the generated code.
TEST(SceneErrors, SolverNamespaceThatCannotCompile) {
  for (const std::string bad : {"NAN", "INFINITY", "robots::M_PI", "linux", "unix::arm", "EOF"}) {
    const std::string text = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: " + bad));
    expect_error(text, "2:9", "solver", "is a macro of the C library's headers or of the compiler");
  }
  const std::string nested_std = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: a::std"));
  expect_error(nested_std, "2:9", "solver", "'a::std' is not a usable namespace: 'std' is reserved");
}

// The namespace names the generated files: bounded when the scene is read (200 characters), so
// that neither a long name nor many nested parts reach the compiler or the file system.
TEST(SceneErrors, SolverNamespaceLength) {
  std::string nested = "a";
  while (nested.size() < 2000) nested += "::a";  // 667 parts
  for (const std::string& bad : {std::string(201, 'a'), std::string(245, 'n'), nested}) {
    const std::string text = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: " + bad));
    expect_error(text, "2:9", "solver",
                 std::to_string(bad.size()) + " characters, more than the limit of 200 (README, \"Limits\"");
  }
  const std::string longest = with_urdf(replace(kFullScene, "solver: panda_nc6", "solver: " + std::string(200, 'a')));
  test::TempDir dir;
  EXPECT_EQ(load(dir, longest).message, "");
}

// Every non-reserved macro the system compiler defines after the C library's headers (under
// -std=gnu++17, CMake's default) is refused: the table in generator/scene/cpp_names.cpp is
// complete for this compiler.
TEST(SceneNames, EveryMacroOfTheCLibraryIsRefused) {
  test::TempDir dir;
  std::string includes;
  for (const char* header : {"cassert", "cctype", "cerrno", "cfloat", "cinttypes", "climits", "clocale", "cmath", "csetjmp",
                             "csignal", "cstdarg", "cstddef", "cstdint", "cstdio", "cstdlib", "cstring", "ctime", "cwchar",
                             "cwctype", "type_traits"})
    includes += "#include <" + std::string(header) + ">\n";
  const std::string source = dir.write("headers.cpp", includes);
  const std::string macros = (dir.path() / "macros.txt").string();
  ASSERT_EQ(std::system(("c++ -std=gnu++17 -dM -E " + source + " > " + macros).c_str()), 0);
  std::ifstream in(macros);
  std::size_t checked = 0;
  for (std::string directive, name; in >> directive >> name && std::getline(in, directive);) {
    name = name.substr(0, name.find('('));
    if (!scene::identifier_problem(name).empty()) ++checked;
    else ADD_FAILURE() << "macro " << name << " is accepted as a name";
  }
  EXPECT_GT(checked, 500u);
}

TEST(SceneErrors, DuplicateInstanceNames) {
  const std::string text = with_urdf(replace(kFullScene, "torques: [tau_ff]", "torques: [tau_ff, tau_ff]"));
  expect_error(text, position(text, 9, "tau_ff", 2), "drivers.torques[1]",
               "duplicate driver instance name 'tau_ff' (first given at ");
  const std::string text2 = with_urdf(replace(kFullScene, "{name: push,", "{name: tau_ff,"));
  expect_error(text2, position(text2, 12, "tau_ff"), "drivers.external_forces[1].name",
               "duplicate driver instance name 'tau_ff'");
  const std::string text3 = with_urdf(replace(kFullScene, "torques: [tau_ff]", "torques: [bias]"));
  expect_error(text3, position(text3, 9, "bias"), "drivers.torques[0]", "'bias' is reserved");
  const std::string text4 = with_urdf(replace(kFullScene, "torques: [tau_ff]", "torques: [tau ff]"));
  expect_error(text4, position(text4, 9, "tau ff"), "drivers.torques[0]", "is not a usable C++ identifier");
}

// Driver names become members of the generated Drivers: the names the generated code declares
// where those members are (their extents, types and views) and macros cannot be one.
TEST(SceneErrors, DriverNamesThatCannotCompile) {
  for (const std::string reserved : {"S", "Scalar", "SixRows", "dof", "constraints", "alpha"}) {
    const std::string text = with_urdf(replace(kFullScene, "torques: [tau_ff]", "torques: [" + reserved + "]"));
    expect_error(text, position(text, 9, reserved), "drivers.torques[0]", "'" + reserved + "' is reserved for ");
    expect_contains(load(test::TempDir(), text).message,
                    "(reserved driver names: bias, alpha, S, Scalar, SixRows, dof, constraints); pick another name");
  }
  for (const std::string macro : {"NAN", "M_PI"}) {
    const std::string text = with_urdf(replace(kFullScene, "{name: push,", "{name: " + macro + ","));
    expect_error(text, position(text, 12, macro), "drivers.external_forces[1].name",
                 "'" + macro + "' is not a usable C++ identifier: it is a macro");
  }
}

TEST(SceneErrors, DecompositionGroupNamesUnknownInstance) {
  const std::string text =
      with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[bias, tau_f], [contact]]"));
  expect_error(text, position(text, 14, "tau_f"), "decomposition[0][1]", "unknown driver instance 'tau_f'", "tau_ff");
  const std::string text2 = with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: split"));
  expect_error(text2, position(text2, 14, "split"), "decomposition", "unknown decomposition 'split'");
  const std::string text3 = with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[bias], []]"));
  expect_error(text3, position(text3, 14, "[]"), "decomposition[1]", "empty group");
}

TEST(SceneErrors, InstanceInTwoGroups) {
  const std::string text =
      with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[bias, push], [contact, push]]"));
  expect_error(text, position(text, 14, "push", 2), "decomposition[1][1]", "'push' is already in a group (at ");
}

TEST(SceneErrors, PrioritizeExternalNeedsSeparableExternalForces) {
  const std::string text = with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: composed"));
  expect_error(text, position(text, 15, "prioritize_external"), "policies[1]",
               "external force 'contact' shares track 'composed' with the bias, torque 'tau_ff'");
  const std::string text2 =
      with_urdf(replace(kFullScene, "decomposition: decomposed", "decomposition: [[tau_ff, push]]"));
  expect_error(text2, position(text2, 15, "prioritize_external"), "policies[1]",
               "external force 'push' shares track 'tau_ff' with torque 'tau_ff'");
}

TEST(SceneErrors, ConstraintCountOutOfRange) {
  for (const std::string count : {"7", "-1"}) {
    const std::string text = with_urdf(replace(kFullScene, "constraints: 6", "constraints: " + count));
    expect_error(text, position(text, 13, count), "drivers.constraints", "must be in 0..6, got " + count);
  }
  const std::string text = with_urdf(replace(
      kFullScene, "constraints: 6",
      "constraints: {directions: [[1,0,0,0,0,0],[1,0,0,0,0,0],[1,0,0,0,0,0],[1,0,0,0,0,0],[1,0,0,0,0,0],[1,0,0,0,0,0],"
      "[1,0,0,0,0,0]]}"));
  expect_error(text, position(text, 13, "[["), "drivers.constraints.directions", "at most 6 constraint directions");
}

TEST(Scene, ConstraintSetsOnAnyLinks) {
  test::TempDir dir;
  const std::string text = with_urdf(replace(kFullScene, "constraints: 6",
                                             "constraints:\n    - {link: panda_link4, count: 2}\n"
                                             "    - {link: panda_hand, directions: [[0,0,0,0,0,1]]}\n"
                                             "    - {link: panda_link2, count: 1}"));
  const Scene s = scene::load_scene(dir.write("scene.yaml", text));
  ASSERT_EQ(s.layout.sets.size(), 3u);
  EXPECT_EQ(s.layout.sets[0].link, "panda_link4");
  EXPECT_EQ(s.layout.sets[0].count, 2u);
  EXPECT_FALSE(s.layout.sets[0].directions_fixed());
  EXPECT_EQ(s.layout.sets[1].link, "panda_hand");
  ASSERT_EQ(s.layout.sets[1].fixed.size(), 1u);
  EXPECT_EQ(s.layout.sets[1].fixed[0].force, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(s.layout.constraints, 4u);
  EXPECT_EQ(s.layout.run_time_directions(), 3u);
  EXPECT_EQ(s.layout.listed_sets(), 3u);
  const model::Chain chain = scene::load_scene_chain(s);
  // α: the run-time directions only, in order (sets 0 and 2); out: Ẍ of every listed set.
  const solver::FlatLayout flat = s.flat_layout(chain);
  EXPECT_EQ(flat.input_directions, (std::vector<std::size_t>{0, 1, 3}));
  EXPECT_EQ(flat.direction_set, (std::vector<std::size_t>{0, 0, 1, 2}));
  EXPECT_EQ(flat.status(), flat.tip_acceleration() + 6 + 3 * 6);
}

TEST(SceneErrors, ConstraintSets) {
  const auto sets = [](const std::string& list) {
    return with_urdf(replace(kFullScene, "constraints: 6", "constraints:\n" + list));
  };
  const std::string unknown = sets("    - {link: panda_link4, count: 2}\n    - {link: panda_lnk6, count: 1}");
  expect_error(unknown, position(unknown, 15, "panda_lnk6"), "drivers.constraints[1].link",
               "link 'panda_lnk6' of a constraint set is not on the chain", "panda_link6");
  const std::string twice = sets("    - {link: panda_link4, count: 2}\n    - {link: panda_link4, count: 1}");
  expect_error(twice, position(twice, 15, "panda_link4"), "drivers.constraints[1].link",
               "a second constraint set on link 'panda_link4' (first at ");
  const std::string seven = sets("    - {link: panda_hand, count: 7}");
  expect_error(seven, position(seven, 14, "7"), "drivers.constraints[0].count", "at most 6 constraint directions");
  const std::string both = sets("    - {link: panda_hand, count: 1, directions: [[0,0,0,0,0,1]]}");
  expect_error(both, position(both, 14, "{"), "drivers.constraints[0]", "exactly one of 'count'");
  const std::string base = sets("    - {link: panda_link0, count: 1}");
  expect_error(base, position(base, 14, "panda_link0"), "drivers.constraints[0].link", "is fixed to the base");
  // Joints 1 and 2 move panda_link2: three directions there (or two there and two more on
  // panda_link1) over-determine the robot.
  const std::string over = sets("    - {link: panda_link2, count: 3}");
  expect_error(over, position(over, 14, "-"), "drivers.constraints",
               "3 constraint directions on link 'panda_link2' but only 2 joints move them");
  const std::string over2 = sets("    - {link: panda_link1, count: 1}\n    - {link: panda_link2, count: 2}");
  expect_error(over2, position(over2, 14, "-"), "drivers.constraints",
               "3 constraint directions on links 'panda_link1', 'panda_link2' but only 2 joints move them");
  const std::string empty = with_urdf(replace(kFullScene, "constraints: 6", "constraints: []"));
  expect_error(empty, position(empty, 13, "[]"), "drivers.constraints", "an empty list of constraint sets");
}

// A fixed direction is taken as its unit vector (said in Scene::notes, as the loader says of
// axes); a zero one, or one of other than six numbers, is refused.
TEST(SceneErrors, FixedDirectionZeroOrNotSix) {
  const std::string text =
      with_urdf(replace(kFullScene, "constraints: 6", "constraints: {directions: [[0,0,0,1,0,0], [0,0,0,0,0,0]]}"));
  expect_error(text, position(text, 13, "[0,0,0,0"), "drivers.constraints.directions[1]", "a zero direction constrains nothing");
  const std::string text3 =
      with_urdf(replace(kFullScene, "constraints: 6", "constraints: {directions: [[0,0,0,1,0]]}"));
  expect_error(text3, position(text3, 13, "[0,0,0"), "drivers.constraints.directions[0]", "expected 6 numbers");
  test::TempDir dir;
  const Scene s = scene::load_scene(
      dir.write("scene.yaml", with_urdf(replace(kFullScene, "constraints: 6", "constraints: {directions: [[0,0,1,0,0,1], [0,0,0,1,0,0]]}"))));
  const std::vector<solver::ConstraintSet> sets = s.layout.constraint_sets();  // a copy: held below
  const auto& fixed = sets.at(0).fixed;
  EXPECT_EQ(fixed.at(0).moment.z(), 1 / std::sqrt(2.0));  // v / |v|, as read
  EXPECT_EQ(fixed.at(0).force.z(), 1 / std::sqrt(2.0));
  ASSERT_EQ(s.notes.size(), 1u);  // the unit one is taken as written, unsaid
  expect_contains(s.notes[0], "scene.yaml:13:");
  expect_contains(s.notes[0], "constraint direction [0, 0, 1, 0, 0, 1] taken as the unit vector [0, 0, 0.70710678118654746, 0, 0, "
                              "0.70710678118654746]");
}

TEST(SceneErrors, FixedDirectionNaN) {
  const std::string text =
      with_urdf(replace(kFullScene, "constraints: 6", "constraints: {directions: [[0,0,0,1,0,.nan]]}"));
  expect_error(text, position(text, 13, ".nan"), "drivers.constraints.directions[0][5]", "not finite");
}

TEST(SceneErrors, UnknownPolicy) {
  const std::string text = with_urdf(replace(kFullScene, "saturate_exact]", "saturate_exakt]"));
  expect_error(text, position(text, 15, "saturate_exakt"), "policies[3]", "unknown policy 'saturate_exakt'",
               "saturate_exact");
  const std::string text2 = with_urdf(replace(kFullScene, "saturate_exact]", "original]"));
  expect_error(text2, position(text2, 15, "original", 2), "policies[3]", "duplicate policy 'original'");
  const std::string text3 = with_urdf(replace(kFullScene, "policies: [original, prioritize_external, saturate, saturate_exact]", "policies: []"));
  expect_error(text3, position(text3, 15, "[]"), "policies", "at least one policy");
}

TEST(SceneErrors, UnknownScalar) {
  const std::string text = with_urdf(replace(kFullScene, "scalars: [double, float]", "scalars: [double, flaot]"));
  expect_error(text, position(text, 16, "flaot"), "scalars[1]", "unknown scalar type 'flaot'", "float");
  const std::string text2 = with_urdf(replace(kFullScene, "scalars: [double, float]", "scalars: [double, double]"));
  expect_error(text2, position(text2, 16, "double", 2), "scalars[1]", "duplicate scalar type 'double'");
}

TEST(SceneErrors, ExposeBaseAndPivotTolerance) {
  const std::string text = with_urdf(replace(kFullScene, "expose: all", "expose: everything"));
  expect_error(text, position(text, 17, "everything"), "expose", "unknown expose mode 'everything'");
  for (const std::string bad : {"0", "1", "-1e-9"}) {
    const std::string text2 = with_urdf(replace(kFullScene, "pivot_tolerance: 1e-12", "pivot_tolerance: " + bad));
    expect_error(text2, position(text2, 18, bad), "pivot_tolerance", "must be > 0 and < 1");
  }
  const std::string text4 = with_urdf(replace(kFullScene, "expose: all", "expose: all\nbase: flaoting"));
  expect_error(text4, position(text4, 18, "flaoting"), "base", "unknown base 'flaoting'", "floating");
  const std::string text3 = with_urdf(replace(kFullScene, "constraint_factorisation: damped", "constraint_factorisation: dampd"));
  expect_error(text3, position(text3, 19, "dampd"), "constraint_factorisation", "unknown constraint factorisation 'dampd'",
               "damped");
}

// Errors found against the chain (load_scene_chain).

TEST(SceneErrors, ExternalForceLinkNotOnChain) {
  const std::string text = with_urdf(replace(kFullScene, "link: panda_link5", "link: panda_lnk5"));
  expect_error(text, position(text, 11, "panda_lnk5"), "drivers.external_forces[0].link",
               "link 'panda_lnk5' of external force 'contact' is not on the chain", "panda_link5");
  // Beyond the tip but fixed to it: lumped into the last body, so a force on it is valid.
  const std::string text2 = with_urdf(replace(kFullScene, "tip: panda_hand", "tip: panda_link7"));
  test::TempDir dir;
  EXPECT_EQ(load(dir, text2).message, "");
  EXPECT_EQ(scene::load_scene_chain(scene::load_scene(dir.write("scene.yaml", text2))).frames.at("panda_hand").body, 7u);
  // Beyond the root: not carried by the chain.
  const std::string text3 = with_urdf(replace(replace(replace(kFullScene, "root: panda_link0", "root: panda_link1"),
                                                      "link: panda_link5", "link: panda_link0"),
                                              "panda_joint1: 0.1, ", ""));
  expect_error(text3, position(text3, 11, "panda_link0"), "drivers.external_forces[0].link",
               "link 'panda_link0' of external force 'contact' is not on the chain");
}

TEST(SceneErrors, ExternalForceLinkFixedToBase) {
  const std::string text = with_urdf(replace(kFullScene, "link: panda_link5", "link: panda_link0"));
  expect_error(text, position(text, 11, "panda_link0"), "drivers.external_forces[0].link", "is fixed to the base");
}

TEST(SceneErrors, RotorInertiaUnknownJoint) {
  const std::string text = with_urdf(replace(kFullScene, "panda_joint7: 0.02", "panda_jiont7: 0.02"));
  expect_error(text, position(text, 7, "panda_jiont7"), "rotor_inertia.panda_jiont7",
               "no moving joint 'panda_jiont7' on the chain", "panda_joint7");
  // A fixed joint is not a moving joint.
  const std::string text2 = with_urdf(replace(kFullScene, "panda_joint7: 0.02", "panda_joint8: 0.02"));
  expect_error(text2, position(text2, 7, "panda_joint8"), "rotor_inertia.panda_joint8", "no moving joint");
}

// locked_joints: positions of off-chain joints, each checked against the URDF at its own entry.
const std::string kSideBranchScene = R"(sweepgen_scene: 1
solver: side_branches
urdf: @URDF@
root: base
tip: wrist
locked_joints: {side_joint: 0.7, finger_left_joint: 0.02}
drivers: {external_forces: [{name: pinch, link: finger_left}]}
)";

TEST(Scene, LockedJointsHoldOffChainBranches) {
  const std::string text = with_urdf(kSideBranchScene, test::source_path("tests/data/side_branches.urdf"));
  test::TempDir dir;
  const Scene s = scene::load_scene(dir.write("scene.yaml", text));
  EXPECT_EQ(s.chain.locked_joints.at("side_joint"), 0.7);
  EXPECT_EQ(s.chain.locked_joint_locations.at("finger_left_joint"), s.path + ":" + position(text, 6, "finger_left_joint"));
  const model::Chain chain = scene::load_scene_chain(s);
  ASSERT_EQ(chain.locked_joints.size(), 3u);
  EXPECT_EQ(chain.locked_joints[1].name, "finger_left_joint");
  EXPECT_EQ(chain.locked_joints[1].position, 0.02);
  EXPECT_EQ(chain.locked_joints[2].position, 0.005);  // finger_right_joint: 0 clamped into [0.005, 0.04]
  EXPECT_EQ(chain.frames.at("finger_left").body, 4u);  // the external force's link, lumped into the wrist
}

TEST(SceneErrors, LockedJointsCheckedAtTheirEntry) {
  const std::string urdf = test::source_path("tests/data/side_branches.urdf");
  const std::string on_chain = with_urdf(replace(kSideBranchScene, "side_joint: 0.7", "j2: 0.7"), urdf);
  expect_error(on_chain, position(on_chain, 6, "j2"), "locked_joints.j2", "is a moving joint of the chain");
  const std::string misspelt = with_urdf(replace(kSideBranchScene, "side_joint: 0.7", "side_jiont: 0.7"), urdf);
  expect_error(misspelt, position(misspelt, 6, "side_jiont"), "locked_joints.side_jiont", "no joint of that name", "side_joint");
  const std::string beyond = with_urdf(replace(kSideBranchScene, "side_joint: 0.7", "side_joint: 1.5"), urdf);
  expect_error(beyond, position(beyond, 6, "side_joint"), "locked_joints.side_joint", "outside the joint's limits [-1, 1]");
  const std::string twice = with_urdf(replace(kSideBranchScene, "finger_left_joint: 0.02", "side_joint: 0.02"), urdf);
  expect_error(twice, position(twice, 6, "side_joint", 2), "locked_joints.side_joint", "duplicate joint");
}

// `tips`: the tree of several root-to-tip paths (the bundled dual Panda).
const std::string kTreeScene = R"(sweepgen_scene: 1
solver: dual
urdf: @URDF@
root: station
tips: [left_panda_hand, right_panda_hand]
drivers:
  constraints:
    - {link: left_panda_hand, count: 6}
    - {link: right_panda_link4, count: 2}
)";

TEST(Scene, TipsSpanATree) {
  test::TempDir dir;
  const std::string urdf = test::source_path("robots/dual_panda/dual_panda.urdf");
  const Scene s = scene::load_scene(dir.write("scene.yaml", with_urdf(kTreeScene, urdf)));
  EXPECT_EQ(s.chain.tip_link, "left_panda_hand");
  EXPECT_EQ(s.chain.branch_tips, (std::vector<std::string>{"right_panda_hand"}));
  const model::Chain chain = scene::load_scene_chain(s);
  EXPECT_EQ(chain.dof(), 15u);
  EXPECT_EQ(chain.parent[9], 1u) << "the right arm's first body hangs from the torso";
  EXPECT_EQ(chain.frames.at("right_panda_link4").body, 12u);
}

TEST(SceneErrors, Tips) {
  const std::string urdf = test::source_path("robots/dual_panda/dual_panda.urdf");
  const std::string both = with_urdf(replace(kTreeScene, "root: station", "root: station\ntip: torso"), urdf);
  expect_error(both, position(both, 6, "["), "tips", "give either 'tip' (one chain) or 'tips'");
  const std::string twice = with_urdf(replace(kTreeScene, "right_panda_hand]", "left_panda_hand]"), urdf);
  expect_error(twice, position(twice, 5, "left_panda_hand", 2), "tips[1]", "tip 'left_panda_hand' named twice");
  // A bad entry is reported at its own line and column, not at the list's.
  const std::string unknown = with_urdf(replace(kTreeScene, "right_panda_hand]", "right_panda_hnd]"), urdf);
  expect_error(unknown, position(unknown, 5, "right_panda_hnd"), "tips[1]", "tip link 'right_panda_hnd'", "right_panda_hand");
  const std::string first = with_urdf(replace(kTreeScene, "[left_panda_hand", "[left_panda_hnd"), urdf);
  expect_error(first, position(first, 5, "left_panda_hnd"), "tips[0]", "tip link 'left_panda_hnd'", "left_panda_hand");
  // A message about the tree names every tip, not only the first.
  const std::string off_tree = with_urdf(replace(kTreeScene, "link: left_panda_hand, count: 6", "link: left_panda_hnd, count: 6"), urdf);
  expect_error(off_tree, position(off_tree, 8, "left_panda_hnd"), "drivers.constraints[0].link",
               "link 'left_panda_hnd' of a constraint set is not on the tree from 'station' to 'left_panda_hand', "
               "'right_panda_hand'", "left_panda_hand");
  // Five directions on the right elbow (moved by the torso and four arm joints) and six on the
  // right hand are each within reach, but together they ask 11 of the 8 joints that move them.
  const std::string over = with_urdf(replace(kTreeScene, "right_panda_link4, count: 2", "right_panda_link4, count: 5}\n"
                                                                                       "    - {link: right_panda_hand, count: 6"),
                                     urdf);
  expect_error(over, position(over, 8, "-"), "drivers.constraints",
               "11 constraint directions on links 'right_panda_link4', 'right_panda_hand' but only 8 joints move them");
}

TEST(SceneErrors, UrdfProblemsPointAtTheSceneEntry) {
  const std::string text = with_urdf(replace(kFullScene, "root: panda_link0", "root: panda_lnk0"));
  test::TempDir dir;
  Loaded loaded = load(dir, text);
  expect_contains(loaded.message, loaded.path + ":" + position(text, 4, "panda_lnk0") + ": root: " + panda_urdf());
  expect_contains(loaded.message, "(did you mean 'panda_link0'?)");

  const std::string text2 = replace(kFullScene, "@URDF@", "missing.urdf");
  loaded = load(dir, text2);
  expect_contains(loaded.message, loaded.path + ":" + position(text2, 3, "missing") + ": urdf: ");
  expect_contains(loaded.message, "cannot be opened");
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

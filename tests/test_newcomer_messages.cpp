// What a newcomer's own robot meets first (README, "A first scene"): the default tip of a URDF
// whose flange carries only fixed frames, names that differ by a prefix or suffix, a root that
// does not reach the tip, fixed directions written to four digits, and the model's notes as one
// line per kind (every one behind --notes, as the generated header lists them).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "model/error.hpp"
#include "model/urdf_loader.hpp"
#include "oracle/kdl_chain.hpp"
#include "support/run_command.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using test::CommandResult;

CommandResult sweepgen(const std::vector<std::string>& args) {
  std::vector<std::string> words{SWEEPGEN_EXECUTABLE};
  words.insert(words.end(), args.begin(), args.end());
  return test::run_command(test::shell_command(words));
}

std::string describe(const CommandResult& r) {
  return "exit " + std::to_string(r.exit_code) + "\n--- stdout:\n" + r.out + "\n--- stderr:\n" + r.err;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string link(const std::string& name) {
  return "<link name=\"" + name + "\"><inertial><mass value=\"1\"/>"
         "<inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n";
}

std::string joint(const std::string& name, const std::string& type, const std::string& parent, const std::string& child,
                  const std::string& extra = "") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0.1 0 0.1\"/><axis xyz=\"0 0 1\"/>" +
         (type == "fixed" ? "" : "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/>") + extra + "</joint>\n";
}

// A two-joint arm whose flange carries a tool frame and a sensor frame on fixed joints; with
// `hand`, a side branch on the flange with four fingers, the third a <mimic> of the first.
std::string arm_with_fixed_frames(bool hand) {
  std::string urdf = "<robot name=\"arm\">\n" + link("base_link") + link("upper_link") + link("flange_link") + link("tool0") +
                     link("ft_sensor") + joint("shoulder", "revolute", "base_link", "upper_link") +
                     joint("elbow", "revolute", "upper_link", "flange_link") + joint("flange_tool", "fixed", "flange_link", "tool0") +
                     joint("flange_sensor", "fixed", "flange_link", "ft_sensor");
  if (hand)
    urdf += link("hand_mount") + link("finger_a") + link("finger_b") + link("finger_c") + link("finger_d") +
            joint("flange_hand", "fixed", "flange_link", "hand_mount") + joint("finger_a_joint", "revolute", "hand_mount", "finger_a") +
            joint("finger_b_joint", "revolute", "hand_mount", "finger_b") +
            joint("finger_c_joint", "revolute", "hand_mount", "finger_c", "<mimic joint=\"finger_a_joint\" multiplier=\"1\"/>") +
            joint("finger_d_joint", "revolute", "hand_mount", "finger_d");
  return urdf + "</robot>\n";
}

// Beyond the last moving joint only fixed frames: that body is the tip, and info says so.
TEST(NewcomerMessages, DefaultTipWhereOnlyFixedFramesRemain) {
  test::TempDir dir;
  const std::string urdf = dir.write("arm.urdf", arm_with_fixed_frames(false));
  const CommandResult info = sweepgen({"info", "--urdf", urdf});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  EXPECT_TRUE(contains(info.out, "chain base_link -> flange_link")) << describe(info);
  EXPECT_TRUE(contains(info.out, "tip flange_link: none named")) << describe(info);
}

// The notes of three default-locked fingers are one line with their count, each behind --notes;
// the <mimic> finger's once, with its coupling, not again as a default lock.
TEST(NewcomerMessages, NotesOneLinePerKind) {
  test::TempDir dir;
  const std::string urdf = dir.write("arm.urdf", arm_with_fixed_frames(true));
  const CommandResult info = sweepgen({"info", "--urdf", urdf, "--tip", "tool0"});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  EXPECT_TRUE(contains(info.out, "sweepgen: note: 3 joints off the chain locked at a default position (scene key "
                                 "locked_joints), the first: joint 'finger_a_joint'"))
      << describe(info);
  EXPECT_FALSE(contains(info.out, "'finger_b_joint'")) << describe(info);
  const CommandResult all = sweepgen({"info", "--urdf", urdf, "--tip", "tool0", "--notes"});
  ASSERT_EQ(all.exit_code, 0) << describe(all);
  for (const char* finger : {"finger_a_joint", "finger_b_joint", "finger_d_joint"})
    EXPECT_TRUE(contains(all.out, "note: joint '" + std::string(finger) + "' off the chain is locked at 0")) << describe(all);
  std::size_t mimic_lines = 0;
  for (std::size_t at = all.out.find("'finger_c_joint'"); at != std::string::npos; at = all.out.find("'finger_c_joint'", at + 1))
    ++mimic_lines;
  EXPECT_EQ(mimic_lines, 1u) << describe(all);
}

// Where a moving branch remains beyond a link with several children, there is no default tip.
TEST(NewcomerMessages, NoDefaultTipWhereMovingBranchesRemain) {
  test::TempDir dir;
  const std::string urdf = dir.write(
      "two.urdf", "<robot name=\"two\">\n" + link("base_link") + link("left") + link("right") +
                      joint("left_joint", "revolute", "base_link", "left") + joint("right_joint", "revolute", "base_link", "right") +
                      "</robot>\n");
  const CommandResult info = sweepgen({"info", "--urdf", urdf});
  EXPECT_EQ(info.exit_code, 1) << describe(info);
  EXPECT_TRUE(contains(info.err, "the tree branches here")) << describe(info);
}

TEST(NewcomerMessages, NamesThatDifferByAnAffixGetAHint) {
  const std::vector<std::string> links{"left_hand_link", "right_hand_link", "panda_link8", "base_link"};
  EXPECT_EQ(nearest_name_hint("left_hand", links), " (did you mean 'left_hand_link'?)");
  EXPECT_EQ(nearest_name_hint("link8", links), " (did you mean 'panda_link8'?)");
  EXPECT_EQ(nearest_name_hint("panda_base_link", links), " (did you mean 'base_link'?)");
  EXPECT_EQ(nearest_name_hint("gripper", links), "");  // no affix, no slip of a few letters
  EXPECT_EQ(nearest_name_hint("nk8", links), "");      // an affix at no '_' boundary
}

// A root that does not reach the tip: the root that does (the lowest link above both), or a swap.
TEST(NewcomerMessages, ARootThatDoesNotReachTheTipSuggestsOne) {
  test::TempDir dir;
  const std::string urdf = dir.write("arm.urdf", arm_with_fixed_frames(true));
  const CommandResult side = sweepgen({"info", "--urdf", urdf, "--root", "hand_mount", "--tip", "tool0"});
  EXPECT_EQ(side.exit_code, 1) << describe(side);
  EXPECT_TRUE(contains(side.err, "root 'flange_link', above both, reaches it, as does the URDF's root 'base_link'")) << describe(side);
  const CommandResult swapped = sweepgen({"info", "--urdf", urdf, "--root", "tool0", "--tip", "upper_link"});
  EXPECT_EQ(swapped.exit_code, 1) << describe(swapped);
  EXPECT_TRUE(contains(swapped.err, "it is above it: swap root and tip")) << describe(swapped);
}

// KDL's chain cannot start with a fixed joint (a vendor's world_joint): the reason names the root
// that expresses the same robot.
TEST(NewcomerMessages, KdlRowSuggestsTheRootBelowTheFixedJoints) {
  test::TempDir dir;
  model::ChainSpec spec;
  spec.urdf = dir.write("world.urdf", "<robot name=\"w\">\n<link name=\"world\"/>\n" + link("base_link") + link("upper_link") +
                                          joint("world_joint", "fixed", "world", "base_link") +
                                          joint("shoulder", "revolute", "base_link", "upper_link") + "</robot>\n");
  spec.root_link = "world";
  const model::Chain chain = model::load_chain(spec);
  KDL::Chain kdl;
  std::string why;
  EXPECT_FALSE(oracle::kdl_chain(spec.urdf, chain, kdl, why));
  EXPECT_TRUE(contains(why, "world_joint is fixed before the last moving joint; root: base_link (the scene key)")) << why;
  spec.root_link = "base_link";
  EXPECT_TRUE(oracle::kdl_chain(spec.urdf, model::load_chain(spec), kdl, why)) << why;
}

// A missing end tag is said where its element opened, not where the parser gave up.
TEST(NewcomerMessages, AMissingEndTagIsSaidWhereItsElementOpened) {
  test::TempDir dir;
  const struct {
    std::string urdf, message;
  } cases[] = {
      {"<robot name=\"r\">\n  <link name=\"a\">\n    <inertial>\n      <mass value=\"1\"/>\n  </link>\n</robot>\n",
       "x.urdf:3:5: <inertial>: not well-formed: this element has no end tag (</link> at 5:3 comes first)"},
      {"<robot name=\"r\">\n  <link name=\"a\">\n    <inertial/>\n  <link name=\"b\"/>\n</robot>\n",
       "x.urdf:2:3: <link>: not well-formed: this element has no end tag (</robot> at 5:1 comes first)"},
      {"<robot name=\"r\">\n  <link name=\"a\"/>\n", "x.urdf:1:1: <robot>: not well-formed: this element has no end tag (the text ends first)"},
      // A prefixed name (XML allows ':' in names) is quoted, so the element still ends at ": ".
      {"<robot name=\"r\">\n  <lin: name=\"a\">\n</robot>\n",
       "x.urdf:2:3: <'lin:'>: not well-formed: this element has no end tag (</robot> at 3:1 comes first)"},
  };
  for (const auto& c : cases) {
    const CommandResult r = sweepgen({"info", "--urdf", dir.write("x.urdf", c.urdf)});
    EXPECT_EQ(r.exit_code, 1) << describe(r);
    EXPECT_TRUE(contains(r.err, c.message)) << describe(r);
  }
}

// A fixed direction written to four digits is scaled to unit length and said, not refused; a zero
// one is refused.
TEST(NewcomerMessages, FixedDirectionsAreNormalisedAndSaid) {
  test::TempDir dir;
  const std::string urdf = dir.write("arm.urdf", arm_with_fixed_frames(false));
  const std::string head = "sweepgen_scene: 1\nsolver: arm\nurdf: arm.urdf\ntip: flange_link\n";
  const std::string scene =
      dir.write("arm.yaml", head + "drivers: {constraints: {directions: [[0, 0, 0, 0.7071, 0.7071, 0]]}}\n");
  const CommandResult info = sweepgen({"info", "--scene", scene});
  ASSERT_EQ(info.exit_code, 0) << describe(info);
  EXPECT_TRUE(contains(info.out, "arm.yaml:5:")) << describe(info);
  EXPECT_TRUE(contains(info.out, "constraint direction [0, 0, 0, 0.70709999999999995, 0.70709999999999995, 0] taken as the "
                                 "unit vector [0, 0, 0, 0.70710678118654757, 0.70710678118654757, 0]"))
      << describe(info);
  const std::string zero = dir.write("zero.yaml", head + "drivers: {constraints: {directions: [[0, 0, 0, 0, 0, 0]]}}\n");
  const CommandResult refused = sweepgen({"info", "--scene", zero});
  EXPECT_EQ(refused.exit_code, 1) << describe(refused);
  EXPECT_TRUE(contains(refused.err, "a zero direction constrains nothing")) << describe(refused);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

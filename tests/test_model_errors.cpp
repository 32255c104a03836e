// Every invalid URDF or chain request gets an InputError naming the file, the element and the
// reason.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>

#include "model/error.hpp"
#include "model/urdf_loader.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

// A valid two-joint arm; tests replace one marked piece of it.
std::string arm(const std::string& joint2_type = "revolute", const std::string& link2_inertial =
                    R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)",
                const std::string& extra = "") {
  return R"(<robot name="arm">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>
    <limit effort="10" velocity="1" lower="-1" upper="1"/></joint>
  <link name="l1"><inertial><origin xyz="0.1 0 0"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="j2" type=")" + joint2_type + R"("><parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/><limit effort="10" velocity="1" lower="-1" upper="1"/></joint>
  <link name="l2">)" + link2_inertial + R"(</link>)" + extra + R"(
</robot>)";
}

// A ChainSpec of `urdf` (a path) with a root, a tip and rotor inertias; every other field its default.
model::ChainSpec spec_of(const std::string& urdf, const std::string& root = "", const std::string& tip = "",
                         std::map<std::string, double> rotor = {}) {
  model::ChainSpec spec;
  spec.urdf = urdf;
  spec.root_link = root;
  spec.tip_link = tip;
  spec.rotor_inertia = std::move(rotor);
  return spec;
}

// Loads `urdf` and returns the error message, failing if there is none.
// The message must name `source` (default: the URDF file).
std::string load_error(const std::string& urdf, const std::string& root = "", const std::string& tip = "",
                       std::map<std::string, double> rotor = {}, const std::string& source = "") {
  test::TempDir dir;
  const std::string path = dir.write("robot.urdf", urdf);
  try {
    model::load_chain(spec_of(path, root, tip, rotor));
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(source.empty() ? path : source), std::string::npos) << "message does not name the source: " << message;
    return message;
  }
  ADD_FAILURE() << "no error for:\n" << urdf;
  return "";
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' missing in: " << text;
}

TEST(ModelErrors, ValidArmLoads) {
  test::TempDir dir;
  const model::Chain chain = model::load_chain(spec_of(dir.write("robot.urdf", arm())));
  EXPECT_EQ(chain.dof(), 2u);
  EXPECT_EQ(chain.tip_link, "l2");
}

// The sweeps compute one triangle of every symmetric block, so the loaded inertias must be
// exactly symmetric: R I R^T of a full tensor under a skew rotation is not, in
// floating point, unless the loader makes it so.
TEST(ModelErrors, LoadedInertiasAreExactlySymmetric) {
  const std::string skew_inertial =
      R"(<inertial><origin xyz="0.05 -0.02 0.11" rpy="0.3 0.7 1.1"/><mass value="1.7"/>)"
      R"(<inertia ixx="0.1" ixy="0.013" ixz="0.021" iyy="0.2" iyz="0.037" izz="0.25"/></inertial>)";
  test::TempDir dir;
  const model::Chain chain = model::load_chain(spec_of(dir.write("robot.urdf", arm("revolute", skew_inertial))));
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const auto& M = chain.bodies[i].inertia;
    EXPECT_TRUE(M.A == M.A.transpose()) << chain.bodies[i].link << ":\n" << M.A;
    EXPECT_TRUE(M.C == M.C.transpose()) << chain.bodies[i].link;
  }
}

// XML that is not well-formed is reported at its line and column (model/xml_syntax.hpp); well-formed
// XML that urdfdom rejects, with urdfdom's reason.
TEST(ModelErrors, MalformedXml) {
  const std::string message = load_error("<robot name='x'><link name='a'></robot");
  // The end tag </robot> comes while <link> is open: said where <link> opened (xml_syntax).
  expect_contains(message, "robot.urdf:1:17: <link>: not well-formed: this element has no end tag (</robot> at 1:32 comes first)");
  const std::string urdf = load_error("<robot name='x'>\n  <link name='a'/>\n  <joint name='j' type='sliding'/>\n</robot>");
  expect_contains(urdf, "robot.urdf: <robot>: not a valid URDF");
}

TEST(ModelErrors, MissingFile) {
  try {
    model::load_chain(spec_of("/nonexistent/robot.urdf"));
    FAIL();
  } catch (const InputError& e) {
    expect_contains(e.what(), "/nonexistent/robot.urdf");
    expect_contains(e.what(), "cannot be opened");
  }
}

TEST(ModelErrors, FloatingAndPlanarJointsAreRejected) {
  const std::string planar = load_error(arm("planar"));
  expect_contains(planar, "joint 'j2'");
  expect_contains(planar, "planar joints are not supported");
  // A floating joint: the message says how to model a free-floating robot instead.
  const std::string floating = load_error(arm("floating"));
  expect_contains(floating, "joint 'j2'");
  expect_contains(floating, "a floating joint inside the chain is not supported");
  expect_contains(floating, "as the root and let the base float (scene: base: floating");
}

// A floating base (F5): six coordinates before the root link, which becomes body 6 with its own
// inertial and every link fixed to it (a sensor on the base moves with it: lumped, not left out);
// a URDF joint named like one of the six is refused.
TEST(ModelErrors, FloatingBaseCarriesTheLinksFixedToTheRoot) {
  test::TempDir dir;
  const std::string sensor =
      R"(<joint name="mount" type="fixed"><parent link="base"/><child link="sensor"/><origin xyz="0 0 0.1"/></joint>
  <link name="sensor"><inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>)";
  model::ChainSpec spec;
  spec.urdf = dir.write("robot.urdf", arm("revolute", R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)", sensor));
  spec.floating_base = true;
  const model::Chain chain = model::load_chain(spec);
  ASSERT_EQ(chain.dof(), 8u);
  EXPECT_EQ(chain.base_coordinates(), 6u);
  for (std::size_t i = 1; i <= 6; ++i) EXPECT_TRUE(chain.joints[i].floating_base_coordinate) << i;
  EXPECT_EQ(chain.frames.at("base").body, 6u);
  EXPECT_EQ(chain.frames.at("sensor").body, 6u);
  EXPECT_EQ(chain.bodies[6].mass, 0.5);
  // A massive root link (planar_rpr's base_link, 5 kg) is body 6's; the world frame carries nothing.
  model::ChainSpec planar;
  planar.urdf = std::string(SWEEPGEN_SOURCE_DIR) + "/robots/planar/planar_rpr.urdf";
  planar.floating_base = true;
  const model::Chain free = model::load_chain(planar);
  EXPECT_EQ(free.bodies[6].mass, 5.0);
  EXPECT_EQ(free.bodies[0].mass, 0.0);
  EXPECT_TRUE(chain.left_out.empty());

  spec.urdf = dir.write("taken.urdf", arm("revolute", R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)",
                                          R"(<joint name="floating_base_pz" type="fixed"><parent link="l2"/><child link="l3"/></joint><link name="l3"/>)"));
  try {
    model::load_chain(spec);
    ADD_FAILURE() << "a joint named floating_base_pz was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), "joint 'floating_base_pz'");
    expect_contains(e.what(), "the name is taken by the floating base's coordinates");
  }
}

// A <mimic> is loaded as a joint of its own (tests/test_model_changes.cpp), but it must name a joint
// of the URDF and finite numbers.
TEST(ModelErrors, MimicOfAMissingJoint) {
  std::string urdf = arm();
  urdf.replace(urdf.find("<axis xyz=\"0 1 0\"/>"), 0, "<mimic joint=\"j_1\" multiplier=\"1\"/>");
  const std::string message = load_error(urdf);
  expect_contains(message, "joint 'j2' <mimic>");
  expect_contains(message, "follows joint 'j_1', which the URDF does not have");
  expect_contains(message, "did you mean 'j1'");
}

// A joint that follows itself, or joints that follow each other, have no position to follow:
// refused, naming the joints (not loaded as independent joints with a note).
TEST(ModelErrors, MimicOfItselfOrInACycle) {
  std::string itself = arm();
  itself.replace(itself.find("<axis xyz=\"0 1 0\"/>"), 0, "<mimic joint=\"j2\"/>");
  const std::string self_message = load_error(itself);
  expect_contains(self_message, "joint 'j2' <mimic>: follows the joint itself");
  std::string cycle = arm();
  cycle.replace(cycle.find("<axis xyz=\"0 0 1\"/>"), 0, "<mimic joint=\"j2\"/>");
  cycle.replace(cycle.find("<axis xyz=\"0 1 0\"/>"), 0, "<mimic joint=\"j1\"/>");
  const std::string cycle_message = load_error(cycle);
  expect_contains(cycle_message, "joint 'j1' <mimic>: the <mimic>s of joints 'j1' -> 'j2' -> 'j1' form a cycle");
}

// urdfdom reads a joint's first <mimic> and drops a second without a word: refused at its line.
TEST(ModelErrors, ASecondMimicInAJoint) {
  std::string urdf = arm();
  urdf.replace(urdf.find("<axis xyz=\"0 1 0\"/>"), 0, "<mimic joint=\"j1\"/>\n    <mimic joint=\"j1\" multiplier=\"2\"/>");
  const std::string message = load_error(urdf);
  expect_contains(message, "robot.urdf:9:5: joint 'j2': a second <mimic> (the first at line 8); a joint follows one other joint");
}

TEST(ModelErrors, UnknownLinksGetANearestNameHint) {
  const std::string message = load_error(arm(), "base", "l3");
  expect_contains(message, "tip link 'l3'");
  expect_contains(message, "did you mean 'l");
  expect_contains(load_error(arm(), "bsae", "l2"), "did you mean 'base'");
}

TEST(ModelErrors, DisconnectedRootAndTip) {
  const std::string message = load_error(arm(), "l2", "l1");
  expect_contains(message, "not connected");
}

const std::string kUnitInertial =
    R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)";

TEST(ModelErrors, TwoMovingBranchesNeedATip) {
  const std::string message = load_error(arm("revolute", kUnitInertial,
                                             R"(<joint name="j3" type="revolute"><parent link="l1"/><child link="side"/>
    <axis xyz="1 0 0"/><limit effort="1" velocity="1" lower="-1" upper="1"/></joint><link name="side"/>)"));
  expect_contains(message, "link 'l1'");
  expect_contains(message, "branches");
  expect_contains(message, "2 of them with moving joints below");
}

// A fixed side link (a sensor) does not end the default chain: it is lumped into l1.
TEST(ModelErrors, FixedSideBranchIsLumpedNotAnError) {
  test::TempDir dir;
  model::ChainSpec spec;
  spec.urdf = dir.write("robot.urdf", arm("revolute", kUnitInertial,
                                          R"(<joint name="j3" type="fixed"><parent link="l1"/><child link="side"/></joint>
    <link name="side">)" + kUnitInertial + "</link>"));
  const model::Chain chain = model::load_chain(spec);
  EXPECT_EQ(chain.tip_link, "l2");
  ASSERT_EQ(chain.bodies[1].lumped_links.size(), 1u);
  EXPECT_EQ(chain.bodies[1].lumped_links[0].link, "side");
  EXPECT_EQ(chain.bodies[1].mass, 2.0);
}

// Locked positions (ChainSpec::locked_joints) that cannot be applied: each names the entry's
// location, the joint and the reason.
std::string lock_error(const std::string& extra, const std::string& joint, double position) {
  test::TempDir dir;
  model::ChainSpec spec;
  spec.urdf = dir.write("robot.urdf", arm("revolute", kUnitInertial, extra));
  spec.tip_link = "l2";
  spec.locked_joints[joint] = position;
  spec.locked_joint_locations[joint] = "scene.yaml:4:3";
  try {
    model::load_chain(spec);
  } catch (const InputError& e) {
    const std::string message = e.what();
    expect_contains(message, "scene.yaml:4:3: locked_joints." + joint + ": ");
    return message;
  }
  ADD_FAILURE() << "no error for locking " << joint;
  return "";
}

TEST(ModelErrors, LockedJointsThatCannotBeLocked) {
  const std::string finger = R"(<joint name="finger" type="prismatic"><parent link="l2"/><child link="tip_finger"/>
    <axis xyz="0 1 0"/><limit effort="1" velocity="1" lower="0" upper="0.04"/></joint><link name="tip_finger">)" +
                             kUnitInertial + "</link>";
  expect_contains(lock_error(finger, "fingr", 0.01), "no joint of that name");
  expect_contains(lock_error(finger, "fingr", 0.01), "did you mean 'finger'");
  expect_contains(lock_error(finger, "j2", 0.1), "is a moving joint of the chain; only joints off the chain, and <mimic> joints, are locked");
  expect_contains(lock_error(finger, "finger", 0.05), "outside the joint's limits [0, 0.04]");
  expect_contains(lock_error(finger, "finger", std::nan("")), "not finite");
  const std::string on_base = R"(<joint name="turntable" type="continuous"><parent link="base"/><child link="table"/>
    <axis xyz="0 0 1"/></joint><link name="table"/>)";
  expect_contains(lock_error(finger + on_base, "turntable", 1.0), "not carried by a moving body");
}

TEST(ModelErrors, OffChainJointsThatCannotBeHeld) {
  const std::string floating = R"(<joint name="loose" type="floating"><parent link="l2"/><child link="cup"/></joint><link name="cup"/>)";
  expect_contains(load_error(arm("revolute", kUnitInertial, floating), "", "l2"), "joint 'loose'");
  expect_contains(load_error(arm("revolute", kUnitInertial, floating), "", "l2"), "cannot be locked at one position");
}

TEST(ModelErrors, NonPhysicalInertia) {
  const std::string negative = load_error(arm("revolute", R"(<inertial><mass value="1"/><inertia ixx="-0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)"));
  expect_contains(negative, "link 'l2' <inertial>");
  expect_contains(negative, "not positive semi-definite");
  const std::string triangle = load_error(arm("revolute", R"(<inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.05"/></inertial>)"));
  expect_contains(triangle, "triangle inequality");
  const std::string mass = load_error(arm("revolute", R"(<inertial><mass value="-1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>)"));
  expect_contains(mass, "negative mass");
}

TEST(ModelErrors, MasslessLastBodyWithoutRotorInertia) {
  const std::string message = load_error(arm("revolute", ""));
  expect_contains(message, "joint 'j2'");
  expect_contains(message, "D_N = 0");
  // A point mass on the joint axis has no inertia about it either.
  expect_contains(load_error(arm("revolute", R"(<inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>)")),
                  "D_N = 0");
  // A rotor inertia makes the same chain valid.
  test::TempDir dir;
  EXPECT_NO_THROW(model::load_chain(spec_of(dir.write("robot.urdf", arm("revolute", "")), "", "", {{"j2", 0.01}})));
}

// Crossed position limits admit no position: random states draw from them and locked joints are
// clamped into them (std::clamp requires lower <= upper), so they are refused, on the chain and
// off it; equal limits (a joint held still) are accepted.
TEST(ModelErrors, CrossedJointLimits) {
  std::string crossed = arm();
  crossed.replace(crossed.find(R"(lower="-1" upper="1")"), std::string(R"(lower="-1" upper="1")").size(),
                  R"(lower="1" upper="-1")");
  const std::string message = load_error(crossed);
  expect_contains(message, "joint 'j1' <limit>");
  expect_contains(message, "lower 1 is above upper -1");
  const std::string finger = R"(<joint name="finger" type="prismatic"><parent link="l2"/><child link="tip_finger"/>
    <axis xyz="0 1 0"/><limit effort="1" velocity="1" lower="0.04" upper="0"/></joint><link name="tip_finger">)" +
                             kUnitInertial + "</link>";
  expect_contains(load_error(arm("revolute", kUnitInertial, finger), "", "l2"), "joint 'finger' <limit>: lower 0.04 is above upper 0");
  std::string equal = arm();
  equal.replace(equal.find(R"(lower="-1" upper="1")"), std::string(R"(lower="-1" upper="1")").size(),
                R"(lower="0.5" upper="0.5")");
  test::TempDir dir;
  EXPECT_NO_THROW(model::load_chain(spec_of(dir.write("robot.urdf", equal))));
}

TEST(ModelErrors, NonFiniteNumbers) {
  for (const std::string bad : {"nan", "inf", "1e999"}) {
    std::string urdf = arm();
    urdf.replace(urdf.find("<mass value=\"1\"/>"), std::string("<mass value=\"1\"/>").size(), "<mass value=\"" + bad + "\"/>");
    const std::string message = load_error(urdf);
    // urdfdom rejects some spellings itself ("is not a float"); the rest reach our finiteness check.
    EXPECT_TRUE(message.find("not finite") != std::string::npos || message.find("not a float") != std::string::npos)
        << message;
  }
}

TEST(ModelErrors, RotorInertiaForUnknownJoint) {
  const std::string message = load_error(arm(), "", "", {{"j3", 0.1}}, "--rotor-inertia");
  expect_contains(message, "--rotor-inertia");
  expect_contains(message, "joint 'j3'");
  expect_contains(message, "did you mean");
  expect_contains(load_error(arm(), "", "", {{"j2", -1}}, "--rotor-inertia"), "finite number >= 0");
}

// Names from the input are quoted and escaped (model/error.hpp: quote_name), so that one holding
// ": ", a quote or a line break cannot blur where the element ends and the reason begins.
TEST(ModelErrors, NamesAreQuotedAndEscaped) {
  expect_contains(load_error(arm(), "", "a: b'c\nd"), ": tip link 'a: b\\'c\\nd': no such link");
  EXPECT_EQ(quote_name(std::string("x\0\x01\\y", 5)), "'x\\0\\x01\\\\y'");
  EXPECT_EQ(element_path("locked_joints", "j2"), "locked_joints.j2");
  EXPECT_EQ(element_path("locked_joints", "j 2: x"), "locked_joints.'j 2: x'");
}

TEST(ModelErrors, ChainWithoutMovingJoint) {
  expect_contains(load_error(arm(), "l1", "l1"), "no moving joint");
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

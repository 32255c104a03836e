// What the loader takes differently from the URDF as written, or leaves to the application, and
// that it says so (model/model_notes.hpp): <mimic> joints as joints of their own (or
// locked), the quarter-turn rule and its switch, axes scaled to unit length, inertias made
// symmetric. Each is listed, and where it can be turned off, off gives the literal model.
#include <gtest/gtest.h>

#include <cmath>

#include "model/model_notes.hpp"
#include "model/urdf_loader.hpp"
#include "support/temp_dir.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

const std::string kInertial =
    R"(<inertial><origin xyz="0 0 0.02"/><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>)";

// A one-joint arm with a two-finger hand as robots ship it: finger_right_joint a <mimic> of
// finger_left_joint (multiplier 1, offset 0.01). `j1_origin` and `j1_axis` are j1's attributes.
std::string gripper_arm(const std::string& j1_origin = R"(xyz="0 0 0.1" rpy="0 0 0")",
                        const std::string& j1_axis = "0 0 1") {
  return R"(<robot name="gripper_arm">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="hand"/><origin )" + j1_origin + R"(/>
    <axis xyz=")" + j1_axis + R"("/><limit effort="10" velocity="1" lower="-2" upper="2"/></joint>
  <link name="hand">)" + kInertial + R"(</link>
  <joint name="finger_left_joint" type="prismatic"><parent link="hand"/><child link="finger_left"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit effort="20" velocity="0.2" lower="0" upper="0.04"/></joint>
  <link name="finger_left">)" + kInertial + R"(</link>
  <joint name="finger_right_joint" type="prismatic"><parent link="hand"/><child link="finger_right"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 -1 0"/><limit effort="20" velocity="0.2" lower="0" upper="0.04"/>
    <mimic joint="finger_left_joint" multiplier="1" offset="0.01"/></joint>
  <link name="finger_right">)" + kInertial + R"(</link>
</robot>)";
}

model::Chain load(const std::string& urdf, const std::string& tip, const std::vector<std::string>& branch_tips = {},
                  std::map<std::string, double> locked = {}, bool snap = true) {
  test::TempDir dir;
  model::ChainSpec spec;
  spec.urdf = dir.write("robot.urdf", urdf);
  spec.tip_link = tip;
  spec.branch_tips = branch_tips;
  spec.locked_joints = std::move(locked);
  spec.snap_quarter_turns = snap;
  return model::load_chain(spec);
}

// The one note that contains `part`; fails unless exactly one does.
std::string note_with(const model::Chain& chain, const std::string& part) {
  std::string found;
  int count = 0;
  std::string all;
  for (const std::string& line : model::model_notes(chain)) {
    all += line + "\n";
    if (line.find(part) != std::string::npos) {
      found = line;
      ++count;
    }
  }
  EXPECT_EQ(count, 1) << "'" << part << "' in the notes:\n" << all;
  return found;
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "'" << part << "' missing in: " << text;
}

TEST(MimicJoints, AMimicOnATipPathIsAJointOfItsOwnAndSaidSo) {
  const model::Chain chain = load(gripper_arm(), "finger_left", {"finger_right"});
  ASSERT_EQ(chain.dof(), 3u);
  EXPECT_EQ(chain.joint_index("finger_right_joint"), 3u);
  EXPECT_EQ(chain.parent[3], 1u);  // both fingers on the hand: a tree
  ASSERT_EQ(chain.mimics.size(), 1u);
  EXPECT_EQ(chain.mimics[0].joint, "finger_right_joint");
  EXPECT_EQ(chain.mimics[0].source, "finger_left_joint");
  EXPECT_EQ(chain.mimics[0].multiplier, 1.0);
  EXPECT_EQ(chain.mimics[0].offset, 0.01);
  const std::string note = note_with(chain, "<mimic>");
  expect_contains(note, "joint 'finger_right_joint' is a <mimic> of 'finger_left_joint' (q = 1 q_source + 0.01)");
  expect_contains(note, "a joint of its own, joint 3 of the chain; the application enforces the coupling");
}

// Today's refusal case: the mimic's source on the chain, the mimic itself off it. It is locked as
// every joint off the chain is (0 clamped into [0, 0.04]), and said to be a mimic.
TEST(MimicJoints, AMimicOffTheChainIsLockedLikeEveryJointOffIt) {
  const model::Chain chain = load(gripper_arm(), "finger_left");
  ASSERT_EQ(chain.dof(), 2u);
  ASSERT_EQ(chain.locked_joints.size(), 1u);
  EXPECT_EQ(chain.locked_joints[0].name, "finger_right_joint");
  EXPECT_EQ(chain.locked_joints[0].position, 0.0);
  EXPECT_EQ(chain.frames.at("finger_right").body, 1u);
  expect_contains(note_with(chain, "<mimic>"), "here it is locked at 0 (default); the coupling is not modelled");
}

// The scene's locked_joints may lock a mimic on the tree instead: its link is lumped into the hand
// at the given position, as a fixed joint there would put it.
TEST(MimicJoints, LockedJointsLockAMimicOnTheTree) {
  const model::Chain chain = load(gripper_arm(), "finger_left", {"finger_right"}, {{"finger_right_joint", 0.03}});
  ASSERT_EQ(chain.dof(), 2u);
  EXPECT_EQ(chain.joint_index("finger_right_joint"), 0u);
  const model::Frame& right = chain.frames.at("finger_right");
  EXPECT_EQ(right.body, 1u);
  // Hand frame to finger frame: 0.05 up, then 0.03 along the axis (0, -1, 0).
  EXPECT_EQ(right.X.r, model::Vec3(0, -0.03, 0.05));
  EXPECT_EQ(chain.bodies[1].mass, 0.2);  // the hand and the locked finger
  expect_contains(note_with(chain, "<mimic>"), "here it is locked at 0.03 (locked_joints)");
  // The same robot with that finger fixed at the position: the same inertia on the hand.
  const std::string moving = R"(type="prismatic"><parent link="hand"/><child link="finger_right"/>
    <origin xyz="0 0 0.05"/>)";
  std::string fixed = gripper_arm();
  fixed.replace(fixed.find(moving), moving.size(), R"(type="fixed"><parent link="hand"/><child link="finger_right"/>
    <origin xyz="0 -0.03 0.05"/>)");
  const model::Chain reference = load(fixed, "finger_left");
  EXPECT_EQ(chain.bodies[1].inertia.A, reference.bodies[1].inertia.A);
  EXPECT_EQ(chain.bodies[1].inertia.B, reference.bodies[1].inertia.B);
}

// A robot file's pi/2 as 1.57079632679: 4.8966192e-12 rad below pi/2.
constexpr double kShortHalfPiDeviation = 4.8966192313216916e-12;
// The deviation is the sine of the angle between the two rotations, from their entries, each
// rounded by at most eps/2 = 1.1e-16 in R and in the quaternion's matrix: a few of those, 1e-15.
constexpr double kDeviationRounding = 1e-15;

TEST(QuarterTurns, EveryOriginTheRuleChangesIsListed) {
  const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy="1.57079632679 0 -3.14159265359")"), "finger_left");
  ASSERT_EQ(chain.changes.size(), 1u);
  const model::ModelChange& change = chain.changes[0];
  EXPECT_EQ(change.element, "joint 'j1' <origin>");
  EXPECT_EQ(change.written, "rpy '1.57079632679 0 -3.14159265359'");  // as written, not as urdfdom reads it back
  EXPECT_EQ(change.taken_as, "(pi/2, 0, -pi)");  // the same rotation as urdfdom's (pi/2, 0, pi), as written
  EXPECT_EQ(change.unit, "rad");
  // Both angles are off by 4.9e-12 and 2.1e-13 rad about different axes.
  EXPECT_NEAR(change.deviation, std::hypot(kShortHalfPiDeviation, 3.14159265359 - M_PI), kDeviationRounding);
  // Taken exactly: a signed permutation.
  const model::Mat3& E = chain.joints[1].tree_transform.E;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(E(r, c) == 0 || std::abs(E(r, c)) == 1) << E;
  expect_contains(note_with(chain, "joint 'j1' <origin>"), "taken as (pi/2, 0, -pi) (changed by ");
  expect_contains(note_with(chain, "the quarter-turn rule"), "snap_quarter_turns: false");
}

// A pitch of pi reads back from urdfdom's quaternion as roll and yaw of pi, the same rotation: the
// listing gives the rotation taken in the form the file writes it.
TEST(QuarterTurns, TheRotationTakenIsSaidAsWritten) {
  const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy="0 3.14159265359 0")"), "finger_left");
  ASSERT_EQ(chain.changes.size(), 1u);
  EXPECT_EQ(chain.changes[0].written, "rpy '0 3.14159265359 0'");
  EXPECT_EQ(chain.changes[0].taken_as, "(0, pi, 0)");
  expect_contains(note_with(chain, "joint 'j1' <origin>"), "rpy '0 3.14159265359 0' taken as (0, pi, 0)");
  // Exactly Ry(pi): a signed permutation.
  model::Mat3 expected;
  expected << -1, 0, 0, 0, 1, 0, 0, 0, -1;
  EXPECT_EQ(chain.joints[1].tree_transform.E, expected);
  // An angle that is no quarter turn keeps the triple taken from urdfdom's angles.
  const model::Chain mixed = load(gripper_arm(R"(xyz="0 0 0.1" rpy="1.57079632679 0.3 0")"), "finger_left");
  ASSERT_EQ(mixed.changes.size(), 1u);
  EXPECT_EQ(mixed.changes[0].taken_as.rfind("(pi/2, 0.3", 0), 0u) << mixed.changes[0].taken_as;
}

// A pitch within 1e-5 of pi/2 urdfdom reads back as pi/2 exactly; the deviation, measured
// between the rotations, still shows.
TEST(QuarterTurns, APitchNearAQuarterTurnIsListedWithItsDeviation) {
  const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy="0 1.57079632679 0")"), "finger_left");
  ASSERT_EQ(chain.changes.size(), 1u);
  EXPECT_EQ(chain.changes[0].taken_as, "(0, pi/2, 0)");
  EXPECT_NEAR(chain.changes[0].deviation, kShortHalfPiDeviation, kDeviationRounding);
}

TEST(QuarterTurns, TurnedOffTheFileIsTakenLiterally) {
  for (const std::string& rpy : std::vector<std::string>{"1.57079632679 0 0", "0 1.57079632679 0"}) {
    const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy=")" + rpy + "\""), "finger_left", {}, {}, false);
    EXPECT_TRUE(chain.changes.empty());
    EXPECT_EQ(chain.exact_quarter_turns, 0u);
    // cos(1.57079632679) = 4.8966192e-12 stays in the rotation: entry (1, 1) for a roll, (0, 0) for
    // a pitch; each rounded once in the quaternion and once in its matrix (kDeviationRounding).
    const model::Mat3& E = chain.joints[1].tree_transform.E;
    const int k = rpy[0] == '1' ? 1 : 0;
    EXPECT_NEAR(E(k, k), kShortHalfPiDeviation, kDeviationRounding) << rpy << "\n" << E;
    EXPECT_NE(E(k, k), 0.0);
    for (const std::string& line : model::model_notes(chain)) EXPECT_EQ(line.find("quarter"), std::string::npos) << line;
  }
}

// pi/2 written at full precision differs from pi/2 only by the double's rounding (6e-17 rad): taken
// exactly, counted in one note rather than listed origin by origin.
TEST(QuarterTurns, FullPrecisionQuarterTurnsAreCounted) {
  const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy="1.5707963267948966 0 3.141592653589793")"), "finger_left");
  EXPECT_TRUE(chain.changes.empty());
  EXPECT_EQ(chain.exact_quarter_turns, 1u);
  expect_contains(note_with(chain, "<origin>s whose angles are multiples of pi/2"), "1 <origin>s");
}

TEST(Normalisations, AnAxisScaledToUnitLengthIsListed) {
  const model::Chain chain = load(gripper_arm(R"(xyz="0 0 0.1" rpy="0 0 0")", "0 0 2"), "finger_left");
  ASSERT_EQ(chain.changes.size(), 1u);
  EXPECT_EQ(chain.changes[0].element, "joint 'j1' <axis>");
  EXPECT_EQ(chain.changes[0].written, "(0, 0, 2)");
  EXPECT_EQ(chain.changes[0].taken_as, "the unit vector (0, 0, 1)");
  EXPECT_EQ(chain.changes[0].deviation, 0.5);  // 1 - 1/|axis|
  expect_contains(note_with(chain, "<axis>"), "joint 'j1' <axis>: (0, 0, 2) taken as the unit vector (0, 0, 1)");
}

// R I R^T of a full tensor under a skew rotation is not symmetric in floating point; the loader
// mirrors the upper triangle (tests/test_model_errors.cpp, LoadedInertiasAreExactlySymmetric) and
// says by how much that changed the lower one.
TEST(Normalisations, AnInertiaMadeSymmetricIsListed) {
  std::string urdf = gripper_arm();
  urdf.replace(urdf.find(kInertial), kInertial.size(),
               R"(<inertial><origin xyz="0.05 -0.02 0.11" rpy="0.3 0.7 1.1"/><mass value="1.7"/>)"
               R"(<inertia ixx="0.1" ixy="0.013" ixz="0.021" iyy="0.2" iyz="0.037" izz="0.25"/></inertial>)");
  const model::Chain chain = load(urdf, "finger_left");
  ASSERT_EQ(chain.changes.size(), 1u);
  EXPECT_EQ(chain.changes[0].element, "link 'hand' <inertial>");
  EXPECT_EQ(chain.changes[0].unit, "kg m^2");
  // Rounding of entries of size 0.3: a few eps of them, never more.
  EXPECT_GT(chain.changes[0].deviation, 0.0);
  EXPECT_LT(chain.changes[0].deviation, 1e-15);
  expect_contains(note_with(chain, "made exactly symmetric"), "the inertia tensors about their link origins of link 'hand' made");
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

// Links off the chain count (generator/model/chain.hpp): a URDF whose chain links carry fixed
// side links, a moving side branch and a hand with fingers beyond the tip
// (tests/data/side_branches.urdf), checked against an oracle that reads the whole tree with its
// own loader: kdl_parser's KDL::Tree and KDL's TreeIdSolver_RNE (inverse dynamics over every
// segment, fixed ones included). No code of sweepgen's loader is shared with the oracle.
//
// Round trip, per random state: sweepgen's reference solver gives q̈ for (q, q̇, τff, F_ext) with
// Nc = 0; KDL's inverse dynamics of the whole tree at (q, q̇, q̈), with every off-chain moving
// joint at its locked position and at rest, and the same external wrenches on the same links,
// must give back τff at the chain's joints.
//
// Conventions: TreeIdSolver_RNE takes f_ext per segment in that segment's frame (= the URDF
// link frame), as wrenches acting on the segment, the same as sweepgen's external forces (link
// frame, about its origin); KDL's Wrench is (force, torque), sweepgen's Force [moment; force].
// KDL's `grav` is the gravity vector itself, sweepgen's SolverOptions::gravity likewise; the
// root 'base' sits in 'world' without rotation, so both frames agree.
#include <gtest/gtest.h>

#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

#include <iostream>
#include <map>

#include "model/urdf_loader.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_problem.hpp"

namespace sweepgen {
namespace {

const std::string kUrdf = test::source_path("tests/data/side_branches.urdf");
constexpr double kSideJointLock = 0.7;  // the scene's position for side_joint; the fingers keep the default

// ‖τ_KDL − τff‖∞ / max(1, ‖τff‖∞). The forward solve (ABA) and KDL's RNE are both backward
// stable: each returns the exact answer of a problem perturbed by c·n·ε relative to the torques,
// inertias and transforms involved (‖τ‖ ≤ 100 N·m, ‖M‖·‖q̈‖ of the same order here), with c·n of
// a few hundred for 4 joints and 17 links: ~1e-13. 1e-11 leaves a margin of 100, far below what
// the negative controls below miss by (a branch or the fingers held elsewhere: > kMissed).
constexpr double kTorqueTolerance = 1e-11;
// The negative controls must miss τff by at least this much.
constexpr double kMissed = 1e-4;
constexpr int kStates = 500;

model::Chain load(double side_joint_lock) {
  model::ChainSpec spec;
  spec.urdf = kUrdf;
  spec.root_link = "base";
  spec.tip_link = "wrist";
  spec.locked_joints["side_joint"] = side_joint_lock;
  return model::load_chain(spec);
}

KDL::Tree kdl_tree() {
  KDL::Tree tree;
  if (!kdl_parser::treeFromFile(kUrdf, tree)) throw std::runtime_error("kdl_parser cannot read " + kUrdf);
  return tree;
}

// KDL's joint index (q_nr) of every moving joint of the tree, by joint name.
std::map<std::string, unsigned> kdl_joint_indices(const KDL::Tree& tree) {
  std::map<std::string, unsigned> indices;
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Joint& joint = GetTreeElementSegment(element).getJoint();
    if (joint.getType() != KDL::Joint::None) indices[joint.getName()] = GetTreeElementQNr(element);
  }
  return indices;
}

KDL::Wrench to_kdl(const spatial::Force<double>& f) {
  return KDL::Wrench(KDL::Vector(f.force.x(), f.force.y(), f.force.z()),
                     KDL::Vector(f.moment.x(), f.moment.y(), f.moment.z()));
}

// Worst torque error of the round trip over kStates states: the chain `chain` solved forward,
// the whole tree (with `kdl_locks` for the off-chain joints) backward.
double worst_round_trip(const model::Chain& chain, const std::map<std::string, double>& kdl_locks, unsigned seed) {
  const KDL::Tree tree = kdl_tree();
  const auto indices = kdl_joint_indices(tree);
  KDL::TreeIdSolver_RNE inverse_dynamics(tree, KDL::Vector(0, 0, -9.81));

  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  // On a lumped fixed side link, and on a finger behind a locked joint beyond the tip.
  layout.external_forces = {{"on_sensor", "sensor"}, {"on_finger", "finger_left"}};
  layout.decompose_all();
  solver::ReferenceSolver<double> reference(chain, layout);
  test::RandomProblem random(seed);

  double worst = 0;
  for (int s = 0; s < kStates; ++s) {
    const Eigen::VectorXd q = random.positions(chain), qd = random.velocities(chain);
    reference.drivers().torques[0] = random.torques(chain);
    reference.drivers().external_forces[0] = random.wrench();
    reference.drivers().external_forces[1] = random.wrench();
    reference.outward(q, qd);
    reference.decompose();
    const Eigen::VectorXd qdd = reference.solve(solver::Policy::original, {}).qdd;
    EXPECT_EQ(reference.status(), solver::status_ok);

    const unsigned n = tree.getNrOfJoints();
    KDL::JntArray kq(n), kqd(n), kqdd(n), torques(n);
    for (const auto& [name, position] : kdl_locks) kq(indices.at(name)) = position;
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const unsigned k = indices.at(chain.joints[i].name);
      kq(k) = q[i - 1];
      kqd(k) = qd[i - 1];
      kqdd(k) = qdd[i - 1];
    }
    const KDL::WrenchMap f_ext{{"sensor", to_kdl(reference.drivers().external_forces[0])},
                               {"finger_left", to_kdl(reference.drivers().external_forces[1])}};
    EXPECT_GE(inverse_dynamics.CartToJnt(kq, kqd, kqdd, f_ext, torques), 0);

    const Eigen::VectorXd& tau = reference.drivers().torques[0];
    double error = 0;
    for (std::size_t i = 1; i <= chain.dof(); ++i)
      error = std::max(error, std::abs(torques(indices.at(chain.joints[i].name)) - tau[i - 1]));
    worst = std::max(worst, error / std::max(1.0, tau.lpNorm<Eigen::Infinity>()));
  }
  return worst;
}

// The loader's lumping as the test expects it from the URDF, before any numbers.
TEST(OffChain, EveryLinkIsLumpedLockedOrLeftOut) {
  const model::Chain chain = load(kSideJointLock);
  ASSERT_EQ(chain.dof(), 4u);
  const auto names = [](const model::Body& body) {
    std::vector<std::string> links;
    for (const auto& lumped : body.lumped_links) links.push_back(lumped.link);
    return links;
  };
  EXPECT_EQ(names(chain.bodies[1]), (std::vector<std::string>{"sensor"}));
  ASSERT_EQ(names(chain.bodies[2]), (std::vector<std::string>{"side_arm", "side_tool"}));
  EXPECT_EQ(names(chain.bodies[3]), (std::vector<std::string>{}));
  ASSERT_EQ(names(chain.bodies[4]), (std::vector<std::string>{"hand", "camera", "finger_left", "finger_right"}));
  EXPECT_EQ(chain.bodies[2].lumped_links[1].locked_joint, "side_joint");
  EXPECT_EQ(chain.bodies[4].lumped_links[1].locked_joint, "");
  EXPECT_DOUBLE_EQ(chain.bodies[4].mass, 0.35 + 0.8 + 0.1 + 0.15 + 0.15);
  ASSERT_EQ(chain.locked_joints.size(), 3u);
  EXPECT_EQ(chain.locked_joints[0].name, "side_joint");
  EXPECT_EQ(chain.locked_joints[0].position, kSideJointLock);
  EXPECT_TRUE(chain.locked_joints[0].from_scene);
  // Not given: 0 clamped into the finger's limits [0.005, 0.04].
  EXPECT_EQ(chain.locked_joints[1].name, "finger_left_joint");
  EXPECT_EQ(chain.locked_joints[1].position, 0.005);
  EXPECT_FALSE(chain.locked_joints[1].from_scene);
  ASSERT_EQ(chain.left_out.size(), 2u);
  EXPECT_EQ(chain.left_out[0].link, "pedestal");
  EXPECT_EQ(chain.left_out[0].mass, 2.0);
  EXPECT_NE(chain.left_out[0].reason.find("fixed base"), std::string::npos);
  EXPECT_EQ(chain.left_out[1].link, "world");
  EXPECT_NE(chain.left_out[1].reason.find("not below the root"), std::string::npos);
  // Every link of the URDF (as urdfdom counts them) is on the chain, lumped, or left out.
  EXPECT_EQ(chain.frames.size() + chain.left_out.size(), urdf::parseURDFFile(kUrdf)->links_.size());
}

TEST(OffChain, InverseDynamicsOfTheWholeTreeGivesBackTheTorques) {
  const std::map<std::string, double> locks{
      {"side_joint", kSideJointLock}, {"finger_left_joint", 0.005}, {"finger_right_joint", 0.005}};
  const double worst = worst_round_trip(load(kSideJointLock), locks, 11);
  std::cout << "[off-chain] " << kStates << " states, max |tau_KDL - tau_ff| / max(1, |tau_ff|) = " << worst << std::endl;
  EXPECT_LE(worst, kTorqueTolerance);
}

// Negative controls: the oracle sees what the test is for. A side branch locked elsewhere than
// the oracle holds it, and fingers held elsewhere, are each a miss.
TEST(OffChain, OracleSeesAWronglyLockedBranch) {
  const std::map<std::string, double> locks{
      {"side_joint", kSideJointLock}, {"finger_left_joint", 0.005}, {"finger_right_joint", 0.005}};
  const double branch_elsewhere = worst_round_trip(load(-0.5), locks, 12);
  std::map<std::string, double> fingers_open = locks;
  fingers_open["finger_left_joint"] = fingers_open["finger_right_joint"] = 0.04;
  const double fingers_elsewhere = worst_round_trip(load(kSideJointLock), fingers_open, 13);
  std::cout << "[off-chain] negative controls: side branch locked elsewhere " << branch_elsewhere
            << ", fingers held elsewhere " << fingers_elsewhere << std::endl;
  EXPECT_GE(branch_elsewhere, kMissed);
  EXPECT_GE(fingers_elsewhere, kMissed);
}

}  // namespace
}  // namespace sweepgen

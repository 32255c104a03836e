// Trees (generator/model/chain.hpp, docs/derivation.md "Constraint sets"): the bundled dual-arm
// station (robots/dual_panda/dual_panda.urdf: two Pandas on a turning torso, 15 joints), with
// constraint sets on both hands and on an elbow, checked against
//  - KDL's inverse dynamics of the whole URDF tree (kdl_parser's KDL::Tree, TreeIdSolver_RNE):
//    sweepgen's q̈ and its constraint wrenches α_k ν_k, applied on each set's link with the
//    external force, must give back τff at every joint (the round trip; no code of sweepgen's
//    loader or sweeps is shared with it);
//  - the same round trip on floating bases (the quadruped, the mobile Panda), the URDF's tree
//    hung on six KDL joints;
//  - the chain solver (reduction): with the torso fixed (root = torso) the arms share no moving
//    joint, so the tree's q̈ on each arm is the chain solver's on that arm, constrained as the
//    tree's sets on it are.
#include <gtest/gtest.h>

#include <iostream>

#include "model/urdf_loader.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/kdl_tree_dynamics.hpp"
#include "support/random_problem.hpp"
#include "support/rounding_bound.hpp"
#include "support/skip_count.hpp"
#include "support/state_count.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

const Eigen::Vector3d kGravity(0, 0, -9.81);

// The dual Panda from `root` to `tips`.
model::Chain load(const std::string& root, const std::vector<std::string>& tips) {
  return test::load_tree("robots/dual_panda/dual_panda.urdf", root, tips);
}

// Feed-forward torques, a push on the torso (or, torso fixed, on the left upper arm) and the
// given constraint sets, every direction at run time.
solver::DriverLayout layout(const std::string& pushed_link, std::vector<solver::ConstraintSet> sets) {
  solver::DriverLayout l;
  l.torques = {"tau_ff"};
  l.external_forces = {{"push", pushed_link}};
  for (const auto& set : sets) l.constraints += set.count;
  l.sets = std::move(sets);
  l.decompose_all();
  return l;
}


solver::SolveInputs<double> draw(test::RandomProblem& random, const model::Chain& chain, const solver::DriverLayout& l) {
  solver::SolveInputs<double> in;
  in.q = random.positions(chain);
  in.qd = random.velocities(chain);
  in.torques = {random.torques(chain, 0.5)};
  in.wrenches = {random.wrench()};
  for (std::size_t k = 0; k < l.constraints; ++k) in.alpha.push_back(random.unit_direction());
  in.beta.resize(static_cast<Eigen::Index>(l.constraints));
  for (auto& b : in.beta) b = random.uniform(-2, 2);
  return in;
}

// Torques: ‖τ_KDL − τff‖∞ / max(1, ‖τff‖∞, ‖τcmd − τff‖∞), as in test_off_chain_kdl.cpp
// (kTorqueRounding there): both solvers are backward stable, c·n·ε relative to the terms they
// sum, among them the constraint wrenches' (unit α_k, lever arms ≤ 1.5 m here), whose growth is
// γ = ‖ν‖₁ / max(1, ‖τff‖∞, ‖τcmd − τff‖∞). Factor 1000 over 15 joints and 25 links (measured
// worst error/(ε max(1, γ)) is printed as [rounding]); ceiling 1e-6: states with γ > 4.5e6
// are counted as skipped (at most 5%), never judged by a looser bound.
constexpr test::RoundingBound kTorqueRounding{1000, 1e-6};
constexpr double kMaxSkippedShare = 0.05;

// One round trip: KDL's inverse dynamics of sweepgen's q̈ with the push on `pushed_link` and each
// direction's constraint wrench α_k ν_k on its set's link, against τff: the error relative to
// `scale` = max(1, ‖τff‖∞, ‖τcmd − τff‖∞) and the growth max(1, ‖ν‖₁ / scale).
struct RoundTrip {
  double error, growth, scale;
};
RoundTrip round_trip(test::KdlTreeDynamics& kdl, const solver::DriverLayout& l,
                     const solver::ReferenceSolver<double>& reference, const solver::SolveInputs<double>& in,
                     const solver::Solution<double>& sol, const std::string& pushed_link) {
  KDL::WrenchMap wrenches;
  wrenches[pushed_link] += test::to_kdl(in.wrenches[0]);
  for (std::size_t k = 0; k < l.constraints; ++k) {
    const std::string& link = l.sets[reference.model().constraint_set_of[k]].link;
    wrenches[link] += test::to_kdl(in.alpha[k] * sol.nu[static_cast<Eigen::Index>(k)]);
  }
  const Eigen::VectorXd tau = kdl.inverse_dynamics(in.q, in.qd, sol.qdd, wrenches, in.base_rotation);
  const double scale =
      std::max({1.0, in.torques[0].lpNorm<Eigen::Infinity>(), (sol.tau_cmd - in.torques[0]).lpNorm<Eigen::Infinity>()});
  return {(tau - in.torques[0]).lpNorm<Eigen::Infinity>() / scale, std::max(1.0, sol.nu.lpNorm<1>() / scale), scale};
}

TEST(TreeKdl, ConstraintWrenchesAndAccelerationsReproduceTheTorquesOnTheWholeTree) {
  const model::Chain tree = load("station", {"left_panda_hand", "right_panda_hand"});
  ASSERT_EQ(tree.dof(), 15u);
  ASSERT_FALSE(tree.is_chain());
  test::KdlTreeDynamics kdl(tree, kGravity);
  // Both hands, and the left elbow alone (constraint sets on two branches and inside one).
  const std::vector<std::vector<solver::ConstraintSet>> scenes = {
      {},
      {solver::ConstraintSet::on("left_panda_hand", 6), solver::ConstraintSet::on("right_panda_hand", 6)},
      {solver::ConstraintSet::on("left_panda_link4", 2), solver::ConstraintSet::on("right_panda_hand", 3),
       solver::ConstraintSet::on("left_panda_hand", 3)},
  };
  test::RandomProblem random(61);
  test::SkipCount skips("tree round trip through KDL's TreeIdSolver_RNE", kMaxSkippedShare);
  test::WorstRatio worst("tree round trip");
  int negative_controls_missed = 0, states = 0;
  for (const auto& sets : scenes) {
    const solver::DriverLayout l = layout("torso", sets);
    solver::ReferenceSolver<double> reference(tree, l);
    for (int s = 0; s < test::state_count(300); ++s) {
      const solver::SolveInputs<double> in = draw(random, tree, l);
      const solver::Solution<double>& sol = reference.run(in, solver::Policy::original);
      const RoundTrip trip = round_trip(kdl, l, reference, in, sol, "torso");
      ++states;
      if (skips.skip(!kTorqueRounding.judged(trip.growth), "growth beyond the ceiling")) continue;
      worst.add(trip.error, trip.growth);
      EXPECT_LE(trip.error, kTorqueRounding(trip.growth)) << "sets " << sets.size() << " state " << s;
      // Negative control: the wrenches on the wrong links (all on the torso) must miss τff.
      if (l.constraints > 0) {
        KDL::WrenchMap wrong;
        wrong["torso"] += test::to_kdl(in.wrenches[0]);
        for (std::size_t k = 0; k < l.constraints; ++k)
          wrong["torso"] += test::to_kdl(in.alpha[k] * sol.nu[static_cast<Eigen::Index>(k)]);
        const Eigen::VectorXd off = kdl.inverse_dynamics(in.q, in.qd, sol.qdd, wrong);
        if ((off - in.torques[0]).lpNorm<Eigen::Infinity>() / trip.scale < 1e-4) ++negative_controls_missed;
      }
    }
  }
  std::cout << "[tree] " << states << " states on the 15-joint dual Panda\n";
  EXPECT_EQ(negative_controls_missed, 0);
}

// Relative ‖a − b‖∞ / max(1, ‖b‖∞).
double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(1.0, b.lpNorm<Eigen::Infinity>());
}

// The torso fixed: two arms on the fixed base, a tree of two branches that share no moving
// joint. Each branch moves as the chain solver says it does on its own: the same recursion over
// the same bodies, so to a few roundings (the tree sums E over both branches, where the right
// arm's columns are exactly zero; measured: identical to the last bit on this seed).
TEST(TreeKdl, ATreeOfUnconnectedBranchesIsTheChainSolverOnEachBranch) {
  const model::Chain tree = load("torso", {"left_panda_hand", "right_panda_hand"});
  const model::Chain left = load("torso", {"left_panda_hand"}), right = load("torso", {"right_panda_hand"});
  ASSERT_EQ(tree.dof(), 14u);
  const std::vector<solver::ConstraintSet> left_sets = {solver::ConstraintSet::on("left_panda_hand", 4),
                                                        solver::ConstraintSet::on("left_panda_link4", 1)};
  const solver::DriverLayout tree_layout = layout("left_panda_link2", left_sets);
  const solver::DriverLayout left_layout = layout("left_panda_link2", left_sets);
  solver::DriverLayout right_layout;
  right_layout.torques = {"tau_ff"};
  right_layout.decompose_all();
  solver::ReferenceSolver<double> whole(tree, tree_layout), left_arm(left, left_layout), right_arm(right, right_layout);
  test::RandomProblem random(62);
  double worst = 0;
  for (int s = 0; s < test::state_count(200); ++s) {
    const solver::SolveInputs<double> in = draw(random, tree, tree_layout);
    const Eigen::VectorXd qdd = whole.run(in, solver::Policy::original).qdd;
    solver::SolveInputs<double> on_left = in, on_right;
    on_left.q = in.q.head(7);
    on_left.qd = in.qd.head(7);
    on_left.torques = {in.torques[0].head(7)};
    on_right.q = in.q.tail(7);
    on_right.qd = in.qd.tail(7);
    on_right.torques = {in.torques[0].tail(7)};
    worst = std::max(worst, relative(qdd.head(7), left_arm.run(on_left, solver::Policy::original).qdd));
    worst = std::max(worst, relative(qdd.tail(7), right_arm.run(on_right, solver::Policy::original).qdd));
  }
  std::cout << "[reduction] largest relative difference tree vs chains: " << worst << "\n";
  // A few roundings of q̈'s scale (4 eps): the two run the same operations on each branch.
  EXPECT_LE(worst, 4 * std::numeric_limits<double>::epsilon());
}

// Floating bases (F5) through KDL: the quadruped with its four feet held (3 directions each) or
// free, and the mobile Panda with its hand held (6) and a push on its base, random base
// orientations and twists. sweepgen's q̈ (the base's six as its spatial acceleration), its
// constraint wrenches α_k ν_k on the feet or the hand and the push, fed to KDL's inverse dynamics
// of the URDF's tree hung on six KDL joints (support/kdl_tree_dynamics.hpp), give back τff at
// every joint and the base wrench τff_1..6. Bound and skips as above.
TEST(TreeKdl, FloatingBasesReproduceTheTorquesThroughKdl) {
  struct Case {
    std::string urdf, root;
    std::vector<std::string> tips;
    std::vector<solver::ConstraintSet> sets;
  };
  const std::vector<Case> cases = {
      {"robots/quadruped/quadruped.urdf", "trunk", {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, {}},
      {"robots/quadruped/quadruped.urdf", "trunk", {"FL_foot", "FR_foot", "RL_foot", "RR_foot"},
       {solver::ConstraintSet::on("FL_foot", 3), solver::ConstraintSet::on("FR_foot", 3), solver::ConstraintSet::on("RL_foot", 3),
        solver::ConstraintSet::on("RR_foot", 3)}},
      {"robots/mobile_panda/mobile_panda.urdf", "mobile_base", {"panda_hand"}, {solver::ConstraintSet::on("panda_hand", 6)}},
      // Franka's fingers, panda_finger_joint2 a <mimic> of panda_finger_joint1: a joint of its own.
      {"robots/mobile_panda_gripper/mobile_panda_gripper.urdf", "mobile_base", {"panda_leftfinger", "panda_rightfinger"},
       {solver::ConstraintSet::on("panda_leftfinger", 3), solver::ConstraintSet::on("panda_rightfinger", 3)}},
  };
  test::RandomProblem random(63);
  test::SkipCount skips("floating-base round trip through KDL's TreeIdSolver_RNE", kMaxSkippedShare);
  test::WorstRatio worst("floating-base round trip");
  int states = 0;
  for (const Case& c : cases) {
    const model::Chain chain = test::load_tree(c.urdf, c.root, c.tips, true);
    test::KdlTreeDynamics kdl(chain, kGravity);
    const solver::DriverLayout l = layout(c.root, c.sets);
    solver::ReferenceSolver<double> reference(chain, l);
    for (int s = 0; s < test::state_count(300); ++s) {
      solver::SolveInputs<double> in = draw(random, chain, l);
      in.base_rotation = random.rotation();
      const solver::Solution<double>& sol = reference.run(in, solver::Policy::original);
      const RoundTrip trip = round_trip(kdl, l, reference, in, sol, c.root);
      ++states;
      if (skips.skip(!kTorqueRounding.judged(trip.growth), "growth beyond the ceiling")) continue;
      worst.add(trip.error, trip.growth);
      EXPECT_LE(trip.error, kTorqueRounding(trip.growth)) << c.urdf << " sets " << c.sets.size() << " state " << s;
    }
  }
  std::cout << "[floating] " << states << " states on the quadruped and the mobile Pandas\n";
}

// Franka's fingers as its description ships them (robots/mobile_panda_gripper): panda_finger_joint2
// a <mimic> of panda_finger_joint1, a joint of its own for sweepgen as for KDL (kdl_parser reads no
// <mimic>). On the fixed base: the tree to both fingers, and the chain to the left one with the
// right one off it, locked at 0.02 m (locked_joints), where KDL holds it. Bound and skips as above.
TEST(TreeKdl, MimicFingersAreJointsOfTheirOwn) {
  struct Case {
    std::vector<std::string> tips;
    std::vector<solver::ConstraintSet> sets;
    std::map<std::string, double> locks;
  };
  const std::vector<Case> cases = {
      {{"panda_leftfinger", "panda_rightfinger"},
       {solver::ConstraintSet::on("panda_leftfinger", 3), solver::ConstraintSet::on("panda_rightfinger", 3)},
       {}},
      {{"panda_leftfinger"}, {solver::ConstraintSet::on("panda_leftfinger", 3)}, {{"panda_finger_joint2", 0.02}}},
  };
  test::RandomProblem random(64);
  test::SkipCount skips("mimic fingers' round trip through KDL's TreeIdSolver_RNE", kMaxSkippedShare);
  test::WorstRatio worst("mimic fingers' round trip");
  for (const Case& c : cases) {
    model::ChainSpec spec;
    spec.urdf = test::source_path("robots/mobile_panda_gripper/mobile_panda_gripper.urdf");
    spec.root_link = "mobile_base";
    spec.tip_link = c.tips.front();
    spec.branch_tips.assign(c.tips.begin() + 1, c.tips.end());
    spec.locked_joints = c.locks;
    const model::Chain chain = model::load_chain(spec);
    ASSERT_EQ(chain.dof(), 7 + c.tips.size());
    ASSERT_EQ(chain.mimics.size(), 1u);
    test::KdlTreeDynamics kdl(chain, kGravity, c.locks);
    const solver::DriverLayout l = layout("panda_link3", c.sets);
    solver::ReferenceSolver<double> reference(chain, l);
    for (int s = 0; s < test::state_count(300); ++s) {
      const solver::SolveInputs<double> in = draw(random, chain, l);
      const solver::Solution<double>& sol = reference.run(in, solver::Policy::original);
      const RoundTrip trip = round_trip(kdl, l, reference, in, sol, "panda_link3");
      if (skips.skip(!kTorqueRounding.judged(trip.growth), "growth beyond the ceiling")) continue;
      worst.add(trip.error, trip.growth);
      EXPECT_LE(trip.error, kTorqueRounding(trip.growth)) << c.tips.size() << " tips, state " << s;
    }
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

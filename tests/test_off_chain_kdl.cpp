// Links off the chain count (generator/model/chain.hpp): URDFs whose chain links carry fixed
// side links, a moving side branch and a hand with fingers beyond the tip
// (tests/data/side_branches.urdf), fixed links between moving joints with rotated origins and
// a fixed tool as the tip (tests/data/fixed_rpy_chain.urdf, and the bundled ur5 and panda at
// their tips behind fixed joints), checked against an oracle that reads the whole tree with its
// own loader: kdl_parser's KDL::Tree, KDL's TreeIdSolver_RNE (inverse dynamics over every
// segment, fixed ones included) and KDL's Jacobian and its time derivative on the tree's path
// root -> tip. No code of sweepgen's loader is shared with the oracle.
//
// Round trip, per random state and Nc in {0, 1, 3, 6}: sweepgen's reference solver gives q̈ and
// ν for (q, q̇, τff, F_ext, α, β); KDL's inverse dynamics of the whole tree at (q, q̇, q̈), with
// every off-chain moving joint at its locked position and at rest, the same external wrenches
// on the same links and the physical constraint wrench +Σ_k α_k ν_k on the tip link
// (docs/derivation.md, section 7, "Sign of the constraint wrench"; (T1) τcmd = τff + Jᵀ F_cstr ν),
// must give back τff at the chain's joints. With Nc > 0 the constraint itself is checked on KDL's
// kinematics alone: α_kᵀ Ẍ_tip = β_k, Ẍ_tip from KDL's Jacobian J and J̇ q̇ at sweepgen's q̈.
//
// Conventions: TreeIdSolver_RNE takes f_ext per segment in that segment's frame (= the URDF
// link frame), as wrenches acting on the segment, the same as sweepgen's external forces and α
// (link frame, about its origin; α in the tip link's frame); KDL's Wrench is (force, torque),
// sweepgen's Force [moment; force]. KDL's `grav` is the gravity vector itself, sweepgen's
// SolverOptions::gravity likewise, both in the root frame: every URDF here has the chain root
// as its tree root or (side_branches) sits it in 'world' without rotation. KDL's Jacobian is
// hybrid (base orientation, about the tip origin, rows [linear; angular]); the translation of its
// classical acceleration into sweepgen's Ẍ_tip is at KdlTreeOracle::tip_acceleration.
#include <gtest/gtest.h>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacdotsolver.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/tree.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl_parser/kdl_parser.hpp>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <iomanip>
#include <iostream>
#include <map>

#include "model/urdf_loader.hpp"
#include "oracle/kdl_convention.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/kdl_tree_dynamics.hpp"
#include "support/oracle_problem.hpp"
#include "support/rounding_bound.hpp"
#include "support/skip_count.hpp"
#include "support/state_count.hpp"
#include "support/text_pattern.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using oracle::from_kdl;
using oracle::kdl_joints;
using oracle::kdl_vector;
using spatial::Force;
using spatial::Motion;

const std::string kSideBranchesUrdf = test::source_path("tests/data/side_branches.urdf");
const std::string kFixedRpyUrdf = test::source_path("tests/data/fixed_rpy_chain.urdf");
constexpr double kSideJointLock = 0.7;  // the scene's position for side_joint; the fingers keep the default
const Eigen::Vector3d kGravity(0, 0, -9.81);

// Torques: ‖τ_KDL − τff‖∞ / max(1, ‖τff‖∞, ‖τcmd − τff‖∞), against the torques that realise the
// motion (τcmd − τff = Jᵀ α ν, T1). The forward solve (ABA) and KDL's RNE are both backward
// stable: each returns the exact answer of a problem perturbed by c·n·ε relative to the terms it
// sums, c·n of a few hundred for up to 7 joints and 17 links. Among those terms are the
// constraint wrench's, α_k ν_k (unit α_k, lever arms ≤ 1 m here), whose joint torques can be far
// smaller than ν where the α_k are nearly dependent through J (E^A_cstr,0 nearly singular: ν
// grows with its condition and its terms cancel): the growth is γ = ‖ν‖₁ / max(1, ‖τff‖∞,
// ‖τcmd − τff‖∞). Measured worst error/(ε max(1, γ)): 117 (printed as [rounding]); factor 1000.
// Ceiling 1e-6: states with γ > 4.5e6 are counted as skipped, never judged by a looser bound
// (measured γ ≤ 7e4: none).
constexpr test::RoundingBound kTorqueRounding{1000, 1e-6};
// Constraints: |α_kᵀ Ẍ_tip,KDL − β_k| / max(1, ‖J q̈‖∞, ‖J̇ q̇‖∞, ‖g‖∞), against the terms Ẍ_tip
// sums. The solver meets β through a backward-stable factorisation of E^A_cstr,0 ν = r (C2):
// whatever the condition of E, the residual r − E ν is rounding of E ν's terms, ‖E‖∞ ‖ν‖∞, also
// on a row whose pivot it dropped (E singular, β consistent); the growth is γ = ‖E‖∞ ‖ν‖∞ /
// max(1, ‖J q̈‖∞, ‖J̇ q̇‖∞, ‖g‖∞) (E and ν are sweepgen's: they only size the bound). Measured
// worst error/(ε max(1, γ)): 20; factor 200. Ceiling 1e-6: γ > 2.25e7 is counted as skipped
// (measured: 34 states, all UR5 with Nc = 6, where random directions meet its singular poses).
constexpr test::RoundingBound kConstraintRounding{200, 1e-6};
// Share of a check's states (pooled over cases and Nc) that may be skipped: measured 34 of 6000
// constrained states (0.6%) for the constraint, none for the torques.
constexpr double kMaxSkippedShare = 0.05;
// The negative controls must miss τff by at least this much.
constexpr double kMissed = 1e-4;
const int kStates = test::state_count(500);
// Random target accelerations q̈* for the setpoints, [rad/s² or m/s²].
constexpr double kTargetAcceleration = 5.0;

model::Chain load(double side_joint_lock) {
  model::ChainSpec spec;
  spec.urdf = kSideBranchesUrdf;
  spec.root_link = "base";
  spec.tip_link = "wrist";
  spec.locked_joints["side_joint"] = side_joint_lock;
  return model::load_chain(spec);
}

using test::to_kdl;

// KDL's view of the URDF a chain was read from (chain.source), by kdl_parser: the whole tree for
// inverse dynamics, and its path chain.root_link -> chain.tip_link (fixed segments included)
// for the tip's kinematics. Off-chain moving joints are held at `locks` (at rest).
class KdlTreeOracle {
 public:
  KdlTreeOracle(const model::Chain& chain, const std::map<std::string, double>& locks)
      : dynamics_(chain, kGravity, locks),
        path_(path(dynamics_.tree(), chain)),
        jacobian_(path_),
        jacobian_dot_(path_),
        forward_kinematics_(path_),
        tip_link_(chain.tip_link) {}
  KdlTreeOracle(const KdlTreeOracle&) = delete;  // the KDL solvers hold references to path_

  // τ at the chain's joints = RNE of the whole tree at (q, q̇, q̈) with `wrenches` (per link,
  // its frame, acting on it).
  Eigen::VectorXd inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                   const KDL::WrenchMap& wrenches) {
    return dynamics_.inverse_dynamics(q, qd, qdd, wrenches);
  }

  // The tip link's Ẍ as sweepgen defines it (spatial, minus gravity, in the tip frame,
  // [angular; linear]; docs/derivation.md, section 7, "Ẍ_N is spatial, minus gravity"), from
  // KDL's kinematics alone: with the hybrid J (rows [linear; angular]), [ṗ; ω] = J q̇ and the
  // classical acceleration [p̈; ω̇] = J q̈ + J̇ q̇ of the tip origin, in base orientation, and R the
  // tip's orientation:  Ẍ_tip = [Rᵀ ω̇; Rᵀ (p̈ − ω × ṗ − g)].
  struct TipAcceleration {
    Motion<double> spatial;
    double scale;  // max(1, ‖J q̈‖∞, ‖J̇ q̇‖∞, ‖g‖∞): the terms it sums
  };
  TipAcceleration tip_acceleration(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
    KDL::Jacobian J(path_.getNrOfJoints());
    KDL::Twist jacobian_dot_qd;
    KDL::Frame tip;
    if (jacobian_.JntToJac(kdl_joints(q), J) < 0 ||
        jacobian_dot_.JntToJacDot(KDL::JntArrayVel(kdl_joints(q), kdl_joints(qd)), jacobian_dot_qd) < 0 ||
        forward_kinematics_.JntToCart(kdl_joints(q), tip) < 0)
      throw std::runtime_error("KDL kinematics failed");
    const Eigen::Matrix<double, 6, 1> velocity = J.data * qd, joint_term = J.data * qdd;
    Eigen::Matrix<double, 6, 1> bias_term;
    bias_term << from_kdl(jacobian_dot_qd.vel), from_kdl(jacobian_dot_qd.rot);
    const Eigen::Matrix<double, 6, 1> classical = joint_term + bias_term;
    const Eigen::Matrix3d R = from_kdl(tip.M);
    const Eigen::Vector3d p_dot = velocity.head<3>(), omega = velocity.tail<3>();
    const Motion<double> spatial{R.transpose() * classical.tail<3>(),
                                 R.transpose() * (classical.head<3>() - omega.cross(p_dot) - kGravity)};
    return {spatial, std::max({1.0, joint_term.lpNorm<Eigen::Infinity>(), bias_term.lpNorm<Eigen::Infinity>(),
                               kGravity.lpNorm<Eigen::Infinity>()})};
  }

  const std::string& tip_link() const { return tip_link_; }

 private:
  // The tree's path root -> tip; its moving joints must be the chain's, in order.
  static KDL::Chain path(const KDL::Tree& tree, const model::Chain& chain) {
    KDL::Chain path;
    if (!tree.getChain(chain.root_link, chain.tip_link, path))
      throw std::runtime_error("no KDL path to " + chain.tip_link);
    std::vector<std::string> kdl_names, chain_names;
    for (const auto& segment : path.segments)
      if (segment.getJoint().getType() != KDL::Joint::None) kdl_names.push_back(segment.getJoint().getName());
    for (std::size_t i = 1; i <= chain.dof(); ++i) chain_names.push_back(chain.joints[i].name);
    if (kdl_names != chain_names) throw std::runtime_error("KDL's path has other moving joints than the chain");
    return path;
  }

  test::KdlTreeDynamics dynamics_;
  KDL::Chain path_;
  KDL::ChainJntToJacSolver jacobian_;
  KDL::ChainJntToJacDotSolver jacobian_dot_;
  KDL::ChainFkSolverPos_recursive forward_kinematics_;
  std::string tip_link_;
};

// One state's checks: each error relative to the physical terms, and the growth γ of its
// rounding (see the bounds above).
struct StateCheck {
  double torque_error = 0, torque_growth = 1;
  double constraint_error = 0, constraint_growth = 1;  // Nc > 0 only
  bool rank_deficient = false;                         // sweepgen dropped a pivot of E^A_cstr,0
  double nu = 0;                                       // ‖ν‖∞: large where E^A_cstr,0 is nearly singular
};

// The round trip of case `c` with Nc constraints over kStates states, each handed to
// `per_state`: sweepgen solves forward, KDL's tree backward with the constraint wrench
// `constraint_sign` · α ν on the tip (+1 the physical one). Setpoints: β_k = α_kᵀ Ẍ*_tip, Ẍ*_tip
// KDL's tip acceleration of the same state under a random q̈*: random, and achievable also where
// αᵀ J lacks full row rank (Nc > N, singular poses), so that the constraint holds in every state.
template <class PerState>
void round_trip(const test::OracleCase& c, KdlTreeOracle& oracle, std::size_t nc, unsigned seed,
                double constraint_sign, PerState&& per_state) {
  solver::ReferenceSolver<double> reference(c.chain, test::oracle_layout(c, nc));
  test::RandomProblem random(seed);
  for (int s = 0; s < kStates; ++s) {
    test::OracleProblem p = test::draw_problem(random, c, nc);
    Eigen::VectorXd qdd_target(p.q.size());
    for (auto& a : qdd_target) a = random.uniform(-kTargetAcceleration, kTargetAcceleration);
    const Motion<double> target = oracle.tip_acceleration(p.q, p.qd, qdd_target).spatial;
    for (std::size_t k = 0; k < nc; ++k)
      p.beta[static_cast<Eigen::Index>(k)] = spatial::dot(p.alpha_columns[k], target);

    const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::original);
    EXPECT_EQ(reference.status() & ~solver::status_constraint_rank_deficient, solver::status_ok);
    StateCheck check;
    check.rank_deficient = sol.dropped_pivots > 0;

    KDL::WrenchMap wrenches;
    for (std::size_t k = 0; k < p.wrenches.size(); ++k) wrenches[c.external_links[k]] += to_kdl(p.wrenches[k]);
    Force<double> constraint_wrench;  // Σ α_k ν_k, tip frame
    for (std::size_t k = 0; k < nc; ++k) constraint_wrench += p.alpha_columns[k] * sol.nu[static_cast<Eigen::Index>(k)];
    wrenches[oracle.tip_link()] += to_kdl(constraint_wrench * constraint_sign);
    const Eigen::VectorXd tau = oracle.inverse_dynamics(p.q, p.qd, sol.qdd, wrenches);
    const double torques = std::max({1.0, p.tau_ff.lpNorm<Eigen::Infinity>(),
                                     (sol.tau_cmd - p.tau_ff).lpNorm<Eigen::Infinity>()});
    check.torque_error = (tau - p.tau_ff).lpNorm<Eigen::Infinity>() / torques;
    check.torque_growth = std::max(1.0, sol.nu.lpNorm<1>() / torques);

    if (nc > 0) {
      const auto tip = oracle.tip_acceleration(p.q, p.qd, sol.qdd);
      const auto& E = reference.articulated().body[0].constraint_energy;  // E^A_cstr,0
      check.nu = sol.nu.lpNorm<Eigen::Infinity>();
      check.constraint_growth = std::max(1.0, E.cwiseAbs().rowwise().sum().maxCoeff() * check.nu / tip.scale);
      for (std::size_t k = 0; k < nc; ++k) {
        const double residual = spatial::dot(p.alpha_columns[k], tip.spatial) - p.beta[static_cast<Eigen::Index>(k)];
        check.constraint_error = std::max(check.constraint_error, std::abs(residual) / tip.scale);
      }
    }
    per_state(check);
  }
}

// One check over a test: its bound, its counted skips and its worst error/(ε max(1, γ)).
class Judge {
 public:
  Judge(const char* what, test::RoundingBound bound) : bound_(bound), skips_(what, kMaxSkippedShare), worst_(what) {}
  // error / tolerance of one state, or 0 when its growth puts it beyond the ceiling (then it
  // is counted as skipped under `where`).
  double ratio(double error, double growth, const std::string& where) {
    if (skips_.skip(!bound_.judged(growth), where.c_str())) return 0;
    worst_.add(error, growth);
    return error / bound_(growth);
  }

 private:
  test::RoundingBound bound_;
  test::SkipCount skips_;
  test::WorstRatio worst_;
};

// The cases: side_branches (side_joint at kSideJointLock, the fingers at their default 0.005),
// fixed_rpy_chain, and the bundled robots whose tips sit behind fixed links; external wrenches
// on lumped fixed links and on links behind locked joints or at the tip.
struct TreeCase : test::OracleCase {
  std::map<std::string, double> kdl_locks;  // off-chain moving joints, as the oracle holds them
};
const std::map<std::string, double> kSideBranchLocks{
    {"side_joint", kSideJointLock}, {"finger_left_joint", 0.005}, {"finger_right_joint", 0.005}};

model::Chain load_fixed_rpy_chain() {
  model::ChainSpec spec;
  spec.urdf = kFixedRpyUrdf;
  spec.root_link = "base";
  spec.tip_link = "tool";
  return model::load_chain(spec);
}
model::Chain load_bundled_robot(const std::string& name) {
  for (const auto& robot : test::bundled_robots())
    if (robot.name == name) return test::load_bundled(robot);
  throw std::runtime_error("no bundled robot " + name);
}

// side_branches with side_joint locked at `side_joint_lock` for sweepgen; the oracle holds
// the off-chain joints at kSideBranchLocks.
TreeCase side_branches_case(double side_joint_lock) {
  return {{"side_branches", load(side_joint_lock), {"sensor", "finger_left"}}, kSideBranchLocks};
}

std::vector<TreeCase> tree_cases() {
  return {
      side_branches_case(kSideJointLock),
      {{"fixed_rpy_chain", load_fixed_rpy_chain(), {"spacer_b", "tool"}}, {}},
      {{"ur5", load_bundled_robot("ur5"), {"forearm_link", "tool0"}}, {}},
      {{"panda", load_bundled_robot("panda"), {"panda_link4", "panda_link8"}}, {}},
  };
}

// The links lumped into `body`, in the order added.
std::vector<std::string> names(const model::Body& body) {
  std::vector<std::string> links;
  for (const auto& lumped : body.lumped_links) links.push_back(lumped.link);
  return links;
}

// The loader's lumping as the test expects it from the URDF, before any numbers.
TEST(OffChain, EveryLinkIsLumpedLockedOrLeftOut) {
  const model::Chain chain = load(kSideJointLock);
  ASSERT_EQ(chain.dof(), 4u);
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
  EXPECT_EQ(chain.frames.size() + chain.left_out.size(), urdf::parseURDFFile(kSideBranchesUrdf)->links_.size());
  // And each with its mass in the listing that `sweepgen info` and the generated header print,
  // the base's links (the root, and what is fixed to it) included: "<link> <mass> kg".
  std::string listing;
  for (const std::string& line : model::lumping_summary(chain)) listing += line + "\n";
  const urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDFFile(kSideBranchesUrdf);
  for (const auto& [name, link] : urdf_model->links_)
    EXPECT_TRUE(test::Pattern("(^| )" + name + " [-+.e0-9]+ kg").search(listing)) << name << " is not listed:\n"
                                                                                << listing;
}

// fixed_rpy_chain as written: every fixed link lumped into the moving body before it, the tool
// (the tip) into body 6, nothing locked or left out.
TEST(OffChain, FixedLinksInsideTheChainAreLumped) {
  const model::Chain chain = load_fixed_rpy_chain();
  ASSERT_EQ(chain.dof(), 6u);
  const std::vector<std::vector<std::string>> lumped{
      {"flange1"}, {}, {"spacer_a", "spacer_b"}, {}, {"adapter"}, {"tool"}};
  for (std::size_t i = 1; i <= 6; ++i) EXPECT_EQ(names(chain.bodies[i]), lumped[i - 1]) << "body " << i;
  EXPECT_EQ(chain.joints[3].type, model::JointType::prismatic);
  EXPECT_EQ(chain.joints[5].type, model::JointType::prismatic);
  EXPECT_EQ(chain.tip().body, 6u);
  EXPECT_FALSE(chain.tip().X.E.isIdentity(1e-3));
  EXPECT_TRUE(chain.locked_joints.empty());
  EXPECT_TRUE(chain.left_out.empty());
  EXPECT_EQ(chain.frames.size(), urdf::parseURDFFile(kFixedRpyUrdf)->links_.size());
}

// Per case and Nc in {0, 1, 3, 6}: KDL's tree inverse dynamics gives τff back, and (Nc > 0)
// KDL's tip acceleration meets the setpoints. States where sweepgen drops a pivot of
// E^A_cstr,0 are judged like any other; with Nc > N (side_branches, Nc = 6) that is every state,
// so the dropped-pivot path is covered.
TEST(OffChain, InverseDynamicsOfTheWholeTreeGivesBackTheTorques) {
  Judge torques("KDL tree inverse dynamics vs tau_ff", kTorqueRounding);
  Judge constraints("KDL tip acceleration vs beta", kConstraintRounding);
  unsigned seed = 11;
  for (const TreeCase& c : tree_cases()) {
    KdlTreeOracle oracle(c.chain, c.kdl_locks);
    for (std::size_t nc : {0u, 1u, 3u, 6u}) {
      const std::string where = c.name + " Nc=" + std::to_string(nc);
      double torque_ratio = 0, constraint_ratio = 0, max_nu = 0;  // worst error / tolerance, ‖ν‖∞
      int rank_deficient = 0;
      round_trip(c, oracle, nc, seed++, 1, [&](const StateCheck& s) {
        torque_ratio = std::max(torque_ratio, torques.ratio(s.torque_error, s.torque_growth, where));
        if (nc > 0)
          constraint_ratio = std::max(constraint_ratio, constraints.ratio(s.constraint_error, s.constraint_growth, where));
        rank_deficient += s.rank_deficient ? 1 : 0;
        max_nu = std::max(max_nu, s.nu);
      });
      std::cout << std::setprecision(2) << std::scientific << "[off-chain] " << where << ", " << kStates
                << " states: max error/tolerance: torques " << torque_ratio << ", constraints " << constraint_ratio
                << "; max |nu| " << max_nu << ", rank-deficient " << rank_deficient << std::endl;
      EXPECT_LE(torque_ratio, 1.0) << where;
      EXPECT_LE(constraint_ratio, 1.0) << where;
      if (nc > c.chain.dof()) {
        EXPECT_EQ(rank_deficient, kStates) << where;
      }
    }
  }
}

// Negative controls: the oracle sees what the test is for. A side branch locked elsewhere than
// the oracle holds it, and fingers held elsewhere, are each a miss.

// The worst torque error of `c`'s round trip with Nc constraints and the constraint wrench
// `constraint_sign` · α ν.
double worst_torque_error(const TreeCase& c, std::size_t nc, unsigned seed, double constraint_sign = 1) {
  KdlTreeOracle oracle(c.chain, c.kdl_locks);
  double worst = 0;
  round_trip(c, oracle, nc, seed, constraint_sign,
             [&](const StateCheck& s) { worst = std::max(worst, s.torque_error); });
  return worst;
}

TEST(OffChain, OracleSeesAWronglyLockedBranch) {
  const double branch_elsewhere = worst_torque_error(side_branches_case(-0.5), 0, 12);
  TreeCase fingers_open = side_branches_case(kSideJointLock);
  fingers_open.kdl_locks["finger_left_joint"] = fingers_open.kdl_locks["finger_right_joint"] = 0.04;
  const double fingers_elsewhere = worst_torque_error(fingers_open, 0, 13);
  std::cout << "[off-chain] negative controls: side branch locked elsewhere " << branch_elsewhere
            << ", fingers held elsewhere " << fingers_elsewhere << std::endl;
  EXPECT_GE(branch_elsewhere, kMissed);
  EXPECT_GE(fingers_elsewhere, kMissed);
}

// ... and so is the constraint wrench with the wrong sign (−α ν, KDL's Vereshchagin convention).
TEST(OffChain, OracleSeesTheSignOfTheConstraintWrench) {
  for (const TreeCase& c : tree_cases()) {
    const double wrong_sign = worst_torque_error(c, 3, 14, -1);
    std::cout << "[off-chain] negative control: " << c.name << " Nc=3 with -alpha nu on the tip " << wrong_sign
              << std::endl;
    EXPECT_GE(wrong_sign, kMissed) << c.name;
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

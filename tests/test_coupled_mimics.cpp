// Coupled <mimic> joints (scene key mimic: coupled; docs/derivation.md, M1, M2) in the reference
// solver:
//   - the loader's resolution: a <mimic> of a <mimic> follows the root source, multipliers and
//     offsets composed (the bundled parallel gripper's right inner finger: −1 · (1 · q) + 0.05);
//     a source the model does not move, and the modes' keys and flags, refused with the joints named;
//   - against the dense oracle's Gauss principle with the rows e_mᵀ − k e_sᵀ (rhs 0) beside the
//     sets' rows α_kᵀ J (rhs β − α_kᵀ c), at random states where each coupled joint's q, q̇ follow its
//     source: the bundled parallel gripper pinching (12 joints, 5 couplings, 2 world sets), the
//     same without its sets, and the mobile Panda's Franka fingers (prismatic, floating base); with
//     the inward columns (I2) and refinement (R1), and the outward rows (I6) without; q̈ (every
//     joint), ν with the couplings' λ, τcmd (T1 with the torque pairs), q̈_m = k q̈_s;
//   - the parallel gripper in binary128 against DenseDynamics<Quad>;
//   - the CLI: `info --mimic coupled` lists each coupling, `solve --urdf ... --mimic coupled` takes q
//     and qd without the coupled joints and answers their coupling_torque by name, as the scene's
//     own problem (`solve --scene`) with the same sets;
//   - the report's KDL and dense KKT rows, which know no coupling (nor loop), step aside saying why;
//   - the gripper swinging under gravity for 2 s (RK4 at 1 ms and 0.5 ms): the energy stays to
//     RK4's error (the transmissions' torque pairs do no work while the couplings hold), the
//     coupled joints with their sources.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "report/dense_kkt_row.hpp"
#include "report/kdl_row.hpp"
#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "solver/flat_layout.hpp"
#include "solver/quad_scalar.hpp"
#include "support/dense_rows.hpp"
#include "support/non_orthogonality.hpp"
#include "support/oracle_problem.hpp"
#include "support/rk4.hpp"
#include "support/run_command.hpp"
#include "support/skip_count.hpp"
#include "support/state_count.hpp"
#include "support/temp_dir.hpp"

namespace {
namespace SWEEPGEN_TEST_FILE {

using namespace sweepgen;
using test::LongDouble;
using test::Oracle;
using test::OracleMat;
using test::OracleVec;

constexpr const char* kGripper = "robots/parallel_gripper/parallel_gripper_pinch.yaml";

// As the loop sets' dense comparison (test_loop_sets.cpp): a double solve loses ~eps cond(E) in ν,
// q̈ up to ten times that; judged up to a ceiling of 1e-5 (cond(E) ≤ 1e9), the rest counted.
constexpr double kEps = std::numeric_limits<double>::epsilon();
double tolerance(LongDouble cond) { return std::max(1e-10, 100 * kEps * static_cast<double>(cond)); }
constexpr double kCeiling = 1e-5;

using test::dense_rows;

struct CoupledCase {
  std::string name;
  model::Chain chain;
  solver::DriverLayout layout;
  model::Vec3 gravity;
};

std::vector<CoupledCase> coupled_cases() {
  std::vector<CoupledCase> cases;
  {
    const scene::Scene s = scene::load_scene(test::source_path(kGripper));
    cases.push_back({"parallel_gripper_pinch", scene::load_scene_chain(s), s.layout, s.gravity});
    solver::DriverLayout free;  // the couplings alone
    free.torques = {"tau_ff"};
    free.decompose_all();
    cases.push_back({"parallel_gripper_free", cases.back().chain, free, s.gravity});
  }
  {  // Franka's fingers (prismatic) on the floating mobile Panda, a 3-D set on the left finger
    scene::Scene s = scene::load_scene(test::source_path("robots/mobile_panda_gripper/mobile_panda_grasp.yaml"));
    s.chain.couple_mimics = true;
    solver::DriverLayout layout;
    layout.torques = {"tau_ff"};
    layout.sets = {solver::ConstraintSet::on("panda_leftfinger", 3)};
    layout.constraints = 3;
    layout.decompose_all();
    cases.push_back({"mobile_panda_fingers", scene::load_scene_chain(s), layout, s.gravity});
  }
  return cases;
}

// The drawn state with each coupled joint where its source puts it (M1).
void follow(test::OracleProblem& p, const model::Chain& chain) {
  solver::follow_couplings(p.q, p.qd, chain.couplings);
}

solver::SolveInputs<double> inputs_of(const test::OracleProblem& p, const solver::DriverLayout& layout) {
  solver::SolveInputs<double> in;
  in.q = p.q;
  in.qd = p.qd;
  in.torques = {p.tau_ff};
  in.wrenches.assign(layout.external_forces.size(), spatial::Force<double>{});
  std::size_t drawn = 0;
  in.alpha = solver::directions_with(layout, [&] { return p.alpha_columns[drawn++]; });
  in.beta = p.beta;
  in.base_rotation = p.base_rotation;
  return in;
}

TEST(CoupledMimics, ALoaderResolvesAMimicOfAMimicToItsRootSource) {
  const scene::Scene s = scene::load_scene(test::source_path(kGripper));
  const model::Chain chain = scene::load_scene_chain(s);
  ASSERT_EQ(chain.couplings.size(), 5u);
  EXPECT_EQ(chain.independent_dof(), 7u);
  const std::size_t finger = chain.joint_index("finger_joint");
  const model::JointCoupling* right = chain.coupling_of(chain.joint_index("right_inner_finger_joint"));
  ASSERT_NE(right, nullptr);
  EXPECT_EQ(right->source, finger);  // through right_inner_knuckle_joint, itself a <mimic> of finger_joint
  EXPECT_EQ(right->multiplier, -1.0);
  EXPECT_EQ(right->offset, 0.05);
  EXPECT_EQ(right->through, std::vector<std::string>{"right_inner_knuckle_joint"});
  for (const model::JointCoupling& c : chain.couplings) EXPECT_EQ(c.source, finger) << chain.joints[c.joint].name;
  // The default takes each <mimic> joint as a joint of its own.
  scene::Scene independent = s;
  independent.chain.couple_mimics = false;
  EXPECT_TRUE(scene::load_scene_chain(independent).couplings.empty());
}

TEST(CoupledMimics, ASourceTheModelDoesNotMoveIsRefusedNamingBothJoints) {
  // The gripper with its left outer finger's tips only: finger_joint moves, but lock it.
  scene::Scene s = scene::load_scene(test::source_path(kGripper));
  s.chain.locked_joints["finger_joint"] = 0.2;
  s.chain.tip_link = "right_inner_finger_pad";
  s.chain.branch_tips = {"right_inner_knuckle"};
  try {
    scene::load_scene_chain(s);
    FAIL() << "a coupling to a locked joint was taken";
  } catch (const std::exception& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'finger_joint'"), std::string::npos) << message;
    EXPECT_NE(message.find("<mimic>"), std::string::npos) << message;
    EXPECT_NE(message.find("locked at 0.2"), std::string::npos) << message;
    EXPECT_NE(message.find("mimic: coupled"), std::string::npos) << message;
  }
}

// 25 joints that follow a first: one constraint direction each, more than a solve holds.
TEST(CoupledMimics, MoreCouplingsThanASolveHoldsAreRefused) {
  const test::TempDir dir;
  std::string urdf = "<robot name=\"fan\">\n  <link name=\"l0\"/>\n";
  for (int i = 1; i <= 26; ++i) {
    const std::string link = "l" + std::to_string(i), parent = "l" + std::to_string(i - 1);
    urdf += "  <link name=\"" + link + "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" "
            "iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n  <joint name=\"j" + std::to_string(i) +
            "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + link +
            "\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"0 0 1\"/><limit effort=\"10\" lower=\"-1\" upper=\"1\" "
            "velocity=\"1\"/>" + (i > 1 ? "<mimic joint=\"j1\" multiplier=\"0.5\"/>" : "") + "</joint>\n";
  }
  const std::string path = dir.write("fan.urdf", urdf + "</robot>\n");
  const std::string scene = dir.write("fan.yaml", "sweepgen_scene: 1\nsolver: fan\nurdf: " + path + "\nmimic: coupled\n");
  try {
    scene::load_scene_chain(scene::load_scene(scene));
    FAIL() << "25 couplings were taken";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("25 coupled <mimic> joints and 0 set directions: a solve holds at most 24"),
              std::string::npos)
        << e.what();
  }
}

TEST(CoupledMimics, SceneKeysAreChecked) {
  const test::TempDir dir;
  const std::string urdf = test::source_path("robots/parallel_gripper/parallel_gripper.urdf");
  const auto scene_with = [&](const std::string& extra) {
    return dir.write("s.yaml", "sweepgen_scene: 1\nsolver: g\nurdf: " + urdf +
                                   "\nroot: base_link\ntips: [left_inner_finger_pad, right_inner_finger_pad, "
                                   "left_inner_knuckle, right_inner_knuckle]\ndrivers: {torques: [tau_ff]}\n" + extra);
  };
  const auto message_of = [&](const std::string& extra) {
    try {
      scene::load_scene(scene_with(extra));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message_of("mimic: tied\n").find("mimic mode"), std::string::npos);
  EXPECT_NE(message_of("outputs: [qdd, coupling_torque]\n").find("coupling_torque has no entries"), std::string::npos);
  EXPECT_EQ(message_of("mimic: coupled\nderivatives: true\n"), "");  // q, q̇ columns of the independent joints (D2)
  EXPECT_EQ(message_of("mimic: coupled\noutputs: [qdd, coupling_torque]\n"), "");
}

TEST(CoupledMimics, TheCliTakesTheMimicMode) {
  const std::string urdf = test::source_path("robots/parallel_gripper/parallel_gripper.urdf");
  const std::vector<std::string> chain{"--urdf", urdf, "--root", "base_link", "--tip", "left_inner_finger_pad",
                                       "--branch-tip", "right_inner_finger_pad", "--branch-tip", "left_inner_knuckle",
                                       "--branch-tip", "right_inner_knuckle", "--mimic", "coupled"};
  std::vector<std::string> info{SWEEPGEN_EXECUTABLE, "info"};
  info.insert(info.end(), chain.begin(), chain.end());
  const test::CommandResult listed = test::run_command(test::shell_command(info));
  ASSERT_EQ(listed.exit_code, 0) << listed.err;
  EXPECT_NE(listed.out.find("right_inner_finger_joint (revolute, axis 1 0 0, axis-aligned: folds to one column) moves "
                            "right_inner_finger against right_outer_knuckle, mass 0.0104003 kg, effort limit 20, rotor "
                            "inertia 0, coupled: q = -1 q_7 + 0.05 ('finger_joint'; no input of its own; coupling_torque[2])"),
            std::string::npos)
      << listed.out;
  // One state through `solve --urdf --mimic coupled` (sets in the line) and `solve --scene`.
  const std::string q = "[0.3,-1.1,1.4,-0.6,1.2,0.4,0.35]", qd = "[0.5,-0.3,0.4,0.8,-0.6,0.9,1.5]";
  const std::string sets = R"([{"link":"left_inner_finger_pad","alpha":[[0,0,0,0,-1,0]],"beta":[0.2]},)"
                           R"({"link":"right_inner_finger_pad","alpha":[[0,0,0,0,-1,0]],"beta":[-0.1]}])";
  std::vector<std::string> by_urdf{SWEEPGEN_EXECUTABLE, "solve"};
  by_urdf.insert(by_urdf.end(), chain.begin(), chain.end());
  const test::CommandResult a =
      test::run_command(test::shell_command(by_urdf), R"({"q":)" + q + R"(,"qd":)" + qd + R"(,"constraints":)" + sets + "}\n");
  const test::CommandResult b = test::run_command(
      test::shell_command({SWEEPGEN_EXECUTABLE, "solve", "--scene", test::source_path(kGripper)}),
      R"({"q":)" + q + R"(,"qd":)" + qd + R"(,"beta":[0.2,-0.1]})" + "\n");
  ASSERT_EQ(a.exit_code, 0) << a.out << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  const nlohmann::json by_line = nlohmann::json::parse(a.out), by_scene = nlohmann::json::parse(b.out);
  ASSERT_EQ(by_line["coupling_torque"].size(), 5u) << a.out;
  EXPECT_TRUE(by_line["coupling_torque"].contains("right_inner_finger_joint")) << a.out;
  for (const char* key : {"qdd", "nu", "tau_cmd", "coupling_torque"}) EXPECT_EQ(by_line[key], by_scene[key]) << key;
  const auto qdd = by_line["qdd"].get<std::vector<double>>();
  EXPECT_NEAR(qdd[9], -qdd[6], 1e-12 * std::max(1.0, std::abs(qdd[6])));  // right inner finger = -finger_joint
  // q with an entry for every joint is the wrong size: the coupled joints have none.
  const test::CommandResult wrong = test::run_command(
      test::shell_command(by_urdf), R"({"q":[0,0,0,0,0,0,0,0,0,0,0,0],"qd":)" + qd + "}\n");
  EXPECT_EQ(wrong.exit_code, 1);
  EXPECT_NE(wrong.err.find("expected 7 numbers, got 12"), std::string::npos) << wrong.err;
}

TEST(CoupledMimics, TheReportsOraclesThatKnowNoCouplingStepAside) {
  report::TimingOptions untimed;
  untimed.repetitions = 0;
  for (const char* path : {kGripper, "robots/four_bar/four_bar_loop.yaml"}) {
    scene::Scene s = scene::load_scene(test::source_path(path));
    const model::Chain chain = scene::load_scene_chain(s);
    const auto problems = report::random_problems(s, chain, 3, 7);
    const report::VariantResult dense = report::measure_dense_kkt(s, chain, problems, untimed);
    EXPECT_TRUE(dense.outcomes.empty()) << path;
    EXPECT_NE(dense.note.find(chain.couplings.empty() ? "tests/test_loop_sets.cpp" : "tests/test_coupled_mimics.cpp"),
              std::string::npos)
        << path << ": " << dense.note;
  }
  // A serial chain with a coupled <mimic> (the UR5 to the gripper's left pad, the rest locked): KDL
  // would take the mimic as a joint of its own.
  scene::Scene s = scene::load_scene(test::source_path(kGripper));
  s.chain.tip_link = "left_inner_finger_pad";
  s.chain.branch_tips.clear();
  s.layout = solver::DriverLayout{};
  s.layout.torques = {"tau_ff"};
  s.layout.decompose_all();
  const model::Chain chain = scene::load_scene_chain(s);
  ASSERT_TRUE(chain.is_chain());
  ASSERT_EQ(chain.couplings.size(), 1u);
  const report::VariantResult kdl = report::measure_kdl(s, chain, report::random_problems(s, chain, 3, 7), untimed);
  EXPECT_TRUE(kdl.outcomes.empty());
  EXPECT_NE(kdl.note.find("mimic: coupled"), std::string::npos) << kdl.note;
}

TEST(CoupledMimics, ReferenceSolverAgreesWithTheDenseCoupledRows) {
  test::RandomProblem random(461);
  test::SkipCount skips("coupled mimics against the dense oracle", 0.05);
  for (const CoupledCase& c : coupled_cases()) {
    const std::size_t nc = c.layout.constraints, n = c.chain.dof(), total = nc + c.chain.couplings.size();
    for (const auto rows : {solver::ConstraintRows::inward_columns, solver::ConstraintRows::outward_rows}) {
      solver::SolverOptions options;
      options.gravity = c.gravity;
      options.constraint_rows = rows;
      options.refinement = rows == solver::ConstraintRows::inward_columns;  // (I6) on its own first pass
      solver::ReferenceSolver<double> reference(c.chain, c.layout, options);
      double worst = 0, coupling_residual = 0;
      for (int state = 0; state < test::state_count(200); ++state) {
        test::OracleProblem p = test::draw_problem(random, test::OracleCase{c.name, c.chain, {}}, nc);
        follow(p, c.chain);
        solver::SolveInputs<double> in = inputs_of(p, c.layout);
        // The coupled joints' own entries are not inputs: anything there changes nothing.
        for (const model::JointCoupling& coupling : c.chain.couplings)
          in.q[static_cast<Eigen::Index>(coupling.joint - 1)] = in.qd[static_cast<Eigen::Index>(coupling.joint - 1)] = 1e3;
        const solver::Solution<double>& sol = reference.run(in, solver::Policy::original);
        const Oracle o(c.chain, p.base_gravity(c.gravity));
        const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd), tau = test::to_long(p.tau_ff);
        OracleMat alpha(6, static_cast<Eigen::Index>(nc));
        for (std::size_t k = 0; k < nc; ++k)
          alpha.col(static_cast<Eigen::Index>(k)) << in.alpha[k].moment.cast<LongDouble>(), in.alpha[k].force.cast<LongDouble>();
        const auto [Jc, rhs] = dense_rows(o, c.layout, c.chain, q, qd, alpha, test::to_long(p.beta));
        const OracleMat M = o.mass_matrix(q);
        const OracleMat E = Oracle::constraint_energy(M, Jc);
        const std::string where = c.name + " state " + std::to_string(state) +
                                  (rows == solver::ConstraintRows::outward_rows ? " (I6)" : " (I2)");
        // E^A_cstr,0 = J M^-1 J^T with the coupling rows (M2).
        EXPECT_LE(static_cast<double>((reference.articulated().body[0].constraint_energy.cast<LongDouble>() - E).cwiseAbs().maxCoeff() /
                                      E.cwiseAbs().maxCoeff()),
                  1e-11)
            << where;  // test_dense_oracle's kEnergyTolerance
        const auto kept = Oracle::kept_constraints(E, LongDouble(reference.model().pivot_tolerance));
        EXPECT_EQ(sol.dropped_pivots, static_cast<double>(total - kept.size())) << where;
        OracleMat Jk(static_cast<Eigen::Index>(kept.size()), static_cast<Eigen::Index>(n));
        OracleVec rk(static_cast<Eigen::Index>(kept.size()));
        for (std::size_t j = 0; j < kept.size(); ++j) {
          Jk.row(static_cast<Eigen::Index>(j)) = Jc.row(kept[j]);
          rk[static_cast<Eigen::Index>(j)] = rhs[kept[j]];
        }
        const Oracle::KktSolution kkt = o.solve_rows(q, qd, tau, Jk, rk);
        const LongDouble cond = Oracle::condition(Oracle::constraint_energy(M, Jk));
        if (skips.skip(tolerance(cond) > kCeiling, "cond(E) > 1e9")) continue;
        OracleVec nu = OracleVec::Zero(static_cast<Eigen::Index>(total));
        for (std::size_t j = 0; j < kept.size(); ++j) nu[kept[j]] = kkt.nu[static_cast<Eigen::Index>(j)];
        const double e_qdd = test::relative_error(sol.qdd, o.in_solver_coordinates(q, qd, kkt.qdd));
        const double e_nu = test::relative_error(sol.nu, nu);
        const double e_tau = test::relative_error(sol.tau_cmd, OracleVec(tau + Jc.transpose() * nu));  // (T1), (M2)
        EXPECT_LE(e_qdd, tolerance(cond)) << where;
        EXPECT_LE(e_nu, tolerance(cond)) << where;
        EXPECT_LE(e_tau, tolerance(cond)) << where;
        // q̈_m = k q̈_s (M1), relative to the largest q̈.
        const double scale = std::max(1.0, sol.qdd.cwiseAbs().maxCoeff());
        for (const model::JointCoupling& coupling : c.chain.couplings) {
          const double r = std::abs(sol.qdd[static_cast<Eigen::Index>(coupling.joint - 1)] -
                                    coupling.multiplier * sol.qdd[static_cast<Eigen::Index>(coupling.source - 1)]) / scale;
          EXPECT_LE(r, tolerance(cond)) << where << " coupling of joint " << coupling.joint;
          coupling_residual = std::max(coupling_residual, r / tolerance(cond));
        }
        worst = std::max({worst, e_qdd / tolerance(cond), e_nu / tolerance(cond), e_tau / tolerance(cond)});
      }
      std::printf("[coupled mimics] %s %s: largest error / tolerance %.3g, coupling residual / tolerance %.3g\n",
                  c.name.c_str(), rows == solver::ConstraintRows::outward_rows ? "(I6)" : "(I2)", worst, coupling_residual);
    }
  }
}

// In binary128 (ε = 2^-112): ReferenceSolver<Quad> against DenseDynamics<Quad>'s rows on the
// bundled gripper scene as it states it; q̈ and ν within 100 (ε + δ) κ as the loop scenes'
// (test_loop_sets.cpp: δ the model's rotations' distance from orthogonal in double, here the UR5's
// and the gripper's quarter turns, exact, and its URDF angles), judged where that is at most 1e-6.
TEST(CoupledMimics, TheBundledGripperAgreesWithTheDenseSolveInBinary128) {
  using Q = solver::Quad;
  using QOracle = oracle::DenseDynamics<Q>;
  const double eps = std::ldexp(1.0, -112);
  test::RandomProblem random(1128);
  test::SkipCount skips("coupled gripper in binary128", 0.05);
  const scene::Scene s = scene::load_scene(test::source_path(kGripper));
  const model::Chain chain = scene::load_scene_chain(s);
  const double delta = test::non_orthogonality(chain, s.layout);
  solver::ReferenceSolver<Q> reference(chain, s.layout, s.solver_options());
  const std::size_t nc = s.layout.constraints, total = nc + chain.couplings.size();
  double worst = 0;
  for (int state = 0; state < test::state_count(8); ++state) {
    test::OracleProblem p = test::draw_problem(random, test::OracleCase{kGripper, chain, {}}, nc);
    follow(p, chain);
    const solver::SolveInputs<double> in = inputs_of(p, s.layout);
    const solver::Solution<Q>& sol = reference.run(in.cast<Q>(), solver::Policy::original);
    const QOracle o(chain, p.base_gravity(s.gravity));
    // The coupled joints' q, q̇ as the solver forms them, in binary128 (in double, q_m = k q_s + o
    // would be rounded: a different state by ~1e-17).
    QOracle::Vec q = p.q.cast<Q>(), qd = p.qd.cast<Q>();
    const QOracle::Vec tau = p.tau_ff.cast<Q>();
    for (const model::JointCoupling& c : chain.couplings) {
      q[static_cast<Eigen::Index>(c.joint - 1)] = Q(c.multiplier) * q[static_cast<Eigen::Index>(c.source - 1)] + Q(c.offset);
      qd[static_cast<Eigen::Index>(c.joint - 1)] = Q(c.multiplier) * qd[static_cast<Eigen::Index>(c.source - 1)];
    }
    QOracle::Mat alpha(6, static_cast<Eigen::Index>(nc));
    for (std::size_t k = 0; k < nc; ++k)
      alpha.col(static_cast<Eigen::Index>(k)) << in.alpha[k].moment.cast<Q>(), in.alpha[k].force.cast<Q>();
    const auto [Jc, rhs] = dense_rows(o, s.layout, chain, q, qd, alpha, QOracle::Vec(p.beta.cast<Q>()));
    const QOracle::Mat M = o.mass_matrix(q);
    const QOracle::Mat E = QOracle::constraint_energy(M, Jc);
    const auto kept = QOracle::kept_constraints(E, reference.model().pivot_tolerance);
    const std::string where = "parallel gripper state " + std::to_string(state);
    ASSERT_EQ(kept.size(), total) << where;  // no direction is redundant here
    const QOracle::KktSolution kkt = o.solve_rows(q, qd, tau, Jc, rhs);
    const double kappa = std::max(1.0, static_cast<double>(QOracle::condition(E)));
    const double bound = 100 * (eps + delta) * kappa;
    if (skips.skip(bound > 1e-6, "100 (eps + delta) kappa > 1e-6")) continue;
    const double e_qdd = static_cast<double>(
        (sol.qdd - kkt.qdd).cwiseAbs().maxCoeff() / std::max(Q(1), kkt.qdd.cwiseAbs().maxCoeff()));
    const double e_nu = static_cast<double>(
        (sol.nu - kkt.nu).cwiseAbs().maxCoeff() / std::max(Q(1), kkt.nu.cwiseAbs().maxCoeff()));
    EXPECT_LE(e_qdd, bound) << where;
    EXPECT_LE(e_nu, bound) << where;
    worst = std::max({worst, e_qdd / ((eps + delta) * kappa), e_nu / ((eps + delta) * kappa)});
  }
  std::printf("[coupled mimics] binary128: largest error %.3g (eps + delta) kappa, delta %.3g\n", worst, delta);
}

// The gripper on the UR5 swinging under gravity, undriven and undamped, 2 s of RK4 over every joint
// (the coupled ones start on their sources, M1): the energy, ½ q̇ᵀ M q̇ + V over every joint, stays
// to RK4's error (the torque pairs do no work while q̇_m = k q̇_s), and the coupled joints' q and q̇
// stay k q_s + o and k q̇_s to 1e-12 (the issue's bound; rounding of 2000-4000 steps).
TEST(CoupledMimics, TheSwingingGripperKeepsItsEnergy) {
  const scene::Scene s = scene::load_scene(test::source_path(kGripper));
  const model::Chain chain = scene::load_scene_chain(s);
  solver::DriverLayout free;
  free.torques = {"tau_ff"};
  free.decompose_all();
  solver::SolverOptions options;
  options.gravity = s.gravity;
  solver::ReferenceSolver<double> reference(chain, free, options);
  const auto n = static_cast<Eigen::Index>(chain.dof());
  Eigen::VectorXd q(n), qd(n);
  q << 0.3, -1.1, 1.4, -0.6, 1.2, 0.4, 0.35, 0, 0, 0, 0, 0;
  qd << 0.5, -0.3, 0.4, 0.8, -0.6, 0.9, 1.5, 0, 0, 0, 0, 0;
  solver::follow_couplings(q, qd, chain.couplings);
  const Oracle o(chain, s.gravity);
  const auto energy = [&](const Eigen::VectorXd& at, const Eigen::VectorXd& velocity) {
    const OracleVec v = test::to_long(velocity);
    return static_cast<double>(0.5L * v.dot(o.mass_matrix(test::to_long(at)) * v) + o.potential_energy(test::to_long(at)));
  };
  const double start = energy(q, qd);
  const auto accelerate = [&](const Eigen::VectorXd& at, const Eigen::VectorXd& velocity) {
    Eigen::VectorXd a(at.size()), b(velocity.size());
    a = at;
    b = velocity;
    solver::follow_couplings(a, b, chain.couplings);
    solver::SolveInputs<double> in;
    in.q = a;
    in.qd = b;
    in.torques = {Eigen::VectorXd::Zero(n)};
    const Eigen::VectorXd qdd = reference.run(in, solver::Policy::original).qdd;
    EXPECT_EQ(reference.status(), solver::status_ok);
    return qdd;
  };
  // The drift at step h and at h / 2: RK4's own error falls about 16-fold (a missing term's would not).
  const auto simulate = [&](double h, double& coupling) {
    Eigen::VectorXd x = q, v = qd;
    double drift = 0;
    for (int step = 0; step < static_cast<int>(std::lround(2.0 / h)); ++step) {
      test::rk4_step(accelerate, x, v, h);
      Eigen::VectorXd followed_q = x, followed_qd = v;
      solver::follow_couplings(followed_q, followed_qd, chain.couplings);
      // RK4 moves the coupled joints' entries by their own q̈ = k q̈_s: they stay with their sources.
      coupling = std::max({coupling, (followed_q - x).cwiseAbs().maxCoeff(), (followed_qd - v).cwiseAbs().maxCoeff()});
      drift = std::max(drift, std::abs(energy(followed_q, followed_qd) - start) / std::abs(start));
    }
    return drift;
  };
  double coupling = 0;
  const double drift = simulate(1e-3, coupling), halved = simulate(5e-4, coupling);
  std::printf("[coupled mimics] 2 s swinging: relative energy drift %.3g at 1 ms, %.3g at 0.5 ms; coupled joints off "
              "their sources by %.3g\n",
              drift, halved, coupling);
  EXPECT_LE(halved, 1e-6);       // the issue's bound, at the step that meets it
  EXPECT_GE(drift / halved, 10);  // RK4's O(h^4): 16-fold, the error is the integrator's
  EXPECT_LE(coupling, 1e-12);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

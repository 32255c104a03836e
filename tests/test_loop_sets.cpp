// Constraint sets between two links (docs/derivation.md, L1, L4, L5) in the reference solver:
//   - against the dense oracle's Gauss principle with the relative Jacobian J_A − ᴬX_B J_B and the
//     bias of (L2) (DenseDynamics::relative_motion), at random (open) states: the planar four-bar
//     (robots/four_bar, and closed by a 6-D set: three redundant directions dropped), the dual Panda with a 6-D set between its hands at turned offsets beside a
//     world set, the quadruped on its floating base with a set between two feet beside two world
//     sets, and the linkage biped (robots/linkage_biped: feet on the ground, knees' loops closed);
//     with the inward columns (I2) and refinement (R1), the outward rows (I6) without; q̈, ν,
//     τcmd (T1), the solver's own d/dt v_rel (set_acceleration) meeting β, and the closure error
//     (L3, L1) against the oracle's;
//   - the closure error's rotation vector against Eigen's angle-axis, near 0 and near π;
//   - `at` as a frame fixed to the link: a set at an offset equals the set on a fixed link there;
//   - the scene's keys and the messages for a set that cannot work;
//   - the bundled four-bar and delta closed and simulated 10 s by RK4 with β from a stabilising law
//     of their closure error: the loops stay closed, the energy stays (the loops' forces do no work).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "solver/closure_error.hpp"
#include "solver/quad_scalar.hpp"
#include "solver/outward_sweep.hpp"
#include "solver/shared_body_sets.hpp"
#include "support/dense_rows.hpp"
#include "support/non_orthogonality.hpp"
#include "support/oracle_problem.hpp"
#include "support/rk4.hpp"
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

// As the dense-oracle test of sets on one link (test_dense_oracle.cpp): ‖a − b‖∞ / max(1, ‖b‖∞) of
// the double solver against the long-double oracle within max(1e-10, 100 eps cond(E)) (a double
// solve loses ~eps cond(E) in ν, q̈ up to ten times that), judged up to a ceiling of 1e-5
// (cond(E) ≤ 1e9 in double), the rest counted.
constexpr double kEps = std::numeric_limits<double>::epsilon();
double tolerance(LongDouble cond) { return std::max(1e-10, 100 * kEps * static_cast<double>(cond)); }
constexpr double kCeiling = 1e-5;

using test::attached;
using test::dense_rows;
using test::DenseRows;

struct LoopCase {
  std::string name;
  model::Chain chain;
  solver::DriverLayout layout;  // one torque instance, the sets, decomposed
  model::Vec3 gravity;
  bool planar = false;  // α in the plane of motion (x, y force; z moment)
};

solver::DriverLayout layout_with(std::vector<solver::ConstraintSet> sets) {
  solver::DriverLayout layout;
  layout.torques = {"tau_ff"};
  for (const auto& set : sets) layout.constraints += set.count;
  layout.sets = std::move(sets);
  layout.decompose_all();
  return layout;
}

solver::ConstraintSet between(const std::string& a, const model::Transform& at, const std::string& b,
                              const model::Transform& relative_at, std::size_t count) {
  solver::ConstraintSet set = solver::ConstraintSet::on(a, count);
  set.at = at;
  set.relative_to = b;
  set.relative_at = relative_at;
  return set;
}

std::vector<LoopCase> loop_cases() {
  std::vector<LoopCase> cases;
  {
    const scene::Scene s = scene::load_scene(test::source_path("robots/four_bar/four_bar_loop.yaml"));
    cases.push_back({"four_bar", scene::load_scene_chain(s), layout_with(s.layout.sets), s.gravity, true});
    cases.back().layout.sets[0].fixed.clear();  // directions drawn below, in the plane
    // The same loop closed by a 6-D set (a weld): three of its six directions are redundant at
    // every state, dropped by the pivoted factorisation (the dropped count asserted below).
    const solver::ConstraintSet& pin = s.layout.sets[0];
    cases.push_back({"four_bar_welded", cases.back().chain,
                     layout_with({between(pin.link, pin.at, pin.relative_to, pin.relative_at, 6)}), s.gravity});
  }
  {  // floating, world sets on the feet beside the knees' loops (robots/linkage_biped)
    const scene::Scene s = scene::load_scene(test::source_path("robots/linkage_biped/linkage_biped_stance.yaml"));
    cases.push_back({"linkage_biped", scene::load_scene_chain(s), layout_with(s.layout.sets), s.gravity});
    for (solver::ConstraintSet& set : cases.back().layout.sets) set.fixed.clear();  // drawn below
  }
  const model::Transform turned = model::origin_transform({0.05, -0.02, 0.1}, {0.3, -0.7, 1.1});
  const model::Transform other = model::origin_transform({-0.03, 0.04, 0.02}, {-1.2, 0.4, 0.25});
  cases.push_back({"dual_panda",
                   test::load_tree("robots/dual_panda/dual_panda.urdf", "station", {"left_panda_hand", "right_panda_hand"}),
                   layout_with({between("left_panda_hand", turned, "right_panda_hand", other, 6),
                                solver::ConstraintSet::on("left_panda_hand", 3)}),
                   {0, 0, -9.81}});
  cases.push_back({"quadruped",
                   test::load_tree("robots/quadruped/quadruped.urdf", "trunk", {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, true),
                   layout_with({between("FL_foot", turned, "FR_foot", {}, 3), solver::ConstraintSet::on("RL_foot", 3),
                                solver::ConstraintSet::on("RR_foot", 3)}),
                   {0, 0, -9.81}});
  return cases;
}

TEST(LoopSets, ReferenceSolverAgreesWithTheDenseRelativeRows) {
  test::RandomProblem random(46);
  test::SkipCount skips("loop sets against the dense oracle", 0.05);
  for (const LoopCase& c : loop_cases()) {
    const std::size_t nc = c.layout.constraints, n = c.chain.dof();
    for (const auto rows : {solver::ConstraintRows::inward_columns, solver::ConstraintRows::outward_rows}) {
      solver::SolverOptions options;
      options.gravity = c.gravity;
      options.constraint_rows = rows;
      // (R1) refines ν from the residual of d/dt v_rel, which holds (L5)'s term on its own: with the
      // refinement, a first pass without the term would come out right. The rows (I6) run without it.
      options.refinement = rows == solver::ConstraintRows::inward_columns;
      solver::ReferenceSolver<double> reference(c.chain, c.layout, options);
      test::OracleCase oracle_case{c.name, c.chain, {}};
      double worst = 0;
      for (int s = 0; s < test::state_count(200); ++s) {
        test::OracleProblem p = test::draw_problem(random, oracle_case, nc);
        if (c.planar)
          for (std::size_t k = 0; k < nc; ++k) {
            const double angle = random.uniform(-3.2, 3.2);
            p.alpha_columns[k] = {{0, 0, 0}, {std::cos(angle), std::sin(angle), 0}};
          }
        const solver::Solution<double>& sol = test::solve(reference, p, solver::Policy::original);
        const Oracle o(c.chain, p.base_gravity(c.gravity));
        const OracleVec q = test::to_long(p.q), qd = test::to_long(p.qd), tau = test::to_long(p.tau_ff);
        const OracleMat alpha = p.alpha(nc);
        const DenseRows<Oracle> dense = dense_rows(o, c.layout, c.chain, q, qd, alpha, test::to_long(p.beta));
        const OracleMat M = o.mass_matrix(q);
        const OracleMat E = Oracle::constraint_energy(M, dense.Jc);
        const std::string where = c.name + " state " + std::to_string(s) +
                                  (rows == solver::ConstraintRows::outward_rows ? " (I6)" : " (I2)");
        // E^A_cstr,0 = J M^-1 J^T with the relative rows (why E stays J M^-1 J^T: L4).
        const double e_energy = static_cast<double>(
            (reference.articulated().body[0].constraint_energy.cast<LongDouble>() - E).cwiseAbs().maxCoeff() /
            E.cwiseAbs().maxCoeff());
        EXPECT_LE(e_energy, 1e-11) << where;  // test_dense_oracle's kEnergyTolerance, its derivation
        // The directions the pivoted policy keeps (redundant ones dropped, as on one link).
        const auto kept = Oracle::kept_constraints(E, LongDouble(reference.model().pivot_tolerance));
        EXPECT_EQ(sol.dropped_pivots, static_cast<double>(nc - kept.size())) << where;
        OracleMat Jk(static_cast<Eigen::Index>(kept.size()), static_cast<Eigen::Index>(n));
        OracleVec rk(static_cast<Eigen::Index>(kept.size()));
        for (std::size_t j = 0; j < kept.size(); ++j) {
          Jk.row(static_cast<Eigen::Index>(j)) = dense.Jc.row(kept[j]);
          rk[static_cast<Eigen::Index>(j)] = dense.rhs[kept[j]];
        }
        const Oracle::KktSolution kkt = o.solve_rows(q, qd, tau, Jk, rk);
        const LongDouble cond = Oracle::condition(Oracle::constraint_energy(M, Jk));
        if (skips.skip(tolerance(cond) > kCeiling, "cond(E) > 1e9")) continue;
        OracleVec nu = OracleVec::Zero(static_cast<Eigen::Index>(nc));
        for (std::size_t j = 0; j < kept.size(); ++j) nu[kept[j]] = kkt.nu[static_cast<Eigen::Index>(j)];
        const double e_qdd = test::relative_error(sol.qdd, o.in_solver_coordinates(q, qd, kkt.qdd));
        const double e_nu = test::relative_error(sol.nu, nu);
        const double e_tau = test::relative_error(sol.tau_cmd, OracleVec(tau + dense.Jc.transpose() * nu));  // (T1)
        EXPECT_LE(e_qdd, tolerance(cond)) << where;
        EXPECT_LE(e_nu, tolerance(cond)) << where;
        EXPECT_LE(e_tau, tolerance(cond)) << where;
        // The solver's own d/dt v_rel (or Ẍ_A) meets β on the kept directions.
        for (std::size_t j = 0; j < kept.size(); ++j) {
          const std::size_t k = static_cast<std::size_t>(kept[j]), set = reference.model().constraint_set_of[k];
          const Oracle::Six achieved = test::to_six(sol.set_acceleration[set]);
          const LongDouble scale = std::max<LongDouble>(1, achieved.cwiseAbs().maxCoeff());
          EXPECT_LE(static_cast<double>(std::abs(alpha.col(kept[j]).dot(achieved) - p.beta[k]) / scale), tolerance(cond))
              << where << " direction " << k;
        }
        worst = std::max({worst, e_qdd / tolerance(cond), e_nu / tolerance(cond), e_tau / tolerance(cond)});
        // The closure error (L3, L1) against the oracle's, from its own poses and Jacobians: the
        // solver composes a few transforms (rounding ~10 eps of quantities below 10).
        std::size_t loop = 0;
        for (const solver::ConstraintSet& set : c.layout.constraint_sets()) {
          if (!set.relative()) continue;
          const auto A = attached<Oracle>(set.link, set.at), B = attached<Oracle>(set.relative_to, set.relative_at);
          const auto& [pose, velocity] = sol.closure_error.at(loop++);
          EXPECT_LE(test::relative_error(test::to_six(pose), o.pose_error(q, A, B)), 1e-13) << where;
          EXPECT_LE(test::relative_error(test::to_six(velocity), o.relative_motion(q, qd, A, B).velocity), 1e-13) << where;
        }
        EXPECT_EQ(loop, sol.closure_error.size());
      }
      std::printf("[loop sets] %s %s: largest error / tolerance %.3g\n", c.name.c_str(),
                  rows == solver::ConstraintRows::outward_rows ? "(I6)" : "(I2)", worst);
    }
  }
}

// The bundled closed-chain scenes in binary128: ReferenceSolver<Quad> against the dense rows of
// DenseDynamics<Quad> (Gauss' principle on α_k^T J_rel, (L2)), each as its scene states it
// (gravity, fixed directions; run-time ones and the states drawn at random, external forces 0):
// q̈ and ν within 100 (ε + δ) κ (ε = 2^-112; 100 ε κ the suite's factor for a solve against a
// dense one, test_dense_oracle.cpp; δ the model's non-orthogonality (support/non_orthogonality.hpp), 0 for the four-bar
// whose rotations are exact, ~1e-16 where a URDF turns by an angle double cannot hold exactly),
// κ = max(1, cond(E)) of the kept directions, judged where 100 (ε + δ) κ is at most 1e-6, the rest
// counted.
TEST(LoopSets, TheBundledLoopScenesAgreeWithTheDenseSolveInBinary128) {
  using Q = solver::Quad;
  using QOracle = oracle::DenseDynamics<Q>;
  const double eps = std::ldexp(1.0, -112);
  test::RandomProblem random(128);
  test::SkipCount skips("bundled loop scenes in binary128", 0.05);
  for (const char* path : {"robots/four_bar/four_bar_loop.yaml", "robots/delta/delta_loops.yaml",
                           "robots/dual_panda/dual_panda_box_loop.yaml", "robots/linkage_biped/linkage_biped_stance.yaml"}) {
    const scene::Scene s = scene::load_scene(test::source_path(path));
    const model::Chain chain = scene::load_scene_chain(s);
    solver::ReferenceSolver<Q> reference(chain, s.layout, s.solver_options());
    const std::size_t n = chain.dof(), nc = s.layout.constraints;
    const double delta = test::non_orthogonality(chain, s.layout);
    double worst = 0;
    for (int state = 0; state < test::state_count(8); ++state) {
      test::OracleProblem p = test::draw_problem(random, test::OracleCase{path, chain, {}}, nc);
      // A floating base upright: the oracle takes gravity in base coordinates as a double, R^T g
      // of a drawn rotation would be rounded there and not in the solver (the base still moves).
      p.base_rotation.setIdentity();
      solver::SolveInputs<double> in;
      in.q = p.q;
      in.qd = p.qd;
      in.torques = {p.tau_ff};
      in.wrenches.assign(s.layout.external_forces.size(), spatial::Force<double>{});
      std::size_t drawn = 0;
      in.alpha = solver::directions_with(s.layout, [&] { return p.alpha_columns[drawn++]; });
      in.beta = p.beta;
      in.base_rotation = p.base_rotation;
      const solver::Solution<Q>& sol = reference.run(in.cast<Q>(), solver::Policy::original);
      const QOracle o(chain, p.base_gravity(s.gravity));
      const QOracle::Vec q = p.q.cast<Q>(), qd = p.qd.cast<Q>(), tau = p.tau_ff.cast<Q>();
      QOracle::Mat alpha(6, static_cast<Eigen::Index>(nc));
      for (std::size_t k = 0; k < nc; ++k)
        alpha.col(static_cast<Eigen::Index>(k)) << in.alpha[k].moment.cast<Q>(), in.alpha[k].force.cast<Q>();
      const DenseRows<QOracle> dense = dense_rows(o, s.layout, chain, q, qd, alpha, QOracle::Vec(p.beta.cast<Q>()));
      const QOracle::Mat M = o.mass_matrix(q);
      const QOracle::Mat E = QOracle::constraint_energy(M, dense.Jc);
      const auto kept = QOracle::kept_constraints(E, reference.model().pivot_tolerance);
      const std::string where = std::string(path) + " state " + std::to_string(state);
      EXPECT_EQ(static_cast<double>(sol.dropped_pivots), static_cast<double>(nc - kept.size())) << where;
      QOracle::Mat Jk(static_cast<Eigen::Index>(kept.size()), static_cast<Eigen::Index>(n));
      QOracle::Vec rk(static_cast<Eigen::Index>(kept.size()));
      for (std::size_t j = 0; j < kept.size(); ++j) {
        Jk.row(static_cast<Eigen::Index>(j)) = dense.Jc.row(kept[j]);
        rk[static_cast<Eigen::Index>(j)] = dense.rhs[kept[j]];
      }
      const double kappa = std::max(1.0, static_cast<double>(QOracle::condition(QOracle::constraint_energy(M, Jk))));
      const double tolerance = 100 * (eps + delta) * kappa;
      if (skips.skip(tolerance > 1e-6, "tolerance beyond 1e-6")) continue;
      const QOracle::KktSolution kkt = o.solve_rows(q, qd, tau, Jk, rk);
      QOracle::Vec nu = QOracle::Vec::Zero(static_cast<Eigen::Index>(nc));
      for (std::size_t j = 0; j < kept.size(); ++j) nu[kept[j]] = kkt.nu[static_cast<Eigen::Index>(j)];
      const double e_qdd = static_cast<double>(oracle::relative_error<Q>(sol.qdd, o.in_solver_coordinates(q, qd, kkt.qdd)));
      const double e_nu = static_cast<double>(oracle::relative_error<Q>(sol.nu, nu));
      EXPECT_LE(e_qdd, tolerance) << where << " kappa " << kappa;
      EXPECT_LE(e_nu, tolerance) << where << " kappa " << kappa;
      worst = std::max({worst, e_qdd / ((eps + delta) * kappa), e_nu / ((eps + delta) * kappa)});
    }
    std::printf("[loop sets] %s in binary128 (model's rotations orthogonal to %.3g): largest error / ((eps + that) kappa) %.3g\n",
                path, delta, worst);
  }
}

// The rotation vector of the closure error (solver/closure_error.hpp) against Eigen's angle-axis
// of the same matrix, at random rotations, small ones (the w form's limit 1/2 w) and ones near π
// (the symmetric part's form; its sign from w). Both round: 1e-14 of a vector below π, except where
// the angle is within 1e-6 of π, where the axis Eigen reads from the symmetric part and the one
// here may differ by the rounding of sin θ relative to itself (θ − π of 1e-6: 2e-16 / 1e-6).
TEST(LoopSets, TheRotationVectorOfAClosureError) {
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (int n = 0; n < 3000; ++n) {
    const Eigen::Vector3d axis = Eigen::Vector3d(uniform(random), uniform(random), uniform(random)).normalized();
    const double angle = n < 1000 ? 3.14159 * std::abs(uniform(random))
                         : n < 2000 ? std::pow(10.0, -12 * std::abs(uniform(random)))
                                    : M_PI - std::pow(10.0, -1 - 5 * std::abs(uniform(random)));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    const Eigen::Vector3d v = solver::rotation_vector<double>(R);
    EXPECT_LE((v - angle * axis).cwiseAbs().maxCoeff(), 1e-14 + 2e-16 / (M_PI - angle)) << "angle " << angle;
  }
  EXPECT_EQ(solver::rotation_vector<double>(Eigen::Matrix3d::Identity()), Eigen::Vector3d::Zero());
}

// A set `at` an offset on its link is the set on a link fixed there: the four-bar's coupler_end
// sits at xyz 1 0 0 of the coupler, the end the scene's loop set names with `at`. The same numbers
// to rounding (the offset composed with the link's transform, or the fixed joint's).
TEST(LoopSets, AnOffsetIsALinkFixedThere) {
  const scene::Scene s = scene::load_scene(test::source_path("robots/four_bar/four_bar_loop.yaml"));
  const model::Chain chain = scene::load_scene_chain(s);
  solver::DriverLayout at_offset = layout_with(s.layout.sets), on_link = at_offset;
  on_link.sets[0].link = "coupler_end";
  on_link.sets[0].at = {};
  // And a world set at the same place (its own test of `at` on a set against the world).
  solver::DriverLayout world_at = layout_with({solver::ConstraintSet::on("coupler", 2, s.layout.sets[0].fixed)});
  world_at.sets[0].at = s.layout.sets[0].at;
  solver::DriverLayout world_on = layout_with({solver::ConstraintSet::on("coupler_end", 2, s.layout.sets[0].fixed)});
  solver::SolverOptions options;
  options.gravity = s.gravity;
  test::RandomProblem random(7);
  const test::OracleCase oracle_case{"four_bar", chain, {}};
  for (const auto& [a, b] : {std::pair{at_offset, on_link}, std::pair{world_at, world_on}}) {
    solver::ReferenceSolver<double> x(chain, a, options), y(chain, b, options);
    for (int n = 0; n < 50; ++n) {
      const test::OracleProblem p = test::draw_problem(random, oracle_case, 2);
      const solver::Solution<double> sx = test::solve(x, p, solver::Policy::original);
      const solver::Solution<double>& sy = test::solve(y, p, solver::Policy::original);
      // Both round the same products of a few terms of size ≤ 10 differently: 1e-12 relative.
      EXPECT_LE(test::relative_error(sx.qdd, sy.qdd), 1e-12);
      EXPECT_LE(test::relative_error(sx.nu, sy.nu), 1e-12);
    }
  }
}

// Sets that constrain one body's motion together are warned of (their directions beyond six are
// dependent); a set between two links constrains its body relative to the other, not the same motion
// as a set on it against the world: the dual Panda's box scene (a 6-D world set on the left hand, a
// 6-D set between the hands) has no warning, two sets between the same two hands have one.
TEST(LoopSets, OnlySetsOnTheSameMotionShareABody) {
  const model::Chain chain =
      test::load_tree("robots/dual_panda/dual_panda.urdf", "station", {"left_panda_hand", "right_panda_hand"});
  const solver::ConstraintSet world = solver::ConstraintSet::on("left_panda_hand", 6);
  const solver::ConstraintSet loop = between("left_panda_hand", {}, "right_panda_hand", {}, 6);
  const solver::ConstraintSet turned = between("right_panda_hand", {}, "left_panda_link7", {}, 3);
  EXPECT_TRUE(solver::shared_body_warnings({world, loop}, chain).empty());
  const std::vector<std::string> twice = solver::shared_body_warnings({world, loop, turned}, chain);
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_NE(twice[0].find("relative to the body of link"), std::string::npos) << twice[0];
}

// The scene's keys for a set between two links, and its mistakes named where they are.
TEST(LoopSets, SceneKeysAndTheirMistakes) {
  test::TempDir dir;
  std::filesystem::copy_file(test::source_path("robots/four_bar/four_bar.urdf"), dir.path() / "four_bar.urdf");
  const auto scene_with = [&](const std::string& set) {
    return dir.write("s.yaml", "sweepgen_scene: 1\nsolver: s\nurdf: four_bar.urdf\nroot: ground\ntips: [coupler, rocker]\n"
                               "drivers:\n  torques: [motor]\n  constraints:\n" + set);
  };
  const auto error_of = [&](const std::string& set) {
    try {
      scene::load_scene_chain(scene::load_scene(scene_with(set)));
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const scene::Scene s = scene::load_scene(scene_with(
      "    - {link: coupler, at: {xyz: [1, 0, 0]}, relative_to: ground, relative_at: {xyz: [1, 0.5, 0], rpy: [0, 0, 0.5]}, count: 2}\n"));
  ASSERT_EQ(s.layout.sets.size(), 1u);
  EXPECT_EQ(s.layout.sets[0].relative_to, "ground");  // the ground: a loop closed to the world (body 0)
  EXPECT_EQ(s.layout.sets[0].at.r, model::Vec3(1, 0, 0));
  EXPECT_NEAR(s.layout.sets[0].relative_at.E(0, 1), std::sin(0.5), 1e-16);  // E = R^T: row 0, column 1 is sin
  EXPECT_NO_THROW(scene::load_scene_chain(s));
  // Derivatives take a set between two links (D8's terms for it; tests/test_solve_derivatives.cpp).
  const scene::Scene differentiated = scene::load_scene(dir.write(
      "d.yaml", "sweepgen_scene: 1\nsolver: d\nurdf: four_bar.urdf\nroot: ground\ntips: [coupler, rocker]\nderivatives: true\n"
                "drivers:\n  torques: [motor]\n  constraints:\n    - {link: coupler, relative_to: rocker, count: 2}\n"));
  EXPECT_TRUE(differentiated.derivatives);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: rocke, count: 2}\n").find("did you mean 'rocker'"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: coupler_end, count: 2}\n").find("never move apart"), std::string::npos);
  EXPECT_NE(error_of("    - {link: ground, relative_to: rocker, count: 2}\n").find("as 'relative_to'"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_at: {xyz: [1, 0, 0]}, count: 2}\n").find("give relative_to"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, at: {xyz: [1, 0]}, count: 2}\n").find("expected 3 numbers"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: coupler, count: 2}\n").find("never move apart"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, at: {xyz: [.nan, 0, 0]}, relative_to: rocker, count: 2}\n")
                .find("at.xyz[0]: number is not finite"),
            std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: rocker, relative_at: {rpy: [0, .inf, 0]}, count: 2}\n")
                .find("relative_at.rpy[1]: number is not finite"),
            std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, at: {xzy: [1, 0, 0]}, count: 2}\n").find("unknown key"), std::string::npos);
  // Redundant directions of a set between two links are the rule, not an error (a planar loop
  // closed by a 6-D set): the scene loads, and the warning counts the joints between the links
  // (the coupler and the rocker move apart by three, not by the two to the base), and fixed
  // directions no joint moves are taken (they are among the redundant ones).
  EXPECT_EQ(error_of("    - {link: coupler, relative_to: rocker, count: 6}\n"), "no error");
  EXPECT_EQ(error_of("    - {link: coupler, relative_to: rocker, directions: [[0, 0, 0, 0, 0, 1], [0, 0, 0, 1, 0, 0]]}\n"),
            "no error");
  solver::ConstraintSet welded = between("coupler", {}, "rocker", {}, 6), pinned = welded;
  pinned.count = 3;
  const model::Chain chain = scene::load_scene_chain(s);
  const std::vector<std::string> warned = solver::redundant_loop_warnings({welded, pinned}, chain);
  ASSERT_EQ(warned.size(), 1u);
  EXPECT_NE(warned[0].find("holds 6 directions but only 3 joints"), std::string::npos) << warned[0];
  EXPECT_TRUE(solver::redundant_loop_warnings({between("coupler", {}, "crank", {}, 1)}, chain).empty());
  EXPECT_EQ(solver::redundant_loop_warnings({between("coupler", {}, "crank", {}, 2)}, chain).size(), 1u);
  // A world set still may not ask more than its joints give.
  EXPECT_NE(error_of("    - {link: crank, count: 2}\n").find("only 1 joint"), std::string::npos);
}

// A bundled scene's loops closed and simulated by RK4, undriven and undamped, β from a stabilising
// law of each set's own closure error (L1, L3; the README's "Closed chains"):
// β = −Kd α^T v_rel − Kp α^T e, e = [the rotation vector of R_B^T R_A; R_A^T (p_A − p_B)] from ᴬX_B
// (relative_pose) and v_rel from the outward sweep.
class LoopSimulation {
 public:
  LoopSimulation(const std::string& scene, const model::Vec3& gravity)
      : scene_(scene::load_scene(test::source_path(scene))),
        chain_(scene::load_scene_chain(scene_)),
        reference_(chain_, scene_.layout, options(gravity)),
        energy_of_(chain_, gravity),
        alpha_(solver::directions_with(scene_.layout, [] { return spatial::Force<double>{}; })) {}

  std::size_t dof() const { return chain_.dof(); }
  std::size_t directions() const { return alpha_.size(); }

  // α_k^T e and α_k^T v_rel of every direction (all sets here join two links).
  Eigen::VectorXd closure(const Eigen::VectorXd& q) { return along_directions(q, Eigen::VectorXd::Zero(dof()), true); }
  Eigen::VectorXd relative_velocity(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    return along_directions(q, qd, false);
  }

  // Closes the loops by Newton's method on the joints `free` (as many as directions), the others
  // held; then q̇ on those joints such that v_rel = 0 (linear in q̇: its columns by unit vectors).
  void close(Eigen::VectorXd& q, Eigen::VectorXd& qd, const std::vector<Eigen::Index>& free) {
    ASSERT_EQ(free.size(), directions());
    const Eigen::Index m = static_cast<Eigen::Index>(free.size());
    for (int iteration = 0; iteration < 50 && closure(q).norm() > 1e-15; ++iteration) {
      Eigen::MatrixXd J(m, m);
      for (Eigen::Index j = 0; j < m; ++j) {
        Eigen::VectorXd plus = q, minus = q;
        plus[free[j]] += 1e-7;
        minus[free[j]] -= 1e-7;
        J.col(j) = (closure(plus) - closure(minus)) / 2e-7;
      }
      const Eigen::VectorXd step = J.fullPivLu().solve(closure(q));
      for (Eigen::Index j = 0; j < m; ++j) q[free[j]] -= step[j];
    }
    Eigen::MatrixXd J(m, m);
    for (Eigen::Index j = 0; j < m; ++j) J.col(j) = relative_velocity(q, Eigen::VectorXd::Unit(dof(), free[j]));
    Eigen::VectorXd held = qd;
    for (Eigen::Index j : free) held[j] = 0;
    const Eigen::VectorXd solved = J.fullPivLu().solve(-relative_velocity(q, held));
    for (Eigen::Index j = 0; j < m; ++j) qd[free[j]] = solved[j];
  }

  Eigen::VectorXd accelerate(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double Kp, double Kd) {
    solver::SolveInputs<double> in;
    in.q = q;
    in.qd = qd;
    in.torques = {Eigen::VectorXd::Zero(dof())};
    in.alpha = alpha_;
    in.beta = solver::ConstraintVector<double>(-Kd * relative_velocity(q, qd) - Kp * closure(q));
    const solver::Solution<double>& sol = reference_.run(in, solver::Policy::original);
    EXPECT_EQ(reference_.status(), solver::status_ok);
    return sol.qdd;
  }

  double energy(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    return 0.5 * qd.dot(energy_of_.mass_matrix(q) * qd) + energy_of_.potential_energy(q);
  }

 private:
  solver::SolverOptions options(const model::Vec3& gravity) const {
    solver::SolverOptions o = scene_.solver_options();
    o.gravity = gravity;
    return o;
  }
  Eigen::VectorXd along_directions(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, bool pose) {
    reference_.outward(q, qd);
    const solver::SolverModel<double>& model = reference_.model();
    Eigen::VectorXd out(static_cast<Eigen::Index>(directions()));
    for (std::size_t c = 0; c < model.constraint_sets.size(); ++c) {
      spatial::Motion<double> e = reference_.kinematics().loop[c].relative_velocity;
      if (pose) {
        const spatial::Transform<double> A_X_B = solver::relative_pose(model, reference_.kinematics(), c);
        const Eigen::AngleAxisd turn(Eigen::Matrix3d(A_X_B.E.transpose()));  // R_B^T R_A, angle in [0, π]
        e = {turn.angle() * turn.axis(), A_X_B.E * A_X_B.r};                  // (L3)
      }
      const solver::ConstraintSetModel<double>& set = model.constraint_sets[c];
      for (std::size_t k = set.first; k < set.first + set.count; ++k)
        out[static_cast<Eigen::Index>(k)] = alpha_[k].moment.dot(e.angular) + alpha_[k].force.dot(e.linear);
    }
    return out;
  }

  scene::Scene scene_;
  model::Chain chain_;
  solver::ReferenceSolver<double> reference_;
  oracle::DenseDynamics<double> energy_of_;
  std::vector<spatial::Force<double>> alpha_;
};

// 10 s of RK4 at 1 ms from (q, q̇), closed on `free`: the largest closure error and relative
// energy change along the way, and the state at the end.
struct TenSeconds {
  double open = 0, drift = 0;
  Eigen::VectorXd q;
};
TenSeconds ten_seconds(LoopSimulation& loops, Eigen::VectorXd q, Eigen::VectorXd qd, const std::vector<Eigen::Index>& free,
                       double Kp, double Kd) {
  loops.close(q, qd, free);
  EXPECT_LT(loops.closure(q).norm(), 1e-14) << "a closed start";
  EXPECT_LT(loops.relative_velocity(q, qd).norm(), 1e-13) << "a consistent start";
  const double e0 = loops.energy(q, qd);
  TenSeconds run;
  const auto accelerate = [&](const Eigen::VectorXd& p, const Eigen::VectorXd& pd) { return loops.accelerate(p, pd, Kp, Kd); };
  for (int step = 0; step < 10000; ++step) {
    test::rk4_step(accelerate, q, qd, 1e-3);
    run.open = std::max(run.open, loops.closure(q).cwiseAbs().maxCoeff());
    run.drift = std::max(run.drift, std::abs(loops.energy(q, qd) - e0) / std::abs(e0));
  }
  run.q = q;
  return run;
}

// The four-bar (robots/four_bar) from the crank at 1 rad turning at 3 rad/s, under gravity in its
// plane; the delta (robots/delta) with its platform moving at 8 mm/s from 0.45 m below the base
// (without gravity, which would fold it onto its singular lowest pose within a second: the
// mechanism coasts, its kinetic energy the one to keep). Both hold the bounds, closure
// 1e-8 (m, rad) and energy 1e-6, with Kp = 100 /s², Kd = 20 /s (ω = 10 /s, critically damped,
// far below the step's 1000 /s), to the integrator's error: RK4's global error C h^4 (measured
// figures printed).
TEST(LoopSets, AFourBarAndADeltaStayClosedForTenSeconds) {
  {
    LoopSimulation four_bar("robots/four_bar/four_bar_loop.yaml", {0, -9.81, 0});
    Eigen::VectorXd q(3), qd(3);
    q << 1.0, -0.5, 1.5;  // the crank's angle held, the others closed by Newton (the coupler above the ground)
    qd << 3, 0, 0;
    const TenSeconds run = ten_seconds(four_bar, q, qd, {1, 2}, 100, 20);
    std::printf("[loop sets] four-bar, 10 s of RK4 at 1 ms: closure %.3g m, energy drift %.3g (crank at %.3g rad)\n",
                run.open, run.drift, run.q[0]);
    EXPECT_LE(run.open, 1e-8);
    EXPECT_LE(run.drift, 1e-6);
    EXPECT_GT(std::abs(run.q[0] - 1.0), 6.3) << "the crank turned fully";
  }
  {
    LoopSimulation delta("robots/delta/delta_loops.yaml", {0, 0, 0});
    // Joints (the first tip's path first): the platform's x, y, z (0..2); per arm its shoulder, elbow
    // swing and tilt (3..11).
    Eigen::VectorXd q = Eigen::VectorXd::Zero(12), qd = Eigen::VectorXd::Zero(12);
    for (int arm = 0; arm < 3; ++arm) q.segment<3>(3 + 3 * arm) << 0.5, 1.9, 0;
    q[2] = -0.45;
    qd.head<3>() << 0.006, -0.003, 0.004;
    const TenSeconds run = ten_seconds(delta, q, qd, {3, 4, 5, 6, 7, 8, 9, 10, 11}, 100, 20);
    std::printf("[loop sets] delta, 10 s of RK4 at 1 ms: closure %.3g m, energy drift %.3g (platform at %.3g %.3g %.3g m)\n",
                run.open, run.drift, run.q[0], run.q[1], run.q[2]);
    EXPECT_LE(run.open, 1e-8);
    EXPECT_LE(run.drift, 1e-6);
    EXPECT_GT((run.q.head<3>() - Eigen::Vector3d(0, 0, -0.45)).norm(), 0.05) << "the platform moved";
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

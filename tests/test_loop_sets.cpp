// Constraint sets between two links (docs/derivation.md, L1, L4, L5) in the reference solver:
//   - against the dense oracle's Gauss principle with the relative Jacobian J_A − ᴬX_B J_B and the
//     bias of (L2) (DenseDynamics::relative_motion), at random (open) states: the planar four-bar
//     (robots/four_bar), the dual Panda with a 6-D set between its hands at turned offsets beside a
//     world set, and the quadruped on its floating base with a set between two feet beside two world
//     sets; with the inward columns (I2) and the outward rows (I6); q̈, ν, τcmd (T1) and the solver's
//     own d/dt v_rel (set_acceleration) meeting β;
//   - `at` as a frame fixed to the link: a set at an offset equals the set on a fixed link there;
//   - the scene's keys and the messages for a set that cannot work.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "solver/outward_sweep.hpp"
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

// The oracle's frame for a set's frame A (or B): the transform link -> frame as R (frame -> link
// coordinates) and p (its origin in the link's).
Oracle::AttachedFrame attached(const std::string& link, const model::Transform& X) {
  return {link, X.E.transpose().cast<LongDouble>(), X.r.cast<LongDouble>()};
}

// The dense rows of every set: α_k^T J_A (a world set: A's frame is its link's here) or α_k^T J_rel
// (L2), right-hand side β_k − α_k^T c.
struct DenseRows {
  OracleMat Jc;
  OracleVec rhs;
};
DenseRows dense_rows(const Oracle& o, const solver::DriverLayout& layout, const model::Chain& chain, const OracleVec& q,
                     const OracleVec& qd, const OracleMat& alpha, const OracleVec& beta) {
  const Eigen::Index n = static_cast<Eigen::Index>(chain.dof()), nc = alpha.cols();
  DenseRows rows{OracleMat(nc, n), OracleVec(nc)};
  Eigen::Index k = 0;
  for (const solver::ConstraintSet& set : layout.constraint_sets()) {
    const OracleMat a = alpha.middleCols(k, static_cast<Eigen::Index>(set.count));
    Oracle::Jacobian J;
    Oracle::Six c;
    if (set.relative()) {
      const auto r = o.relative_motion(q, qd, attached(set.link, set.at), attached(set.relative_to, set.relative_at));
      J = r.J;
      c = r.drift;
    } else {
      EXPECT_TRUE(set.at.E.isIdentity() && set.at.r.isZero()) << "the oracle's world rows are at the link's frame";
      J = o.jacobian(q, set.link_in(chain));
      c = o.drift(q, qd, set.link_in(chain));
    }
    rows.Jc.middleRows(k, a.cols()) = a.transpose() * J;
    rows.rhs.segment(k, a.cols()) = beta.segment(k, a.cols()) - a.transpose() * c;
    k += a.cols();
  }
  return rows;
}

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
        const DenseRows dense = dense_rows(o, c.layout, c.chain, q, qd, alpha, test::to_long(p.beta));
        const OracleMat M = o.mass_matrix(q);
        const OracleMat E = dense.Jc * M.ldlt().solve(dense.Jc.transpose());
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
        const LongDouble cond = Oracle::condition(Jk * M.ldlt().solve(Jk.transpose()));
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
      }
      std::printf("[loop sets] %s %s: largest error / tolerance %.3g\n", c.name.c_str(),
                  rows == solver::ConstraintRows::outward_rows ? "(I6)" : "(I2)", worst);
    }
  }
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
  EXPECT_NE(error_of("    - {link: coupler, relative_to: rocke, count: 2}\n").find("did you mean 'rocker'"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: coupler_end, count: 2}\n").find("never move apart"), std::string::npos);
  EXPECT_NE(error_of("    - {link: ground, relative_to: rocker, count: 2}\n").find("as 'relative_to'"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_at: {xyz: [1, 0, 0]}, count: 2}\n").find("give relative_to"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, at: {xyz: [1, 0]}, count: 2}\n").find("expected 3 numbers"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, at: {xzy: [1, 0, 0]}, count: 2}\n").find("unknown key"), std::string::npos);
  // The joints between the two links, not those to the base, bound a set between them: the
  // coupler and the rocker move apart by three joints; four directions over-determine them.
  EXPECT_NE(error_of("    - {link: coupler, relative_to: rocker, count: 4}\n").find("only 3 joints"), std::string::npos);
  EXPECT_NE(error_of("    - {link: coupler, relative_to: crank, count: 2}\n").find("only 1 joint"), std::string::npos);
}

// The four-bar closed by its scene's loop set and simulated 10 s by RK4 (step 1 ms) from a closed,
// consistent state, undriven and undamped, β from a stabilising law of the set's own closure error
// (L1, L3; the README's "Closed chains"): β = −Kd α^T v_rel − Kp α^T e, e the position part
// R_A^T (p_A − p_B) of ᴬX_B (relative_pose). The loop stays closed and the energy stays, both to
// the integrator's error: RK4's global error C h^4 over 10 s of this motion measured below 1e-10
// (closure) and 1e-8 (energy), against the bounds 1e-8 m and 1e-6 relative; a missing
// product term (L5) opens the loop by millimetres within the first second.
TEST(LoopSets, AFourBarStaysClosedForTenSeconds) {
  const scene::Scene s = scene::load_scene(test::source_path("robots/four_bar/four_bar_loop.yaml"));
  const model::Chain chain = scene::load_scene_chain(s);
  solver::ReferenceSolver<double> reference(chain, s.layout, s.solver_options());
  const oracle::DenseDynamics<double> energy_of(chain, s.gravity);
  const solver::SolverModel<double>& model = reference.model();
  // Closed with the crank at 1 rad, a coupler angle and a rocker angle from the loop's geometry
  // (crank 0.35 m, coupler 1 m, rocker 0.8 m, ground 1 m; robots/four_bar/four_bar.urdf).
  const double crank = 0.35, coupler = 1.0, rocker = 0.8, ground = 1.0, q1 = 1.0;
  const Eigen::Vector2d crank_end(crank * std::cos(q1), crank * std::sin(q1)), d = Eigen::Vector2d(ground, 0) - crank_end;
  const double l = d.norm(), along = (coupler * coupler - rocker * rocker + l * l) / (2 * l);
  const Eigen::Vector2d joint = crank_end + along * d / l + std::sqrt(coupler * coupler - along * along) * Eigen::Vector2d(-d.y(), d.x()) / l;
  Eigen::VectorXd q(3), qd(3);
  q << q1, std::atan2(joint.y() - crank_end.y(), joint.x() - crank_end.x()) - q1, std::atan2(joint.y(), joint.x() - ground);
  // The crank at 3 rad/s, the others as the loop allows: the rows α^T J_rel q̇ = 0, from the solver's
  // own relative velocity (linear in q̇: two unit columns give J_rel).
  const auto relative_velocity = [&](const Eigen::VectorXd& p, const Eigen::VectorXd& pd) {
    reference.outward(p, pd);
    const spatial::Motion<double>& v = reference.kinematics().loop[0].relative_velocity;
    return Eigen::Vector2d(v.linear.x(), v.linear.y());
  };
  Eigen::Matrix2d columns;
  columns << relative_velocity(q, Eigen::Vector3d(0, 1, 0)), relative_velocity(q, Eigen::Vector3d(0, 0, 1));
  qd << 3, columns.lu().solve(-relative_velocity(q, Eigen::Vector3d(3, 0, 0)));
  const double Kp = 100, Kd = 20;  // ω = 10 /s, critically damped: far below the step's 1000 /s
  const auto closure = [&](const Eigen::VectorXd& p) {
    reference.outward(p, Eigen::VectorXd::Zero(3));
    const spatial::Transform<double> A_X_B = solver::relative_pose(model, reference.kinematics(), 0);
    return Eigen::Vector3d(A_X_B.E * A_X_B.r);  // R_A^T (p_A − p_B) (L3)
  };
  const auto accelerate = [&](const Eigen::VectorXd& p, const Eigen::VectorXd& pd) {
    const Eigen::Vector2d e = closure(p).head<2>(), v = relative_velocity(p, pd);
    solver::SolveInputs<double> in;
    in.q = p;
    in.qd = pd;
    in.torques = {Eigen::VectorXd::Zero(3)};
    in.alpha = solver::directions_with(s.layout, [] { return spatial::Force<double>{}; });  // the fixed pair
    in.beta = solver::ConstraintVector<double>(-Kd * v - Kp * e);
    const solver::Solution<double>& sol = reference.run(in, solver::Policy::original);
    EXPECT_EQ(reference.status(), solver::status_ok);
    return Eigen::VectorXd(sol.qdd);
  };
  const auto energy = [&](const Eigen::VectorXd& p, const Eigen::VectorXd& pd) {
    return 0.5 * pd.dot(energy_of.mass_matrix(p) * pd) + energy_of.potential_energy(p);
  };
  ASSERT_LT(closure(q).norm(), 1e-15);
  ASSERT_LT(relative_velocity(q, qd).norm(), 1e-14);
  const double e0 = energy(q, qd);
  double open = 0, drift = 0;
  for (int step = 0; step < 10000; ++step) {
    test::rk4_step(accelerate, q, qd, 1e-3);
    open = std::max(open, closure(q).norm());
    drift = std::max(drift, std::abs(energy(q, qd) - e0) / std::abs(e0));
  }
  std::printf("[loop sets] four-bar, 10 s of RK4 at 1 ms: closure %.3g m, energy drift %.3g (crank at %.3g rad)\n", open,
              drift, q[0]);
  EXPECT_LE(open, 1e-8);
  EXPECT_LE(drift, 1e-6);
  EXPECT_GT(std::abs(q[0] - q1), 1.0) << "the mechanism moved";
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

// (D8)'s closed-form Jacobians of the solve's residuals (docs/derivation.md; solver/residual_jacobians.hpp)
// against what (D1) computes for the same residuals: the forward-mode tangents of
//   ρ = τcmd(T1) − τcmd(T2),  r = E_cstr − αᵀ Ẍ_link (R1)
// through the rigid-body sweeps (O1–O4, S5, T1, T2) with q and q̇ seeded along (D2)'s columns and
// the solution (q̈, ν) held, both in binary128, where the two agree to far below double's rounding:
// the formulas, not their rounding, are under test here (the derivatives' rounding end to end is
// tests/test_solve_derivatives.cpp's). On every kind of bundled scene: a chain with
// external forces and run-time directions, constraint sets, a tree, prismatic joints, floating
// bases (where the q columns are the base's rotation vector's, (D2)), sets between two links,
// coupled <mimic> joints; and
// random chains, trees and floating trees with joints about random axes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "solver/outward_sweep.hpp"
#include "solver/quad_scalar.hpp"
#include "solver/residual_jacobians.hpp"
#include "solver/solver_sweep.hpp"
#include "support/derivative_case.hpp"
#include "support/oracle_problem.hpp"
#include "support/random_chain.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using solver::Dual;
using solver::Quad;

// ∂ρ/∂(q, q̇) over ∂r/∂(q, q̇): rows the N joints then the Nc directions, columns q then q̇.
template <class T>
using Matrix = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

template <class T>
Matrix<T> stacked(const Matrix<T>& rho_q, const Matrix<T>& rho_qd, const Matrix<T>& r_q, const Matrix<T>& r_qd) {
  Matrix<T> m(rho_q.rows() + r_q.rows(), 2 * rho_q.cols());
  m << rho_q, rho_qd, r_q, r_qd;
  return m;
}

// A robot and its drivers: a bundled scene's, or a random one's.
struct Case {
  model::Chain chain;
  solver::DriverLayout layout;
  solver::SolverOptions options;
};

// (D8) at the solution `original` returns for `in`.
Matrix<Quad> closed_form(const Case& c, const solver::SolveInputs<Quad>& in) {
  solver::ReferenceSolver<Quad> s(c.chain, c.layout, c.options);
  s.run(in, solver::Policy::original);
  const auto J = solver::residual_jacobians(s.model(), s.kinematics(), in.qd, s.drivers(), s.solution());
  return stacked<Quad>(J.rho_q, J.rho_qd, J.r_q, J.r_qd);
}

// (D1) in binary128: the residuals' tangents with q̈ and ν those of `held` (the closed form's).
Matrix<Quad> forward_mode(const Case& c, const solver::SolveInputs<Quad>& in) {
  using D = Dual<Quad>;
  solver::ReferenceSolver<Quad> values(c.chain, c.layout, c.options);
  const solver::Solution<Quad>& solved = values.run(in, solver::Policy::original);
  const solver::SolverModel<D> model(c.chain, c.layout, c.options, 1e-16);
  const std::size_t n = model.dof(), nc = model.constraints(), base = model.base_coordinates();
  // A coupled joint has no column (D2): its q and q̇ follow its source's, whose tangent carries it.
  const auto columns = solver::DerivativeColumns::of(n, model.set_directions(), model.couplings);
  const solver::SeededKinematics<Quad> seeds = solver::seeded_kinematics(in.q, in.qd, in.base_rotation, base, columns);
  auto kin = solver::KinematicsState<D>::sized(n);
  solver::outward_sweep_base_to_tip(model, seeds.q, seeds.qd, kin, seeds.base_rotation);
  auto drivers = solver::DriverInputs<D>::sized(c.layout, n);
  for (std::size_t t = 0; t < in.torques.size(); ++t) drivers.torques[t] = in.torques[t].template cast<D>();
  const auto force = [](const spatial::Force<Quad>& f) {
    return spatial::Force<D>{f.moment.template cast<D>(), f.force.template cast<D>()};
  };
  for (std::size_t e = 0; e < in.wrenches.size(); ++e) drivers.external_forces[e] = force(in.wrenches[e]);
  for (std::size_t k = 0; k < in.alpha.size(); ++k) drivers.constraint_directions[k] = force(in.alpha[k]);
  auto held = solver::Solution<D>::sized(n, nc, c.layout.listed_sets(), 0, model.couplings.size());
  held.qdd = solved.qdd.template cast<D>();
  held.nu = solved.nu.template cast<D>();
  solver::accelerations_of_motion(model, kin, held);
  const solver::ConstraintVector<D> r =
      solver::constraint_residuals(model, kin, drivers, solver::ConstraintVector<D>(in.beta.template cast<D>()), held);
  solver::inverse_dynamics_torque_tip_to_base(model, kin, drivers, held);
  const solver::JointVector<D> needed = held.tau_cmd;
  solver::constraint_torque_tip_to_base(model, kin, drivers, held);
  const solver::JointVector<D> rho = held.tau_cmd - needed;
  Matrix<Quad> m(n + nc, 2 * n);
  const auto e = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
  m.setZero();
  for (std::size_t x = 0; x < n; ++x) {
    if (columns.is_coupled(x)) continue;  // (D8) folds its column into its source's
    const std::size_t place = columns.independent(x);
    for (std::size_t j = 0; j < n; ++j) {
      m(e(j), e(x)) = rho[e(j)].derivative(columns.q(place));
      m(e(j), e(n + x)) = rho[e(j)].derivative(columns.qd(place));
    }
    for (std::size_t k = 0; k < nc; ++k) {
      m(e(n + k), e(x)) = r[e(k)].derivative(columns.q(place));
      m(e(n + k), e(n + x)) = r[e(k)].derivative(columns.qd(place));
    }
  }
  return m;
}

// The largest magnitude of row r: the scale each entry of the row is judged against (a joint's ρ
// and a direction's r have units and sizes of their own).
double row_scale(const Matrix<Quad>& m, Eigen::Index r) {
  double scale = 0;
  for (Eigen::Index x = 0; x < m.cols(); ++x) scale = std::max(scale, std::abs(static_cast<double>(m(r, x))));
  return std::max(1.0, scale);
}

// How far the model's rotations are from orthogonal: the largest entry of E_Tᵀ E_T − 1 over the
// joints' tree transforms and the frames of the links (external forces, constraint sets). A
// rotation that is not a quarter turn is a double-rounded matrix (F2), orthogonal to ~1e-16 only.
double rotation_defect(const model::Chain& chain) {
  double defect = 0;
  const auto add = [&](const model::Mat3& E) {  // in binary128: double's own product would round the defect away
    const spatial::Mat3<Quad> e = E.cast<Quad>();
    const spatial::Mat3<Quad> defects = e.transpose() * e - spatial::Mat3<Quad>(spatial::Mat3<Quad>::Identity());
    for (Eigen::Index k = 0; k < 9; ++k) defect = std::max(defect, std::abs(static_cast<double>(defects.data()[k])));
  };
  for (std::size_t i = 1; i < chain.joints.size(); ++i) add(chain.joints[i].tree_transform.E);
  for (const auto& [link, frame] : chain.frames) add(frame.X.E);
  return defect;
}

// How far the bodies' inertias are from rigid ones, relatively: B = h× and C = m 1 hold only to the
// rounding of the links lumped into a body (F4: Xᵀ M X in double), and (D8) reads h from B's lower
// entries and m from C's first.
double inertia_defect(const model::Chain& chain) {
  double defect = 0;
  for (std::size_t i = 1; i < chain.bodies.size(); ++i) {
    const spatial::Inertia<double>& M = chain.bodies[i].inertia;
    const double m = M.C(0, 0);
    if (m <= 0) continue;
    const double h = std::max(M.B.cwiseAbs().maxCoeff(), m);
    defect = std::max({defect, (M.B + M.B.transpose()).cwiseAbs().maxCoeff() / h,
                       (M.C - model::Mat3::Identity() * m).cwiseAbs().maxCoeff() / m});
  }
  return defect;
}

// The tolerance, per entry, times max(1, the row's largest magnitude) (a joint's ρ and a
// direction's r have units and sizes of their own). Both are exact derivatives of the same
// residuals in binary128, apart from three things:
//  - rounding, ε_q = 2⁻¹¹² ≈ 1.9e-34 per operation over at most a few thousand operations (N ≤ 15
//    bodies, 6-vector products) and cancellations of at most the ratio of the subtree's force to
//    the row's entries (≤ 1e4 on these robots): ≤ 1e3 · 1e4 · 1.9e-34 ≈ 2e-27; floor 1e-26;
//  - the model's rotations, orthogonal only to δ_R = rotation_defect: X⁻¹ applied as [Eᵀ ...] is
//    then the inverse of X to δ_R only, which (D1) differentiates as the sweeps compute it and
//    (D8), which takes every transform for an isometry, does not. Each of the ≤ 2N transforms on a
//    path changes a product by ≤ 3 δ_R (a row of E), in each of ≤ 6 terms of an entry: ≤ 36 N δ_R;
//  - the inertias, rigid only to δ_I = inertia_defect: ≤ 6 terms of an entry, each off by δ_I of
//    its size: ≤ 6 δ_I.
// Bound: 1e-26 + 64 N (δ_R + δ_I). A wrong term is of the order of the entry itself (1 of the
// scale), against a ceiling of 1e-26 + 64 · 15 · 1.3e-15 ≈ 1.3e-12 (δ ≤ 1.3e-15 here: the random
// robots' rotations are products of double-rounded ones; the bundled ones' at most 4e-17).
double tolerance(const model::Chain& chain) {
  return 1e-26 + 64.0 * static_cast<double>(chain.dof()) * (rotation_defect(chain) + inertia_defect(chain));
}

// Every entry of every state's Jacobians; prints the worst against the bound.
void check(const Case& c, const std::string& name, const std::vector<solver::SolveInputs<Quad>>& states) {
  const double bound = tolerance(c.chain);
  double worst = 0;
  for (const solver::SolveInputs<Quad>& in : states) {
    const Matrix<Quad> closed = closed_form(c, in);
    const Matrix<Quad> forward = forward_mode(c, in);
    ASSERT_EQ(closed.rows(), forward.rows());
    ASSERT_EQ(closed.cols(), forward.cols());
    for (Eigen::Index r = 0; r < closed.rows(); ++r) {
      const double scale = row_scale(forward, r);
      for (Eigen::Index x = 0; x < closed.cols(); ++x) {
        const double error = std::abs(static_cast<double>(closed(r, x) - forward(r, x))) / scale;
        worst = std::max(worst, error);
        EXPECT_LE(error, bound) << name << " row " << r << " column " << x;
      }
    }
  }
  std::printf("[rounding] %s (D8) against (D1) in binary128: worst %.3g of the row's scale, bound %.3g "
              "(rotations orthogonal to %.3g, inertias rigid to %.3g)\n",
              name.c_str(), worst, bound, rotation_defect(c.chain), inertia_defect(c.chain));
}

void check_scene(const std::string& relative, std::size_t states) {
  const test::SceneCase scene = test::load_scene_case(relative);
  std::vector<solver::SolveInputs<Quad>> inputs;
  for (const report::Problem& p : report::random_problems(scene.scene, scene.chain, states, 41)) inputs.push_back(p.cast<Quad>());
  check({scene.chain, scene.scene.layout, scene.scene.solver_options()}, relative, inputs);
}

// Random robots (tests/support/random_chain.hpp): joints about random axes, prismatic ones, random
// tree transforms and inertias, rotor inertia, lumped frames; one or two external forces on random
// links and, where the robot has the joints for them, two directions at the tip.
void check_random(bool tree, bool floating_tree) {
  test::RandomChainGenerator generator(tree ? 7 : floating_tree ? 11 : 5);
  test::RandomProblem random(13);
  for (int robot = 0; robot < 12; ++robot) {
    const test::OracleCase c = test::random_case(generator, tree, floating_tree);
    const std::size_t nc = std::min<std::size_t>(2, c.chain.dof() - c.chain.base_coordinates());
    const Case robot_case{c.chain, test::oracle_layout(c, nc), {}};
    std::vector<solver::SolveInputs<Quad>> inputs;
    for (int state = 0; state < 3; ++state) {
      const test::OracleProblem p = test::draw_problem(random, c, nc);
      solver::SolveInputs<double> in{p.q, p.qd, {p.tau_ff}, p.wrenches, {}, p.beta, p.base_rotation};
      for (std::size_t k = 0; k < nc; ++k) in.alpha.push_back(p.alpha_columns[k]);
      inputs.push_back(in.cast<Quad>());
    }
    check(robot_case, c.name, inputs);
  }
}

TEST(ResidualJacobians, ChainWithExternalForcesAndRunTimeDirections) { check_scene("panda/panda_nc6.yaml", 20); }
TEST(ResidualJacobians, ConstraintSetsOnSeveralLinks) { check_scene("panda/panda_sets.yaml", 20); }
TEST(ResidualJacobians, TreeWithSetsOnBothArms) { check_scene("dual_panda/dual_panda_box.yaml", 10); }
TEST(ResidualJacobians, PrismaticJoint) { check_scene("planar/planar_nc2.yaml", 20); }
TEST(ResidualJacobians, FloatingBase) { check_scene("mobile_panda/mobile_panda_hand.yaml", 10); }
TEST(ResidualJacobians, FloatingTreeWithPrismaticFingers) { check_scene("mobile_panda_gripper/mobile_panda_grasp.yaml", 10); }
TEST(ResidualJacobians, QuadrupedStance) { check_scene("quadruped/quadruped_stance.yaml", 10); }
// Sets between two links (L1, L4): the relative rows and the other link's wrench, fixed in A.
TEST(ResidualJacobians, LoopSets) { check_scene("four_bar/four_bar_loop.yaml", 20); }
TEST(ResidualJacobians, LoopSetsBesideWorldSetsOnAFloatingBase) { check_scene("linkage_biped/linkage_biped_stance.yaml", 10); }
TEST(ResidualJacobians, ThreeLoopsOnOnePlatform) { check_scene("delta/delta_loops.yaml", 10); }
// Coupled <mimic> joints (M1): a coupled joint's columns folded into its source's, a mimic of a mimic
// with an offset among them.
TEST(ResidualJacobians, CoupledJoints) { check_scene("parallel_gripper/parallel_gripper_pinch.yaml", 10); }
TEST(ResidualJacobians, RandomChains) { check_random(false, false); }
TEST(ResidualJacobians, RandomTrees) { check_random(true, false); }
TEST(ResidualJacobians, RandomFloatingTrees) { check_random(false, true); }

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

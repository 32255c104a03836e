// (C5) as the inward sweep forms it (docs/derivation.md, section 4): where two constraint sets or
// more reach the base through joints of their own, each set's block of B is the sum of the (I3)
// terms of those joints, and E^A_cstr,0 is that sum plus the shared joints' terms, so E − B is
// positive semi-definite and (C5)'s sum bounds (C4)'s. Checked at random states of the robots it
// applies to (the quadruped's four feet on their legs, the dual Panda's hands on their arms), and
// that it does not apply where a set has fewer joints of its own than directions.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>
#include <string>

#include "report/measure.hpp"
#include "scene/scene.hpp"
#include "solver/reference_solver.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

using Matrix = solver::ConstraintMatrix<double>;

scene::Scene bundled(const std::string& path) { return scene::load_scene(std::string(SWEEPGEN_SOURCE_DIR) + "/" + path); }

// The tops of each set's own joints, the bodies whose (I3) matrix completes its block.
void expect_tops(const std::string& scene_path, const std::vector<std::size_t>& tops) {
  const scene::Scene s = bundled(scene_path);
  const solver::ReferenceSolver<double> solver(scene::load_scene_chain(s), s.layout, s.solver_options());
  EXPECT_EQ(solver.model().private_top, tops) << scene_path;
}

TEST(BlockLowerBound, AppliesWhereEachSetHasJointsOfItsOwn) {
  // The quadruped: bodies 1..6 the floating base, each leg hip, thigh, calf; a foot's own joints
  // end at its hip (bodies 7, 10, 13, 16).
  expect_tops("robots/quadruped/quadruped_stance.yaml", {7, 10, 13, 16});
  // A set on the elbow and one on the hand share the elbow's joints; fingers have one joint each
  // for three directions; one set alone has nothing to bound: no (C5).
  expect_tops("robots/panda/panda_sets.yaml", {});
  expect_tops("robots/mobile_panda_gripper/mobile_panda_grasp.yaml", {});
  expect_tops("robots/panda/panda_nc6.yaml", {});
}

// E − B >= 0 with the diagonal of E scaled to 1: its smallest eigenvalue is at least minus the
// rounding of the two sums (each unit-scaled entry a sum of at most 18 joints' terms of size <= 1,
// so within 20 ε; the 2-norm of Nc x Nc such errors is at most Nc times that: 12 · 20 ε = 5.3e-14,
// the ceiling 1e-12); B is 0 outside its blocks.
void check_scene(const std::string& scene_path, int states, double decided_share) {
  const scene::Scene s = bundled(scene_path);
  const model::Chain chain = scene::load_scene_chain(s);
  solver::ReferenceSolver<double> solver(chain, s.layout, s.solver_options());
  const auto& model = solver.model();
  ASSERT_FALSE(model.private_top.empty()) << scene_path;
  const auto problems = report::random_problems(s, chain, static_cast<std::size_t>(states), 5);
  const double tol = model.pivot_tolerance;
  int decided = 0;
  double lowest = 0;
  for (const auto& p : problems) {
    solver.prepare(p);
    const Matrix& E = solver.articulated().body[0].constraint_energy;
    const Matrix& B = solver.articulated().private_energy;
    const Eigen::Index nc = E.rows();
    solver::BlockLowerBound<double> bound{B, {}};
    Eigen::MatrixXi in_block = Eigen::MatrixXi::Zero(nc, nc);
    for (const auto& set : model.constraint_sets) {
      const auto first = static_cast<Eigen::Index>(set.first), count = static_cast<Eigen::Index>(set.count);
      bound.blocks.emplace_back(first, count);
      in_block.block(first, first, count, count).setOnes();
    }
    for (Eigen::Index i = 0; i < nc; ++i)
      for (Eigen::Index j = 0; j < nc; ++j) {
        if (!in_block(i, j)) {
          ASSERT_EQ(B(i, j), 0) << scene_path << ": B(" << i << ", " << j << ") outside the blocks";
        }
      }
    const Eigen::VectorXd unit = E.diagonal().cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd difference = unit.asDiagonal() * (E - B) * unit.asDiagonal();
    const double smallest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(difference).eigenvalues().minCoeff();
    lowest = std::min(lowest, smallest);
    EXPECT_GE(smallest, -1e-12) << scene_path;
    const solver::ConstraintVector<double> r = solver::ConstraintVector<double>::Ones(nc);
    double coupling = 0;
    solver::natural_order_solve(E, r, tol, coupling);
    const double block_sum = solver::block_coupling(E, bound, tol);
    if (solver::kNaturalOrderMargin * tol * block_sum < 10) {
      EXPECT_GE(block_sum, coupling * (1 - 1e-12)) << scene_path;
    }
    decided += solver::kNaturalOrderMargin * tol * block_sum < 1;
  }
  std::printf("[          ] %s: (C5) decides %d of %d states; smallest eigenvalue of E - B (unit diagonal) %.2e\n",
              scene_path.c_str(), decided, states, lowest);
  EXPECT_GE(decided, decided_share * states) << scene_path;
}

// The feet's blocks are the legs' (never straight within the calf's limits): (C5) decides every
// state; the hands' blocks are the arms', singular only at the arms' own singularities.
TEST(BlockLowerBound, TheSweepsBoundIsBelowEAndDecides) {
  check_scene("robots/quadruped/quadruped_stance.yaml", 300, 1.0);
  check_scene("robots/dual_panda/dual_panda_box.yaml", 300, 0.9);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

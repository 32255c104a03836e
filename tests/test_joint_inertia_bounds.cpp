// (J2), docs/derivation.md: the configuration-independent bounds that let the solver drop the
// joint-inertia test (J1) hold at random states of the bundled robots and of random chains and
// trees, and a joint that is proven never locked is one (J1) would not have locked.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "model/joint_inertia_bounds.hpp"
#include "solver/joint_inertia.hpp"
#include "solver/reference_solver.hpp"
#include "support/bundled_robots.hpp"
#include "support/random_chain.hpp"
#include "support/random_problem.hpp"

namespace sweepgen {
namespace {
namespace SWEEPGEN_TEST_FILE {

struct Tally {
  int joints = 0, never_locked = 0, exact_zeros = 0;
  double closest_lower = 1e300, closest_upper = 1e300;  // smallest D / lower and scale-bound ratio seen
};

// At 20 random states within the joint limits: lower <= D_i and d_i + tr block <= upper, for the
// D_i and M^A_i the reference solver computes. The slack 1e-12 relative covers their rounding
// (sums of a few dozen products of the state's ~1e0 entries: ~1e2 ε = 2e-14, with a margin of 50).
void check_bounds(const model::Chain& chain, unsigned seed, Tally& tally) {
  solver::DriverLayout layout;
  layout.torques = {"tau"};
  layout.compose_all();
  solver::ReferenceSolver<double> reference(chain, layout);
  test::RandomProblem random(seed);
  const std::vector<model::JointInertiaBounds> bounds = model::joint_inertia_bounds(chain);
  for (std::size_t i = 1; i <= chain.dof(); ++i) {
    const auto& joint = reference.model().joints[i];
    ++tally.joints;
    tally.never_locked += !joint.can_lock;
    tally.exact_zeros += joint.exact_zero_component >= 0;
  }
  for (int state = 0; state < 20; ++state) {
    reference.outward(random.positions(chain), random.velocities(chain));
    reference.drivers().torques[0] = random.torques(chain);
    reference.decompose();
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const auto& body = reference.articulated().body[i];
      const double scale = solver::joint_inertia_scale(reference.model().joints[i], body.articulated_inertia);
      EXPECT_LE(bounds[i].lower, body.D * (1 + 1e-12)) << chain.source << " joint " << chain.joints[i].name;
      EXPECT_LE(scale, bounds[i].upper * (1 + 1e-12)) << chain.source << " joint " << chain.joints[i].name;
      if (bounds[i].lower > 0) tally.closest_lower = std::min(tally.closest_lower, body.D / bounds[i].lower);
      if (scale > 0) tally.closest_upper = std::min(tally.closest_upper, bounds[i].upper / scale);
      // A joint proven never locked is one (J1) keeps: D_i well above tol times its scale.
      if (!reference.model().joints[i].can_lock) {
        EXPECT_EQ(body.locked, 0.0);
        EXPECT_GT(body.D, 2 * reference.model().joint_inertia_tolerance * scale) << chain.joints[i].name;
      }
    }
  }
}

TEST(JointInertiaBounds, HoldAtRandomStatesOfBundledRobotsAndRandomTrees) {
  Tally tally;
  for (const auto& robot : test::bundled_robots()) check_bounds(test::load_bundled(robot), 3, tally);
  check_bounds(test::load_tree("robots/quadruped/quadruped.urdf", "trunk",
                               {"FL_foot", "FR_foot", "RL_foot", "RR_foot"}, true),
               5, tally);
  test::RandomChainGenerator generator(17);
  for (int k = 0; k < 40; ++k) check_bounds(k % 2 ? generator.tree() : generator.chain(), 100 + k, tally);
  std::printf("[          ] %d joints, %d proven never locked, %d with exact zeros; tightest: D / lower %.3g, "
              "upper / scale %.3g\n",
              tally.joints, tally.never_locked, tally.exact_zeros, tally.closest_lower, tally.closest_upper);
  // Not vacuous: most joints are proven (all of the arms', whose links all have mass off their
  // axes), and the bounds come within a small factor of what is computed somewhere.
  EXPECT_GT(tally.never_locked, tally.joints / 2);
  EXPECT_GT(tally.exact_zeros, 20);
  EXPECT_LT(tally.closest_lower, 2.0);
}

// The bounds body by body, as (J2) states them: per joint i, per body k of its subtree, the reach
// R (the offsets of the joints from k in to i) and tr A_k + 2 R (2 |h_k| + m_k R). Time N^2 depth:
// the one pass of model::joint_inertia_bounds must give the same sums.
model::JointInertiaBounds bounds_by_definition(const model::Chain& chain, std::size_t i) {
  const auto offset = [&](std::size_t j) {
    const model::Joint& joint = chain.joints[j];
    const double r = joint.tree_transform.r.norm();
    if (joint.type == model::JointType::revolute || joint.floating_base_coordinate) return r;
    return r + std::max(std::abs(joint.lower), std::abs(joint.upper));
  };
  const model::Joint& joint = chain.joints[i];
  const bool revolute = joint.type == model::JointType::revolute;
  const auto& own = chain.bodies[i].inertia;
  model::JointInertiaBounds bounds;
  bounds.lower = joint.rotor_inertia + joint.axis.dot((revolute ? own.A : own.C) * joint.axis);
  bounds.upper = joint.rotor_inertia;
  for (std::size_t k = i; k <= chain.dof(); ++k) {
    if (!chain.supports(i, k)) continue;
    const auto& body = chain.bodies[k].inertia;
    if (!revolute) {
      bounds.upper += body.C.trace();
      continue;
    }
    double reach = 0;
    for (std::size_t j = k; j != i; j = chain.parent[j]) reach += offset(j);
    const double mass = body.C.trace() / 3;
    const double h = model::Vec3(body.B(2, 1), body.B(0, 2), body.B(1, 0)).norm();
    bounds.upper += std::isinf(reach) ? std::numeric_limits<double>::infinity()
                                      : body.A.trace() + 2 * reach * (2 * h + mass * reach);
  }
  return bounds;
}

// Both are sums of the same terms >= 0 in another order (a few dozen on these trees): they agree
// to that many roundings, 1e-13 relative with a margin of ~10.
TEST(JointInertiaBounds, TheOnePassGivesTheBodyByBodySums) {
  test::RandomChainGenerator generator(23);
  std::vector<model::Chain> chains;
  for (const auto& robot : test::bundled_robots()) chains.push_back(test::load_bundled(robot));
  for (int k = 0; k < 20; ++k) chains.push_back(k % 2 ? generator.tree() : generator.chain());
  int compared = 0;
  for (const model::Chain& chain : chains) {
    const std::vector<model::JointInertiaBounds> bounds = model::joint_inertia_bounds(chain);
    ASSERT_EQ(bounds.size(), chain.dof() + 1);
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const model::JointInertiaBounds expected = bounds_by_definition(chain, i);
      EXPECT_EQ(bounds[i].lower, expected.lower) << chain.source << " joint " << i;
      if (std::isinf(expected.upper)) EXPECT_TRUE(std::isinf(bounds[i].upper)) << chain.source << " joint " << i;
      else EXPECT_NEAR(bounds[i].upper, expected.upper, 1e-13 * expected.upper) << chain.source << " joint " << i;
      ++compared;
    }
  }
  EXPECT_GT(compared, 100);
}

TEST(JointInertiaBounds, EveryPandaJointIsProvenAndTheTestStaysWhereItCanFire) {
  const model::Chain panda = test::load_bundled(test::bundled_robots().front());
  solver::DriverLayout layout;
  layout.compose_all();
  {
    const solver::SolverModel<double> model(panda, layout, {}, 0x1p-52);
    for (std::size_t i = 1; i <= panda.dof(); ++i) {
      EXPECT_FALSE(model.joints[i].can_lock) << panda.joints[i].name;
      EXPECT_EQ(model.joints[i].exact_zero_component, 2) << panda.joints[i].name;  // the Panda's joints turn about z
    }
  }
  // At tolerance 0.5 no joint can be proven (2 tol upper >= upper >= lower: S^T M S <= tr of the
  // block for a unit axis): every joint keeps the test of (J1) and the general projection.
  solver::SolverOptions coarse;
  coarse.joint_inertia_tolerance = 0.5;
  const solver::SolverModel<double> model(panda, layout, coarse, 0x1p-52);
  for (std::size_t i = 1; i <= panda.dof(); ++i) {
    EXPECT_TRUE(model.joints[i].can_lock) << panda.joints[i].name;
    EXPECT_EQ(model.joints[i].exact_zero_component, -1) << panda.joints[i].name;
  }
  // A floating base's coordinates ride on massless bodies: never proven.
  const model::Chain quadruped =
      test::load_tree("robots/quadruped/quadruped.urdf", "trunk", {"FL_foot"}, true);
  const solver::SolverModel<double> floating(quadruped, layout, {}, 0x1p-52);
  for (std::size_t i = 1; i <= 5; ++i) EXPECT_TRUE(floating.joints[i].can_lock) << i;
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace
}  // namespace sweepgen

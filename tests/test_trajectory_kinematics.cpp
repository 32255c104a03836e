// The trajectory-optimisation example's own hand kinematics (examples/trajectory_optimisation/
// hand_kinematics.hpp: the Panda's joint origins copied from robots/panda/panda.urdf, since the
// generated code returns no pose) against the project's reading of that URDF: the dense oracle's
// pose and body Jacobian of panda_hand (generator/oracle/dense_dynamics.hpp), so that a change to
// the URDF, or a slip in the example's constants, fails here and not silently in the example,
// whose derivative checker only compares the example with itself. And the example's Dual
// derivatives against the same Jacobian: d p / d q_i is the linear velocity along q̇ = e_i.
//
// Tolerance. Both sides multiply the same seven rotations and offsets in another order: each of
// the ~30 products and sums of a pose component rounds by eps relative to sizes of at most 1 (a
// rotation's entries, the arm's ~1 m reach), so any component differs by at most a few tens of
// eps: 64 eps (1.4e-14) absolute, with |q̇| <= 1 for the velocities.
#include <gtest/gtest.h>

#include <random>

#include "../examples/trajectory_optimisation/hand_kinematics.hpp"
#include "oracle/dense_dynamics.hpp"
#include "support/bundled_robots.hpp"

namespace {
namespace SWEEPGEN_TEST_FILE {

using Oracle = sweepgen::oracle::DenseDynamics<double>;
constexpr double kTolerance = 64 * 2.220446049250313e-16;
constexpr int kStates = 200;

TEST(TrajectoryKinematics, TheExamplesHandIsTheUrdfsHand) {
  const sweepgen::test::BundledRobot& panda = sweepgen::test::bundled_robots().front();
  ASSERT_EQ(panda.name, "panda");
  const sweepgen::model::Chain chain = sweepgen::test::load_bundled(panda);
  ASSERT_EQ(chain.dof(), static_cast<std::size_t>(trajopt::kDof));
  const Oracle oracle(chain);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> angle(-2.8, 2.8), rate(-1.0, 1.0);
  for (int s = 0; s < kStates; ++s) {
    Oracle::Vec q(trajopt::kDof), qd(trajopt::kDof);
    for (int i = 0; i < trajopt::kDof; ++i) {
      q[i] = angle(random);
      qd[i] = rate(random);
    }
    const trajopt::HandState<double> hand = trajopt::hand_state(q.data(), qd.data());
    const Oracle::Pose pose = oracle.link_pose(q, "panda_hand");
    const Oracle::Jacobian J = oracle.jacobian(q, "panda_hand");  // twist in the hand's coordinates
    const Oracle::V3 omega = pose.R * (J.topRows<3>() * qd), velocity = pose.R * (J.bottomRows<3>() * qd);
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(hand.p[a], pose.p[a], kTolerance) << "state " << s << " p[" << a << "]";
      EXPECT_NEAR(hand.pd[a], velocity[a], kTolerance) << "state " << s << " pdot[" << a << "]";
      EXPECT_NEAR(hand.omega[a], omega[a], kTolerance) << "state " << s << " omega[" << a << "]";
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(hand.R[3 * a + b], pose.R(a, b), kTolerance) << "state " << s;
    }
    // The Dual tangents of p along q_i: the linear velocity of the hand for q̇ = e_i.
    trajopt::Dual q_dual[trajopt::kDof], qd_dual[trajopt::kDof];
    trajopt::seed(q.data(), qd.data(), q_dual, qd_dual);
    const trajopt::HandState<trajopt::Dual> seeded = trajopt::hand_state(q_dual, qd_dual);
    const Eigen::Matrix<double, 3, Eigen::Dynamic> linear = pose.R * J.bottomRows<3>();
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < trajopt::kDof; ++i)
        EXPECT_NEAR(seeded.p[a].d[i], linear(a, i), kTolerance) << "state " << s << " dp[" << a << "]/dq" << i;
  }
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

// Closed chains in the dense oracle (docs/derivation.md, L1–L3, M1; generator/oracle/dense_dynamics.hpp,
// relative_motion, pose_error, coupling_rows), the reference the solver's loop sets and coupled
// joints will be judged by:
//   - (L1)/(L2) at open states (v_rel ≠ 0, where the product v_A × ᴬX_B v_B matters): J_rel q̈ +
//     c_rel against a central difference of v_rel along q(t) = q + t q̇ + t²/2 q̈, q̇(t) = q̇ + t q̈,
//     for frames at offsets on two branches and on one link with the other (B on the ground);
//   - a four-bar (a crank-rocker written here: crank 0.35 m, coupler 1 m, rocker 0.8 m, ground
//     1 m, under gravity), its loop closed by two in-plane directions with β = 0, and the Franka
//     hand's fingers (robots/mobile_panda_gripper, panda_finger_joint2 a <mimic> of joint1) coupled
//     by (M1) on the swinging arm, each simulated by RK4 on the dense system (Gauss' principle)
//     from a consistent state: the closure (L3) or the coupling, and the energy (the loop's and
//     the transmission's forces do no work), hold to RK4's error, which falls 16-fold when the
//     step halves (the error is the integrator's, not a missing term's).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <utility>

#include "oracle/dense_dynamics.hpp"
#include "support/bundled_robots.hpp"
#include "support/rk4.hpp"
#include "support/temp_dir.hpp"

namespace {
namespace SWEEPGEN_TEST_FILE {

using namespace sweepgen;

constexpr double kCrank = 0.35, kCoupler = 1.0, kRocker = 0.8, kGround = 1.0;

// A rod of `length` along its link's x axis, `mass` kg, centre of mass at its middle.
std::string rod(const std::string& name, double length, double mass) {
  const double izz = mass * length * length / 12;
  return "  <link name=\"" + name + "\"><inertial><origin xyz=\"" + std::to_string(length / 2) +
         " 0 0\"/><mass value=\"" + std::to_string(mass) + "\"/><inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"" +
         std::to_string(izz) + "\" iyz=\"0\" izz=\"" + std::to_string(izz) + "\"/></inertial></link>\n";
}

std::string pin(const std::string& name, const std::string& parent, const std::string& child, double x) {
  return "  <joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><origin xyz=\"" + std::to_string(x) + " 0 0\"/><axis xyz=\"0 0 1\"/>"
         "<limit effort=\"100\" lower=\"-100\" upper=\"100\" velocity=\"100\"/></joint>\n";
}

// The four-bar as the loader reads it: a tree of two branches from the ground (crank, coupler;
// rocker), joints q = (crank, coupler relative to crank, rocker).
model::Chain four_bar(const test::TempDir& dir) {
  const std::string urdf = "<robot name=\"four_bar\">\n  <link name=\"ground\"/>\n" + rod("crank", kCrank, 0.5) +
                           rod("coupler", kCoupler, 1.0) + rod("rocker", kRocker, 0.8) +
                           pin("crank_joint", "ground", "crank", 0) + pin("coupler_joint", "crank", "coupler", kCrank) +
                           pin("rocker_joint", "ground", "rocker", kGround) + "</robot>\n";
  model::ChainSpec spec;
  spec.urdf = dir.write("four_bar.urdf", urdf);
  spec.root_link = "ground";
  spec.tip_link = "coupler";
  spec.branch_tips = {"rocker"};
  return model::load_chain(spec);
}

template <class Scalar>
struct Loop {
  using Oracle = oracle::DenseDynamics<Scalar>;
  typename Oracle::AttachedFrame A{"coupler", Oracle::M3::Identity(), typename Oracle::V3(kCoupler, 0, 0)};
  typename Oracle::AttachedFrame B{"rocker", Oracle::M3::Identity(), typename Oracle::V3(kRocker, 0, 0)};
  // α: the two in-plane directions of A's linear velocity (the pin leaves the turn about z free).
  typename Oracle::Mat alpha() const {
    typename Oracle::Mat a = Oracle::Mat::Zero(6, 2);
    a(3, 0) = a(4, 1) = 1;
    return a;
  }
};

// The closed configuration with the crank at q1 (the coupler above the ground line).
Eigen::Vector3d closed(double q1) {
  const Eigen::Vector2d crank_end(kCrank * std::cos(q1), kCrank * std::sin(q1)), rocker_pivot(kGround, 0);
  const Eigen::Vector2d d = rocker_pivot - crank_end;
  const double l = d.norm(), along = (kCoupler * kCoupler - kRocker * kRocker + l * l) / (2 * l);
  const double across = std::sqrt(kCoupler * kCoupler - along * along);
  const Eigen::Vector2d joint = crank_end + along * d / l + across * Eigen::Vector2d(-d.y(), d.x()) / l;
  const double coupler = std::atan2(joint.y() - crank_end.y(), joint.x() - crank_end.x());
  return {q1, coupler - q1, std::atan2(joint.y(), joint.x() - kGround)};
}

TEST(LoopClosure, RelativeAccelerationIsTheDerivativeOfTheRelativeTwist) {
  using Oracle = oracle::DenseDynamics<long double>;
  test::TempDir dir;
  const Oracle oracle(four_bar(dir), model::Vec3(0, -9.81, 0));
  Loop<long double> loop;
  // Also B with a turned offset, and A against a frame on the ground (one side that never moves).
  Loop<long double> turned = loop;
  turned.B.R = Eigen::AngleAxis<long double>(0.7L, Oracle::V3(0.3L, -0.5L, 0.8L).normalized()).toRotationMatrix();
  turned.B.p = Oracle::V3(0.2L, 0.1L, -0.3L);
  Loop<long double> grounded = loop;
  grounded.B = {"ground", Oracle::M3::Identity(), Oracle::V3(0.4L, 0.2L, 0)};
  std::mt19937_64 random(11);
  std::uniform_real_distribution<long double> uniform(-2, 2);
  const long double h = 1e-5L;
  for (const Loop<long double>* l : {&loop, &turned, &grounded}) {
    for (int s = 0; s < 20; ++s) {
      Oracle::Vec q(3), qd(3), qdd(3);
      for (int i = 0; i < 3; ++i) {
        q[i] = uniform(random);
        qd[i] = uniform(random);
        qdd[i] = uniform(random);
      }
      const auto along = [&](long double t) {
        return oracle.relative_motion(q + t * qd + t * t / 2 * qdd, qd + t * qdd, l->A, l->B).velocity;
      };
      const Oracle::Six difference = (along(h) - along(-h)) / (2 * h);
      const auto r = oracle.relative_motion(q, qd, l->A, l->B);
      const Oracle::Six analytic = r.J * qdd + r.drift;
      // Central difference: truncation h²/6 |v'''| (|v'''| below 1e3 here: 2e-8) and rounding
      // eps_ld |v| / h (1e-14); 1e-7 leaves a margin of 5. A dropped product term errs by |v|², ~1.
      EXPECT_LT((analytic - difference).cwiseAbs().maxCoeff(), 1e-7L) << "state " << s;
      EXPECT_GT(r.velocity.norm(), 1e-3L) << "an open state: v_rel != 0";
    }
  }
}

using Oracle = oracle::DenseDynamics<double>;

// The largest violation of the constraint and relative change of the energy along `seconds` of
// RK4 at `step` from (q, q̇), with `rows(q, q̇)` the constraint rows and their right-hand side.
template <class Rows, class Violation>
std::pair<double, double> simulate(const Oracle& oracle, Rows&& rows, Violation&& violation, const Oracle::Vec& q,
                                   const Oracle::Vec& qd, double step, double seconds) {
  const auto energy = [&](const Oracle::Vec& p, const Oracle::Vec& pd) {
    return 0.5 * pd.dot(oracle.mass_matrix(p) * pd) + oracle.potential_energy(p);
  };
  const double e0 = energy(q, qd);
  const auto accelerate = [&](const Oracle::Vec& p, const Oracle::Vec& pd) {
    const auto [Jc, rhs] = rows(p, pd);
    return oracle.solve_rows(p, pd, Oracle::Vec::Zero(p.size()), Jc, rhs).qdd;
  };
  Oracle::Vec p = q, pd = qd;
  double worst = 0, drift = 0;
  for (long k = 0; k < std::lround(seconds / step); ++k) {
    test::rk4_step(accelerate, p, pd, step);
    worst = std::max(worst, violation(p));
    drift = std::max(drift, std::abs(energy(p, pd) - e0) / std::abs(e0));
  }
  return {worst, drift};
}

// RK4 errs by C h^4 per unit time: the 1 ms runs' errors are their own, 1e-8 (m, rad) and 1e-8 of
// the energy the bound for the solver; and they are the integrator's: halving the step
// divides them by about 16 (more than 8 asserted). A linear constraint (a coupling, M1) RK4 keeps
// exactly, each stage's q̈ meeting it: there its violation is rounding, at most 1e-12 (the
// issue's bound; 50 steps of eps-sized errors on coordinates below 3 are ~1e-14).
void expect_fourth_order(const char* what, std::pair<double, double> fine, std::pair<double, double> coarse,
                         bool linear_constraint = false) {
  std::printf("[%s] RK4: constraint %.3g, energy %.3g (step 1 ms); %.3g, %.3g (2 ms)\n", what, fine.first, fine.second,
              coarse.first, coarse.second);
  EXPECT_LT(fine.second, 1e-8) << what;
  EXPECT_GT(coarse.second / fine.second, 8) << what;
  if (linear_constraint) {
    EXPECT_LE(std::max(fine.first, coarse.first), 1e-12) << what;
  } else {
    EXPECT_LT(fine.first, 1e-8) << what;
    EXPECT_GT(coarse.first / fine.first, 8) << what;
  }
}

TEST(LoopClosure, AFourBarStaysClosedAndKeepsItsEnergy) {
  test::TempDir dir;
  const Oracle oracle(four_bar(dir), model::Vec3(0, -9.81, 0));
  const Loop<double> loop;
  const Oracle::Mat alpha = loop.alpha();
  const auto rows = [&](const Oracle::Vec& q, const Oracle::Vec& qd) {
    const auto r = oracle.relative_motion(q, qd, loop.A, loop.B);
    // α^T d/dt v_rel = β = 0 (L1), as the dense system's rows (L2).
    return std::pair<Oracle::Mat, Oracle::Vec>{alpha.transpose() * r.J, -(alpha.transpose() * r.drift)};
  };
  const auto open = [&](const Oracle::Vec& q) { return oracle.pose_error(q, loop.A, loop.B).tail<3>().cwiseAbs().maxCoeff(); };
  // Closed, the crank at 2 rad/s, the others as the loop allows: α^T J_rel q̇ = 0.
  const Oracle::Vec q = closed(1.0);
  const Oracle::Mat Jc = rows(q, Oracle::Vec::Zero(3)).first;
  Oracle::Vec qd(3);
  qd[0] = 2;
  qd.tail<2>() = Jc.rightCols<2>().fullPivLu().solve(-Jc.col(0) * qd[0]);
  expect_fourth_order("four-bar, 1 s", simulate(oracle, rows, open, q, qd, 1e-3, 1.0),
                      simulate(oracle, rows, open, q, qd, 2e-3, 1.0));
}

TEST(MimicCoupling, TheFrankaHandsFingersMoveAsOne) {
  const model::Chain chain = test::load_tree("robots/mobile_panda_gripper/mobile_panda_gripper.urdf", "panda_link0",
                                             {"panda_leftfinger", "panda_rightfinger"});
  const Oracle oracle(chain);
  const Oracle::Mat coupling = Oracle::coupling_rows(chain);
  ASSERT_EQ(coupling.rows(), 1) << "panda_finger_joint2 follows panda_finger_joint1";
  ASSERT_EQ(coupling.cwiseAbs().sum(), 2) << "multiplier 1: one +1 and one -1";
  const auto rows = [&](const Oracle::Vec&, const Oracle::Vec&) {
    return std::pair<Oracle::Mat, Oracle::Vec>{coupling, Oracle::Vec::Zero(1)};  // (M1): q̈_m − k q̈_s = 0
  };
  const auto apart = [&](const Oracle::Vec& q) { return std::abs((coupling * q)[0]); };  // offset 0
  // The arm away from its singular stretch, the fingers half open and closing together.
  Oracle::Vec q(chain.dof()), qd = Oracle::Vec::Zero(chain.dof());
  q << 0.3, -0.4, 0.2, -2.0, 0.1, 1.6, 0.7, 0.02, 0.02;
  qd.head<7>() << 0.4, -0.3, 0.5, 0.2, -0.6, 0.3, 0.8;
  qd.tail<2>().setConstant(-0.05);
  ASSERT_LT((coupling * qd).cwiseAbs().maxCoeff(), 1e-15) << "a consistent start";
  expect_fourth_order("Franka hand, 0.5 s", simulate(oracle, rows, apart, q, qd, 1e-3, 0.5),
                      simulate(oracle, rows, apart, q, qd, 2e-3, 0.5), true);
}

}  // namespace SWEEPGEN_TEST_FILE
}  // namespace

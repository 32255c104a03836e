// One step of classical fixed-step Runge–Kutta (RK4) on q̈ = accelerate(q, q̇), the integrator of
// the suite's simulations (tests/test_stability.cpp's energy drift, tests/test_closed_chains.cpp):
// its global error is O(h⁴), so halving h divides an error that is the integrator's by about 16.
#pragma once

#include <Eigen/Core>

namespace sweepgen::test {

template <class Accelerate>
void rk4_step(Accelerate&& accelerate, Eigen::VectorXd& q, Eigen::VectorXd& qd, double h) {
  const Eigen::VectorXd a1 = accelerate(q, qd);
  const Eigen::VectorXd q2 = q + 0.5 * h * qd, v2 = qd + 0.5 * h * a1;
  const Eigen::VectorXd a2 = accelerate(q2, v2);
  const Eigen::VectorXd q3 = q + 0.5 * h * v2, v3 = qd + 0.5 * h * a2;
  const Eigen::VectorXd a3 = accelerate(q3, v3);
  const Eigen::VectorXd q4 = q + h * v3, v4 = qd + h * a3;
  const Eigen::VectorXd a4 = accelerate(q4, v4);
  q += h / 6 * (qd + 2 * v2 + 2 * v3 + v4);
  qd += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
}

}  // namespace sweepgen::test

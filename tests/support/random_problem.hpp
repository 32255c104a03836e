// Seeded random states and drivers for the numerical tests.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "model/chain.hpp"
#include "solver/state.hpp"

namespace sweepgen::test {

class RandomProblem {
 public:
  explicit RandomProblem(unsigned seed) : rng_(seed) {}

  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

  // Joint positions within the joint limits (or [-pi, pi] where unlimited).
  Eigen::VectorXd positions(const model::Chain& chain) {
    Eigen::VectorXd q(chain.dof());
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const auto& j = chain.joints[i];
      const double lo = std::isfinite(j.lower) ? j.lower : -M_PI;
      const double hi = std::isfinite(j.upper) ? j.upper : M_PI;
      q[i - 1] = uniform(lo, hi);
    }
    return q;
  }
  Eigen::VectorXd velocities(const model::Chain& chain, double magnitude = 2.0) {
    Eigen::VectorXd qd(chain.dof());
    for (auto& v : qd) v = uniform(-magnitude, magnitude);
    return qd;
  }
  // Torques up to `fraction` of each joint's effort limit (10 where unlimited).
  Eigen::VectorXd torques(const model::Chain& chain, double fraction = 0.5) {
    Eigen::VectorXd tau(chain.dof());
    for (std::size_t i = 1; i <= chain.dof(); ++i) {
      const double limit = std::isfinite(chain.joints[i].effort_limit) ? chain.joints[i].effort_limit : 10.0;
      tau[i - 1] = uniform(-fraction * limit, fraction * limit);
    }
    return tau;
  }
  spatial::Force<double> wrench(double moment = 2.0, double force = 20.0) {
    spatial::Force<double> f;
    for (int k = 0; k < 3; ++k) {
      f.moment[k] = uniform(-moment, moment);
      f.force[k] = uniform(-force, force);
    }
    return f;
  }
  // A random unit 6-vector (moment and force parts share the unit norm).
  spatial::Force<double> unit_direction() {
    spatial::Force<double> f = wrench(1.0, 1.0);
    const double norm = std::sqrt(f.moment.squaredNorm() + f.force.squaredNorm());
    return f * (1.0 / norm);
  }
  // A rotation matrix from a random unit quaternion (a floating base's world_R_base).
  model::Mat3 rotation() {
    return Eigen::Quaterniond(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)).normalized().toRotationMatrix();
  }

 private:
  std::mt19937_64 rng_;
};

}  // namespace sweepgen::test
